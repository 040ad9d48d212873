#include "msdeform/core/skinning.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <glog/logging.h>
#include <omp.h>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define MSDEFORM_SKINNING_AVX2 1
// Functions compiled for AVX2 and FMA whatever the build's -march; they run
// only after RunsAvx2() has checked the CPU (see SkinVertices).
#define MSDEFORM_TARGET_AVX2 __attribute__((target("avx2,fma")))
#endif

namespace msdeform {
namespace {

void CheckInputs(const Eigen::Matrix3Xd& rest, const DeformationGraph& graph,
                 const NodeTransforms& transforms, const SkinningOptions& options) {
  std::string error;
  CHECK(options.Check(&error)) << error;
  CHECK_EQ(transforms.rotations.cols(), graph.num_nodes());
  CHECK_EQ(transforms.translations.cols(), graph.num_nodes());
  CHECK_EQ(graph.weights.num_vertices(), rest.cols()) << "the graph was built for another mesh";
}

// A parallel loop that never waits for a helper thread that has not started.
// An OpenMP region ends with a barrier for every thread of the team: on a
// loaded machine a helper the scheduler has not run yet holds the caller for
// a whole time slice (measured: 2-thread skinning of 42K vertices at 11-23 ms
// instead of 1.5 ms under load 5 on 2 cores). Here the caller and persistent
// helpers take chunks from atomic counters, and the caller waits only for
// chunks a helper has actually taken; a helper that wakes late finds none.
//
// The chunks are split into one contiguous range per thread, each with its
// own counter: a thread takes the chunks of its range in order, then those
// left in the others' ranges. Chunks dealt out one by one from a single
// counter interleave the threads' memory streams every chunk, and that was
// 30% slower (1.66M armadillo, 2 threads: 3.9 ms against 2.9 ms for
// contiguous halves, one thread 5.7 ms; docs/decisions/many-cores-stages.md).
class ChunkPool {
 public:
  static ChunkPool& Get() {
    static ChunkPool* pool = new ChunkPool;  // helpers live for the process
    return *pool;
  }

  void Run(int count, int chunk, int num_threads, const std::function<void(int, int)>& body) {
    const int num_chunks = (count + chunk - 1) / chunk;
    if (num_threads <= 1 || num_chunks <= 1) {
      if (count > 0) body(0, count);
      return;
    }
    const int num_ranges = std::min(num_threads, num_chunks);
    auto job = std::make_shared<Job>(num_ranges);
    job->body = &body;
    job->count = count;
    job->chunk = chunk;
    job->num_chunks = num_chunks;
    for (int r = 0; r < num_ranges; ++r) {
      job->ranges[r].next.store(job->RangeBegin(r), std::memory_order_relaxed);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      while (static_cast<int>(helpers_.size()) < num_threads - 1)
        helpers_.emplace_back([this] { Helper(); });
      job_ = job;
      ++generation_;
    }
    wake_.notify_all();
    Work(job.get());
    while (job->done.load(std::memory_order_acquire) < num_chunks) std::this_thread::yield();
  }

 private:
  // A range's next chunk, alone on its cache line.
  struct alignas(64) Range {
    std::atomic<int> next{0};
  };

  struct Job {
    explicit Job(int num_ranges) : num_ranges(num_ranges), ranges(new Range[num_ranges]) {}
    // Chunks [RangeBegin(r), RangeBegin(r + 1)) make range r.
    int RangeBegin(int r) const {
      return static_cast<int>(static_cast<int64_t>(num_chunks) * r / num_ranges);
    }

    const std::function<void(int, int)>* body = nullptr;  // valid while chunks remain
    int count = 0, chunk = 0, num_chunks = 0;
    const int num_ranges;
    std::unique_ptr<Range[]> ranges;
    std::atomic<int> arrived{0};  // threads that have come to work (the caller first)
    alignas(64) std::atomic<int> done{0};
  };

  static void Work(Job* job) {
    const int first = job->arrived.fetch_add(1, std::memory_order_relaxed) % job->num_ranges;
    for (int i = 0; i < job->num_ranges; ++i) {
      const int r = (first + i) % job->num_ranges;
      const int end = job->RangeBegin(r + 1);
      for (;;) {
        const int c = job->ranges[r].next.fetch_add(1, std::memory_order_relaxed);
        if (c >= end) break;
        (*job->body)(c * job->chunk, std::min(job->count, (c + 1) * job->chunk));
        job->done.fetch_add(1, std::memory_order_release);
      }
    }
  }

  void Helper() {
    uint64_t seen = 0;
    for (;;) {
      std::shared_ptr<Job> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_ != seen; });
        seen = generation_;
        job = job_;
      }
      Work(job.get());
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::shared_ptr<Job> job_;
  uint64_t generation_ = 0;
  std::vector<std::thread> helpers_;
};

int NumThreads(const SkinningOptions& options) {
  return options.num_threads > 0 ? options.num_threads : omp_get_max_threads();
}

// Per node j, one record of kRecord doubles holding what Eq. 9 and the normal
// formula need, each 3-vector padded to 4 so that one 256-bit register holds
// it and the per-vertex work is 4-wide FMAs with no shuffles:
//   [ 0,  4)  M_j col 0   (M_j = R_j - I)      [16, 20)  Q_j col 0   (Q_j = R_j^{-T})
//   [ 4,  8)  M_j col 1                         [20, 24)  Q_j col 1
//   [ 8, 12)  M_j col 2                         [24, 28)  Q_j col 2
//   [12, 16)  c_j = t_j - M_j g_j               [28, 32)  zero
// Padding lanes are zero. A record is 256 bytes, 64-byte aligned: the
// positions read its first two cache lines, the normals the last two.
constexpr int kRecord = 32;
constexpr int kM0 = 0, kM1 = 4, kM2 = 8, kC = 12, kQ0 = 16, kQ1 = 20, kQ2 = 24;

// Fills the records of all nodes; returns the first, 64-byte aligned, inside
// *storage.
const double* BuildNodeRecords(const DeformationGraph& graph, const NodeTransforms& transforms,
                               std::vector<double>* storage) {
  const int num_nodes = graph.num_nodes();
  storage->assign(static_cast<size_t>(kRecord) * num_nodes + 8, 0.0);
  double* records = storage->data();
  while (reinterpret_cast<uintptr_t>(records) % 64 != 0) ++records;
  // Per-node work is small (at most a few thousand nodes): one thread.
  for (int j = 0; j < num_nodes; ++j) {
    double* record = records + static_cast<size_t>(kRecord) * j;
    const Eigen::Matrix3d r = transforms.rotation(j);
    const Eigen::Matrix3d m = r - Eigen::Matrix3d::Identity();
    const Eigen::Vector3d c = transforms.translations.col(j) - m * graph.positions.col(j);
    // Cofactor matrix: cofactor = det(R) R^{-T}; Q_j is the cofactor matrix
    // itself where |det R| < 1e-12 (finite; skinning.h).
    Eigen::Matrix3d cofactor;
    cofactor.col(0) = r.col(1).cross(r.col(2));
    cofactor.col(1) = r.col(2).cross(r.col(0));
    cofactor.col(2) = r.col(0).cross(r.col(1));
    const double det = r.col(0).dot(cofactor.col(0));
    const Eigen::Matrix3d q = std::abs(det) >= 1e-12 ? Eigen::Matrix3d(cofactor / det) : cofactor;
    for (int a = 0; a < 3; ++a) {
      record[kM0 + a] = m(a, 0);
      record[kM1 + a] = m(a, 1);
      record[kM2 + a] = m(a, 2);
      record[kC + a] = c(a);
      record[kQ0 + a] = q(a, 0);
      record[kQ1 + a] = q(a, 1);
      record[kQ2 + a] = q(a, 2);
    }
  }
  return records;
}

// One skinning call as raw arrays (all 3 by #V column-major, or k by #V).
// rest_positions / rest_normals are nullptr when that half is not wanted.
// The node ids are 16-bit or 32-bit (SkinningWeights); the kernels are
// instantiated for both.
struct SkinJob {
  const double* records = nullptr;
  const uint16_t* ids16 = nullptr;
  const int32_t* ids32 = nullptr;
  const float* weights = nullptr;
  int k = 0;
  const double* rest_positions = nullptr;
  const double* rest_normals = nullptr;
  double* positions = nullptr;
  double* normals = nullptr;
  const int* subset = nullptr;  // nullptr: item i is vertex i

  int Vertex(int i) const { return subset != nullptr ? subset[i] : i; }
  template <typename Id>
  const Id* Ids() const;
};

template <>
const uint16_t* SkinJob::Ids<uint16_t>() const {
  return ids16;
}
template <>
const int32_t* SkinJob::Ids<int32_t>() const {
  return ids32;
}

// The portable kernel, for CPUs without AVX2 and FMA (and for tests: see
// SkinningOptions::use_simd). The same operations in the same order as the
// AVX2 kernel, only with the multiply-adds rounded twice instead of once. The
// blend runs over the 16 doubles of the wanted half (kRecord) in loops of
// fixed length with no branch inside, which the compiler vectorises for
// whatever the build targets (SSE2 on plain x86-64; a branch per lane instead
// made this kernel 5x slower, docs/decisions/millions-of-vertices.md).
template <typename Id, bool kPositions, bool kNormals>
void SkinRangePortable(const SkinJob& job, int begin, int end) {
  constexpr int kHalf = kQ0;  // doubles per half of a record
  for (int i = begin; i < end; ++i) {
    const size_t v = job.Vertex(i);
    const Id* nodes = job.Ids<Id>() + job.k * v;
    const float* weights = job.weights + job.k * v;
    // b = sum_s w_s record(node_s) over each wanted half: positions [kM0,
    // kQ0), normals [kQ0, kRecord).
    double b[kRecord] = {};
    for (int s = 0; s < job.k; ++s) {
      const double w = static_cast<double>(weights[s]);
      const double* record = job.records + static_cast<size_t>(kRecord) * nodes[s];
      if (kPositions) {
        for (int l = 0; l < kHalf; ++l) b[l] += w * record[l];
      }
      if (kNormals) {
        for (int l = kHalf; l < kRecord; ++l) b[l] += w * record[l];
      }
    }
    if (kPositions) {
      // v' = v + (M v + c), M and c blended.
      const double* p = job.rest_positions + 3 * v;
      double* out = job.positions + 3 * v;
      for (int a = 0; a < 3; ++a) {
        out[a] = p[a] + (((b[kC + a] + b[kM0 + a] * p[0]) + b[kM1 + a] * p[1]) + b[kM2 + a] * p[2]);
      }
    }
    if (kNormals) {
      const double* n = job.rest_normals + 3 * v;
      double q[3];
      for (int a = 0; a < 3; ++a) {
        q[a] = (b[kQ0 + a] * n[0] + b[kQ1 + a] * n[1]) + b[kQ2 + a] * n[2];
      }
      const double length = std::sqrt((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]);
      const bool usable = length > 0.0 && std::isfinite(length);
      // A positive finite length is in [2.2e-162, 1.4e154] (its square is a
      // double), so the reciprocal is finite.
      const double scale = 1.0 / length;
      double* out = job.normals + 3 * v;
      for (int a = 0; a < 3; ++a) out[a] = usable ? q[a] * scale : 0.0;
    }
  }
}

#ifdef MSDEFORM_SKINNING_AVX2

// Whether this CPU (and OS) runs AVX2 and FMA code.
bool RunsAvx2() {
  static const bool runs = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return runs;
}

// Stores lanes x, y, z of `value` at out[0..2]: a 2-wide and a 1-wide store
// (on AMD's Zen a masked 4-wide store is microcoded and several times slower;
// measured on the 1.66M armadillo, docs/decisions/millions-of-vertices.md).
MSDEFORM_TARGET_AVX2 inline __attribute__((always_inline)) void Store3(__m256d value,
                                                                       double* out) {
  _mm_storeu_pd(out, _mm256_castpd256_pd128(value));
  _mm_store_sd(out + 2, _mm256_extractf128_pd(value, 1));
}

// Normalises the 4 normals and stores the first `count` as columns vertex[i]
// of `normals` (zero where the length is 0 or not finite), as n * (1 / |n|):
// one 4-wide sqrt and one 4-wide division for 4 normals.
MSDEFORM_TARGET_AVX2 inline __attribute__((always_inline)) void StoreUnitNormals(
    const __m256d (&unnormalised)[4], const size_t (&vertex)[4], int count, double* normals) {
  // Squared lengths (x^2 + y^2) + z^2 of the 4 normals in one register (lane
  // 3 of each is 0): the hadds give x^2 + y^2 and z^2 + 0 per normal.
  const __m256d xy_z01 = _mm256_hadd_pd(_mm256_mul_pd(unnormalised[0], unnormalised[0]),
                                        _mm256_mul_pd(unnormalised[1], unnormalised[1]));
  const __m256d xy_z23 = _mm256_hadd_pd(_mm256_mul_pd(unnormalised[2], unnormalised[2]),
                                        _mm256_mul_pd(unnormalised[3], unnormalised[3]));
  const __m256d squared = _mm256_add_pd(_mm256_permute2f128_pd(xy_z01, xy_z23, 0x20),
                                        _mm256_permute2f128_pd(xy_z01, xy_z23, 0x31));
  const __m256d length = _mm256_sqrt_pd(squared);
  // length > 0 and finite (ordered compares: false for NaN).
  const int usable = _mm256_movemask_pd(
      _mm256_and_pd(_mm256_cmp_pd(length, _mm256_setzero_pd(), _CMP_GT_OQ),
                    _mm256_cmp_pd(length, _mm256_set1_pd(HUGE_VAL), _CMP_LT_OQ)));
  alignas(32) double scale[4];
  _mm256_store_pd(scale, _mm256_div_pd(_mm256_set1_pd(1.0), length));
#pragma GCC unroll 4
  for (int i = 0; i < count; ++i) {
    const __m256d unit = (usable >> i & 1) != 0
                             ? _mm256_mul_pd(unnormalised[i], _mm256_broadcast_sd(scale + i))
                             : _mm256_setzero_pd();
    Store3(unit, normals + 3 * vertex[i]);
  }
}

// Up to 4 vertices, items first .. first + count - 1 of the job. Per vertex the
// k records are blended with one FMA per 4-lane group (7 registers), then
// M v + c and Q n take 3 FMAs each with broadcast coordinates; the 4 normals
// are then normalised together. kK is k when known at compile time (the loop
// over the nearest nodes is then unrolled), 0 for job.k.
template <typename Id, bool kPositions, bool kNormals, int kK>
MSDEFORM_TARGET_AVX2 inline __attribute__((always_inline)) void SkinBlockAvx2(
    const SkinJob& job, int first, int count) {
  const int k = kK > 0 ? kK : job.k;
  __m256d unnormalised[4];
  size_t vertex[4] = {};
#pragma GCC unroll 4
  for (int i = 0; i < 4; ++i) {
    if (i >= count) {
      unnormalised[i] = _mm256_setr_pd(1.0, 0.0, 0.0, 0.0);  // a unit vector: a harmless lane
      continue;
    }
    const size_t v = job.Vertex(first + i);
    vertex[i] = v;
    const Id* nodes = job.Ids<Id>() + k * v;
    const float* weights = job.weights + k * v;
    __m256d m0 = _mm256_setzero_pd(), m1 = m0, m2 = m0, c = m0, q0 = m0, q1 = m0, q2 = m0;
#pragma GCC unroll 8
    for (int s = 0; s < k; ++s) {
      const __m256d w = _mm256_set1_pd(static_cast<double>(weights[s]));
      const double* record = job.records + static_cast<size_t>(kRecord) * nodes[s];
      if (kPositions) {
        m0 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kM0), m0);
        m1 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kM1), m1);
        m2 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kM2), m2);
        c = _mm256_fmadd_pd(w, _mm256_load_pd(record + kC), c);
      }
      if (kNormals) {
        q0 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kQ0), q0);
        q1 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kQ1), q1);
        q2 = _mm256_fmadd_pd(w, _mm256_load_pd(record + kQ2), q2);
      }
    }
    if (kPositions) {
      const double* p = job.rest_positions + 3 * v;
      const __m256d x = _mm256_broadcast_sd(p), y = _mm256_broadcast_sd(p + 1),
                    z = _mm256_broadcast_sd(p + 2);
      const __m256d moved =
          _mm256_fmadd_pd(m2, z, _mm256_fmadd_pd(m1, y, _mm256_fmadd_pd(m0, x, c)));
      // (x, y, z, z) from the broadcasts: no 4-wide load past the column.
      const __m256d rest = _mm256_blend_pd(_mm256_blend_pd(x, y, 0b0010), z, 0b1100);
      Store3(_mm256_add_pd(rest, moved), job.positions + 3 * v);
    }
    if (kNormals) {
      const double* n = job.rest_normals + 3 * v;
      unnormalised[i] = _mm256_fmadd_pd(q2, _mm256_broadcast_sd(n + 2),
                                        _mm256_fmadd_pd(q1, _mm256_broadcast_sd(n + 1),
                                                        _mm256_mul_pd(q0, _mm256_broadcast_sd(n))));
    }
  }
  if (kNormals) StoreUnitNormals(unnormalised, vertex, count, job.normals);
}

// Items begin .. end - 1 in blocks of 4. On the 104K armadillo (claw-drag
// graph, one Xeon core) this takes about 0.85 ms where only reading its inputs
// and writing its outputs takes about 0.5 ms: it is close to memory-bound.
// Hence left out, measured: a 512-bit variant (4 FMAs per record instead of
// 7; about 4% faster) and software prefetching (no gain). On AMD's Zen 3 with
// the compact ids and weights the positions pass is bound by its FMAs instead
// (1.66M vertices: 12.7 ms on one core, about 6.7 ms on two, against 4 ms
// for reading and writing the positions alone; docs/decisions/millions-of-vertices.md). On Zen 4
// it is within 1.2-1.4x of its bare memory traffic on two threads
// (bench/skinning_benchmark, BM_SkinMemoryFloor), and a row layout with a
// quarter fewer FMAs was no faster (docs/decisions/millions-of-vertices.md).
template <typename Id, bool kPositions, bool kNormals>
MSDEFORM_TARGET_AVX2 void SkinRangeAvx2(const SkinJob& shared_job, int begin, int end) {
  // A local copy: the compiler then knows the stores to the outputs leave it
  // alone and keeps its fields in registers.
  const SkinJob job = shared_job;
  int i = begin;
  if (job.k == 4) {  // the paper's k and the default
    for (; i + 4 <= end; i += 4) SkinBlockAvx2<Id, kPositions, kNormals, 4>(job, i, 4);
  } else {
    for (; i + 4 <= end; i += 4) SkinBlockAvx2<Id, kPositions, kNormals, 0>(job, i, 4);
  }
  if (i < end) SkinBlockAvx2<Id, kPositions, kNormals, 0>(job, i, end - i);
}

#endif  // MSDEFORM_SKINNING_AVX2

using Range = void (*)(const SkinJob&, int, int);

// The kernel for ids of type Id, the wanted halves and the SIMD choice.
template <typename Id>
Range PickRange(bool positions, bool normals, bool simd) {
#ifdef MSDEFORM_SKINNING_AVX2
  if (simd) {
    return positions && normals ? SkinRangeAvx2<Id, true, true>
           : positions          ? SkinRangeAvx2<Id, true, false>
                                : SkinRangeAvx2<Id, false, true>;
  }
#endif
  (void)simd;
  return positions && normals ? SkinRangePortable<Id, true, true>
         : positions          ? SkinRangePortable<Id, true, false>
                              : SkinRangePortable<Id, false, true>;
}

// Skins the vertices of `subset` (all when nullptr) into *deformed from
// `rest_vertices` and into *deformed_normals from `rest_normals`; a half
// whose rest input is nullptr is skipped. Inputs are checked by the caller.
void SkinVertices(const Eigen::Matrix3Xd* rest_vertices, const Eigen::Matrix3Xd* rest_normals,
                  const DeformationGraph& graph, const NodeTransforms& transforms,
                  const std::vector<int>* subset, Eigen::Matrix3Xd* deformed,
                  Eigen::Matrix3Xd* deformed_normals, const SkinningOptions& options) {
  std::vector<double> storage;
  SkinJob job;
  job.records = BuildNodeRecords(graph, transforms, &storage);
  job.ids16 = graph.weights.ids16();
  job.ids32 = graph.weights.ids32();
  job.weights = graph.weights.weights();
  job.k = graph.weights.k();
  if (rest_vertices != nullptr) {
    job.rest_positions = rest_vertices->data();
    job.positions = deformed->data();
  }
  if (rest_normals != nullptr) {
    job.rest_normals = rest_normals->data();
    job.normals = deformed_normals->data();
  }
  job.subset = subset != nullptr ? subset->data() : nullptr;
  const int count = subset != nullptr ? static_cast<int>(subset->size())
                                      : graph.weights.num_vertices();
  const bool positions = rest_vertices != nullptr, normals = rest_normals != nullptr;
  const bool simd = options.use_simd && SkinningSimdAvailable();
  const Range range = graph.weights.has_16bit_ids() ? PickRange<uint16_t>(positions, normals, simd)
                                                    : PickRange<int32_t>(positions, normals, simd);
  // Small subsets are not worth waking a second thread; see ChunkPool.
  const int threads = count < 8192 ? 1 : NumThreads(options);
  const std::function<void(int, int)> body = [&](int begin, int end) { range(job, begin, end); };
  ChunkPool::Get().Run(count, 2048, threads, body);
}

}  // namespace

bool SkinningOptions::Check(std::string* error) const {
  if (num_threads < 0 || num_threads > kMaxThreads) {
    *error = "num_threads must be in 0.." + std::to_string(kMaxThreads) +
             " (0: OpenMP default), got " + std::to_string(num_threads);
    return false;
  }
  return true;
}

bool SkinningSimdAvailable() {
#ifdef MSDEFORM_SKINNING_AVX2
  return RunsAvx2();
#else
  return false;
#endif
}

void SkinPositions(const Eigen::Matrix3Xd& rest_vertices, const DeformationGraph& graph,
                   const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed,
                   const SkinningOptions& options) {
  CHECK(deformed != nullptr);
  CHECK_NE(deformed, &rest_vertices);
  CheckInputs(rest_vertices, graph, transforms, options);
  deformed->resize(3, rest_vertices.cols());
  SkinVertices(&rest_vertices, nullptr, graph, transforms, nullptr, deformed, nullptr, options);
}

void SkinNormals(const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                 const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed_normals,
                 const SkinningOptions& options) {
  CHECK(deformed_normals != nullptr);
  CHECK_NE(deformed_normals, &rest_normals);
  CheckInputs(rest_normals, graph, transforms, options);
  deformed_normals->resize(3, rest_normals.cols());
  SkinVertices(nullptr, &rest_normals, graph, transforms, nullptr, nullptr, deformed_normals,
               options);
}

void SkinPositionsAndNormals(const Eigen::Matrix3Xd& rest_vertices,
                             const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                             const NodeTransforms& transforms,
                             const std::vector<int>* vertex_subset, Eigen::Matrix3Xd* deformed,
                             Eigen::Matrix3Xd* deformed_normals, const SkinningOptions& options) {
  CHECK(deformed != nullptr || deformed_normals != nullptr);
  CHECK_NE(deformed, &rest_vertices);
  CHECK_NE(deformed_normals, &rest_normals);
  CheckInputs(rest_vertices, graph, transforms, options);
  const int num_vertices = static_cast<int>(rest_vertices.cols());
  if (deformed_normals != nullptr) CHECK_EQ(rest_normals.cols(), num_vertices);
  for (Eigen::Matrix3Xd* out : {deformed, deformed_normals}) {
    if (out == nullptr) continue;
    if (vertex_subset == nullptr) {
      out->resize(3, num_vertices);
    } else {
      CHECK_EQ(out->cols(), num_vertices);
    }
  }
  SkinVertices(deformed != nullptr ? &rest_vertices : nullptr,
               deformed_normals != nullptr ? &rest_normals : nullptr, graph, transforms,
               vertex_subset, deformed, deformed_normals, options);
}

}  // namespace msdeform
