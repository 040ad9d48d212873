// Fixed-chunk parallel loops whose results do not depend on the thread count.
//
// A loop over [0, n) is cut into chunks of a fixed size, chosen by the caller
// and never by the thread count; each chunk is one task. A result gathered per
// chunk and combined in chunk order (a sum, a list) is then the same, bit for
// bit, on 1 thread as on 64: the rule every parallel stage of msdeform keeps
// (docs/decisions/many-cores.md).

#ifndef MSDEFORM_CORE_PARALLEL_H_
#define MSDEFORM_CORE_PARALLEL_H_

#include <algorithm>
#include <cstdint>
#include <vector>

#include <omp.h>

namespace msdeform {

// Passes over fewer items than this run on one thread: starting a team costs
// more than it saves there.
constexpr int64_t kParallelMinItems = 1 << 14;

// Threads for a pass over `items` items: num_threads (at least 1), or 1 for a
// small pass.
inline int ThreadsFor(int num_threads, int64_t items) {
  return items >= kParallelMinItems ? std::max(1, num_threads) : 1;
}

// The number of chunks of at most `chunk` items that cover n items.
inline int64_t NumChunks(int64_t n, int64_t chunk) { return n <= 0 ? 0 : (n + chunk - 1) / chunk; }

// Calls fn(begin, end, chunk_index) for every chunk [begin, end) of [0, n), on
// up to num_threads threads (0: OpenMP's default), serially when there is one
// chunk or one thread.
template <class Fn>
void ForEachChunk(int64_t n, int64_t chunk, int num_threads, Fn&& fn) {
  const int64_t num_chunks = NumChunks(n, chunk);
  const int threads = num_threads > 0 ? num_threads : omp_get_max_threads();
  if (num_chunks <= 1 || threads <= 1) {
    for (int64_t c = 0; c < num_chunks; ++c) fn(c * chunk, std::min(n, (c + 1) * chunk), c);
    return;
  }
#pragma omp parallel for num_threads(static_cast<int>(std::min<int64_t>(threads, num_chunks))) \
    schedule(dynamic, 1)
  for (int64_t c = 0; c < num_chunks; ++c) fn(c * chunk, std::min(n, (c + 1) * chunk), c);
}

// The indices i of [0, n) with keep(i), in increasing order, for any thread
// count: keep is evaluated once per index into flags, each chunk's kept
// indices are counted, and each chunk writes its own range of the result (no
// list grows inside the parallel loops).
template <class Keep>
std::vector<int> SelectIndices(int n, int num_threads, Keep&& keep, int64_t chunk = 1 << 16) {
  std::vector<char> kept(n > 0 ? n : 0);
  std::vector<int64_t> start(NumChunks(n, chunk) + 1, 0);
  ForEachChunk(n, chunk, num_threads, [&](int64_t begin, int64_t end, int64_t c) {
    int64_t count = 0;
    for (int64_t i = begin; i < end; ++i) count += kept[i] = keep(static_cast<int>(i)) ? 1 : 0;
    start[c + 1] = count;
  });
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int> indices(start.back());
  ForEachChunk(n, chunk, num_threads, [&](int64_t begin, int64_t end, int64_t c) {
    int* out = indices.data() + start[c];
    for (int64_t i = begin; i < end; ++i)
      if (kept[i]) *out++ = static_cast<int>(i);
  });
  return indices;
}

// *target = source, column chunks copied on num_threads threads (each thread
// first touches the pages it writes: a 1.66M-vertex mesh's 40 MB of
// coordinates copy in about 17 ms on one core of the build machine).
template <class Matrix>
void CopyColumns(const Matrix& source, int num_threads, Matrix* target) {
  target->resize(source.rows(), source.cols());
  ForEachChunk(source.cols(), int64_t{1} << 15, num_threads,
               [&](int64_t begin, int64_t end, int64_t) {
                 target->middleCols(begin, end - begin) = source.middleCols(begin, end - begin);
               });
}

}  // namespace msdeform

#endif  // MSDEFORM_CORE_PARALLEL_H_
