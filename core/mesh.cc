#include "msdeform/core/mesh.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <sstream>
#include <thread>

#include "msdeform/core/parallel.h"

namespace msdeform {
namespace {

// data[i] += data[i - 1] for i = 1 .. n - 1 (an inclusive scan of integers,
// so any split gives the same sums).
template <typename T>
void InclusiveScan(T* data, int64_t n, int num_threads) {
  const int threads = ThreadsFor(num_threads, n);
  if (threads == 1) {
    std::partial_sum(data, data + n, data);
    return;
  }
  std::vector<T> block_total(threads + 1, 0);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    const int64_t lo = n * t / team, hi = n * (t + 1) / team;
    std::partial_sum(data + lo, data + hi, data + lo);
    block_total[t + 1] = hi > lo ? data[hi - 1] : 0;
#pragma omp barrier
#pragma omp single
    std::partial_sum(block_total.begin(), block_total.end(), block_total.begin());
    const T add = block_total[t];
    for (int64_t i = lo; i < hi; ++i) data[i] += add;
  }
}

// A barrier for a team whose threads wait by yielding their core after a
// short spin. OpenMP's barrier spins for milliseconds first, which on a
// machine busy with other work kept a suspended team mate from the core it
// waited for: the scatter below, with its two barriers a block, then ran ten
// times slower.
class YieldingBarrier {
 public:
  explicit YieldingBarrier(int count) : count_(count) {}
  // `sense`: the calling thread's own flag, false before its first wait.
  void Wait(bool* sense) {
    *sense = !*sense;
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) == count_ - 1) {
      arrived_.store(0, std::memory_order_relaxed);
      released_.store(*sense, std::memory_order_release);
      return;
    }
    for (int spin = 0; released_.load(std::memory_order_acquire) != *sense; ++spin) {
      if (spin >= 100) std::this_thread::yield();
    }
  }

 private:
  const int count_;
  std::atomic<int> arrived_{0};
  std::atomic<bool> released_{false};
};

// Hands keyed values from items to the threads that own the keys, in item
// order: emit_range(begin, end, push) calls push(key, value) for the items
// begin .. end - 1 in turn (at most kMaxPushes times an item), and
// consume(key, value) then sees, for each key, the values pushed for it in
// the order of the items (and of the pushes of one item), as one thread
// looping over the items would. Keys are dealt to the threads in runs of 256
// (run r to thread (hash(r) * team) >> 32: spread evenly whatever the keys'
// order), so each thread writes only its own keys' data and no key's updates
// race or change order.
// The items go in blocks: in each block every thread emits from one slice
// of it, then every thread consumes its keys' values, slice by slice. A
// block's entries take at most kScatterBlockBytes (and each thread keeps that
// much room, for its slice's entries to any owner), so that they are still in
// the cache when consumed: blocks of 10 MB a thread made the normals' scatter
// 30% slower. Each block costs two barriers, where a thread that the system
// suspends holds up the others: OpenMP's barrier, which spins for
// milliseconds, made 600 blocks a pass ten times slower on a 2-core machine
// busy with other work; YieldingBarrier gives the core up.
constexpr int64_t kScatterBlockBytes = 2 << 20;

template <typename Value, int kMaxPushes, typename EmitRange, typename Consume>
void OrderedScatter(int64_t num_items, int num_threads, const EmitRange& emit_range,
                    const Consume& consume) {
  const int threads = ThreadsFor(num_threads, num_items);
  if (threads == 1) {
    emit_range(0, num_items, consume);
    return;
  }
  constexpr int kRunBits = 8;  // kRun = 256 keys
  using Entry = std::pair<int, Value>;
  const int64_t block = std::max<int64_t>(
      4 * threads, kScatterBlockBytes / (kMaxPushes * static_cast<int64_t>(sizeof(Entry))));
  // Thread t's entries for owner o: (*buffers[t])[o * capacity ..], (*ends[t])[o]
  // of them. Each thread's arrays are its own allocations (two threads'
  // counters on one cache line made every push a cache miss).
  std::vector<std::vector<Entry>*> buffers(threads);
  std::vector<std::vector<Entry*>*> ends(threads);
  std::unique_ptr<YieldingBarrier> barrier;
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
#pragma omp single
    barrier = std::make_unique<YieldingBarrier>(team);
    bool sense = false;
    const int64_t capacity = (block / team + 1) * kMaxPushes;
    std::vector<Entry> own(capacity * team);
    std::vector<Entry*> end(team);
    buffers[t] = &own;
    ends[t] = &end;
    Entry** const end_of = end.data();
    auto push = [end_of, team](int key, const Value& value) {
      const uint32_t hash = static_cast<uint32_t>(key >> kRunBits) * 2654435761u;
      Entry*& slot = end_of[(static_cast<uint64_t>(hash) * team) >> 32];
      slot->first = key;
      slot->second = value;
      ++slot;
    };
    for (int64_t begin = 0; begin < num_items; begin += block) {
      const int64_t size = std::min(block, num_items - begin);
      for (int o = 0; o < team; ++o) end[o] = own.data() + o * capacity;
      emit_range(begin + size * t / team, begin + size * (t + 1) / team, push);
      barrier->Wait(&sense);
      for (int slice = 0; slice < team; ++slice) {
        const Entry* entry = buffers[slice]->data() + t * capacity;
        for (const Entry* last = (*ends[slice])[t]; entry != last; ++entry) {
          consume(entry->first, entry->second);
        }
      }
      barrier->Wait(&sense);
    }
  }
}

// Sorts a short run in place (rows of a mesh's adjacency: about six):
// insertion sort, cheaper than std::sort's set-up for rows this short.
inline void SortShort(int* first, int* last) {
  if (last - first > 16) {
    std::sort(first, last);
    return;
  }
  for (int* i = first + 1; i < last; ++i) {
    const int value = *i;
    int* j = i;
    for (; j > first && *(j - 1) > value; --j) *j = *(j - 1);
    *j = value;
  }
}

// The upper neighbours of every vertex, deduplicated and sorted: the far
// ends b > a of the edges (a, b) are far[start[a] .. start[a] + size[a]) (a
// row keeps the room of its repeats). The far ends are grouped by the lower
// end (a counting sort), then each small group is sorted and deduplicated:
// linear time, where one sort of all 3 #F pairs took most of a second on a
// 1.7M-vertex mesh. Every step's result is the same whatever the threads
// (groups are sorted after filling). The large array is left uninitialised
// and first written by the threads: zeroing it on one thread (and its page
// faults) was a serial part as long as the parallel ones.
struct UpperNeighbors {
  std::vector<int> start;      // #V + 1
  std::vector<int> size;       // #V
  std::unique_ptr<int[]> far;  // start[#V]
};

UpperNeighbors ComputeUpperNeighbors(const Mesh& mesh, int num_threads) {
  const int num_vertices = mesh.num_vertices(), num_faces = mesh.num_faces();
  // The faces' sides (a, b), a != b, as (lower end, far end).
  auto sides = [&mesh](int64_t begin, int64_t end, const auto& push) {
    for (int64_t f = begin; f < end; ++f) {
      for (int c = 0; c < 3; ++c) {
        const int a = mesh.faces(c, f), b = mesh.faces((c + 1) % 3, f);
        if (a != b) push(std::min(a, b), std::max(a, b));
      }
    }
  };
  UpperNeighbors upper;
  std::vector<int>& start = upper.start;
  start.assign(num_vertices + 1, 0);
  OrderedScatter<int, 3>(num_faces, num_threads, sides, [&](int a, int) { ++start[a + 1]; });
  InclusiveScan(start.data(), start.size(), num_threads);
  const int vertex_threads = ThreadsFor(num_threads, num_vertices);
  upper.far.reset(new int[start[num_vertices]]);
  {
    std::unique_ptr<int[]> fill(new int[num_vertices]);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
    for (int a = 0; a < num_vertices; ++a) fill[a] = start[a];
    OrderedScatter<int, 3>(num_faces, num_threads, sides,
                           [&](int a, int b) { upper.far[fill[a]++] = b; });
  }
  upper.size.resize(num_vertices);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
  for (int a = 0; a < num_vertices; ++a) {
    int* const first = upper.far.get() + start[a];
    int* const last = upper.far.get() + start[a + 1];
    SortShort(first, last);
    upper.size[a] = static_cast<int>(std::unique(first, last) - first);
  }
  return upper;
}

}  // namespace

Eigen::AlignedBox3d BoundingBox(const Mesh& mesh, int num_threads) {
  // Boxes of fixed chunks merged in chunk order: min and max are exact, and
  // the chunks do not depend on the threads.
  constexpr int64_t kChunk = 1 << 14;
  const int n = mesh.num_vertices();
  std::vector<Eigen::AlignedBox3d> boxes(NumChunks(n, kChunk));
  ForEachChunk(n, kChunk, ThreadsFor(num_threads, n), [&](int64_t begin, int64_t end, int64_t c) {
    // Grown apart and stored once: neighbouring boxes share cache lines.
    Eigen::AlignedBox3d box;
    for (int64_t v = begin; v < end; ++v) box.extend(mesh.vertices.col(v));
    boxes[c] = box;
  });
  Eigen::AlignedBox3d box;
  for (const Eigen::AlignedBox3d& chunk_box : boxes) box.extend(chunk_box);
  return box;
}

double BoundingBoxDiagonal(const Mesh& mesh, int num_threads) {
  if (mesh.num_vertices() == 0) return 0.0;
  return BoundingBox(mesh, num_threads).diagonal().norm();
}

std::vector<std::pair<int, int>> UniqueEdges(const Mesh& mesh, int num_threads) {
  const UpperNeighbors upper = ComputeUpperNeighbors(mesh, num_threads);
  const int num_vertices = mesh.num_vertices();
  const int threads = ThreadsFor(num_threads, num_vertices);
  std::vector<int> first_edge(num_vertices + 1, 0);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int a = 0; a < num_vertices; ++a) first_edge[a + 1] = upper.size[a];
  InclusiveScan(first_edge.data(), first_edge.size(), num_threads);
  std::vector<std::pair<int, int>> edges(first_edge[num_vertices]);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int a = 0; a < num_vertices; ++a) {
    for (int i = 0; i < upper.size[a]; ++i) {
      edges[first_edge[a] + i] = {a, upper.far[upper.start[a] + i]};
    }
  }
  return edges;
}

VertexAdjacency ComputeVertexAdjacency(const Mesh& mesh, int num_threads) {
  // Row v: its lower neighbours (from the upper lists of the vertices below
  // v, taken in ascending order), then its upper neighbours: ascending.
  const UpperNeighbors upper = ComputeUpperNeighbors(mesh, num_threads);
  const int num_vertices = mesh.num_vertices();
  const int threads = ThreadsFor(num_threads, num_vertices);
  // The upper edges (a, b), entries i of upper.far (but a row's repeats),
  // as (b, a).
  auto lower_ends = [&upper, num_vertices](int64_t begin, int64_t end, const auto& push) {
    int a = static_cast<int>(std::upper_bound(upper.start.begin(),
                                              upper.start.begin() + num_vertices + 1, begin) -
                             upper.start.begin()) - 1;
    for (int64_t i = begin; i < end; ++i) {
      while (upper.start[a + 1] <= i) ++a;
      if (i < upper.start[a] + upper.size[a]) push(upper.far[i], a);
    }
  };
  std::vector<int> num_lower(num_vertices, 0);
  const int64_t num_entries = upper.start[num_vertices];
  OrderedScatter<int, 1>(num_entries, num_threads, lower_ends,
                         [&](int b, int) { ++num_lower[b]; });
  VertexAdjacency adjacency;
  adjacency.offsets.assign(num_vertices + 1, 0);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) {
    adjacency.offsets[v + 1] = num_lower[v] + upper.size[v];
  }
  InclusiveScan(adjacency.offsets.data(), adjacency.offsets.size(), num_threads);
  adjacency.neighbors.resize(adjacency.offsets.back());
  std::vector<int>& fill = num_lower;  // from here: the next free lower slot of each row
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) {
    const int lower = fill[v];
    fill[v] = adjacency.offsets[v];
    std::copy(upper.far.get() + upper.start[v], upper.far.get() + upper.start[v] + upper.size[v],
              adjacency.neighbors.begin() + adjacency.offsets[v] + lower);
  }
  OrderedScatter<int, 1>(num_entries, num_threads, lower_ends,
                         [&](int b, int a) { adjacency.neighbors[fill[b]++] = a; });
  return adjacency;
}

namespace {
int FindRoot(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

// The same for a union-find that several threads update. A parent is never
// larger than its child and only ever moves up its tree, so a stale read is
// still an ancestor and path halving may store it without a compare.
int FindRoot(std::atomic<int>* parent, int v) {
  int up = parent[v].load(std::memory_order_relaxed);
  while (up != v) {
    const int grand = parent[up].load(std::memory_order_relaxed);
    if (grand != up) parent[v].store(grand, std::memory_order_relaxed);
    v = grand;
    up = parent[v].load(std::memory_order_relaxed);
  }
  return v;
}

// Links the larger root under the smaller, so every root stays the smallest
// vertex of its tree. A failed compare means another thread linked it first.
void Unite(std::atomic<int>* parent, int a, int b) {
  while (true) {
    a = FindRoot(parent, a);
    b = FindRoot(parent, b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    int expected = a;
    if (parent[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
  }
}
}  // namespace

Components ConnectedComponents(const Mesh& mesh, int num_threads) {
  const int n = mesh.num_vertices(), num_faces = mesh.num_faces();
  Components components;
  const int threads = ThreadsFor(num_threads, std::max(n, num_faces));
  if (threads == 1) {
    std::vector<int> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    for (int f = 0; f < num_faces; ++f) {
      for (int c = 1; c < 3; ++c) {
        int a = FindRoot(parent, mesh.faces(0, f));
        int b = FindRoot(parent, mesh.faces(c, f));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    components.component_of_vertex.assign(n, -1);
    std::vector<int> id_of_root(n, -1);
    for (int v = 0; v < n; ++v) {
      int root = FindRoot(parent, v);
      if (id_of_root[root] < 0) id_of_root[root] = components.count++;
      components.component_of_vertex[v] = id_of_root[root];
    }
    return components;
  }
  // Each component's root is its smallest vertex (Unite), and components are
  // numbered in the order of their roots: the numbering above, whatever the
  // order in which the threads linked the trees.
  std::unique_ptr<std::atomic<int>[]> parent(new std::atomic<int>[n]);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int v = 0; v < n; ++v) parent[v].store(v, std::memory_order_relaxed);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int f = 0; f < num_faces; ++f) {
    Unite(parent.get(), mesh.faces(0, f), mesh.faces(1, f));
    Unite(parent.get(), mesh.faces(0, f), mesh.faces(2, f));
  }
  std::vector<int>& component = components.component_of_vertex;
  component.resize(n);
  std::vector<int> roots_before(threads + 1, 0);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    const int lo = static_cast<int>(static_cast<int64_t>(n) * t / team);
    const int hi = static_cast<int>(static_cast<int64_t>(n) * (t + 1) / team);
    int roots = 0;
    for (int v = lo; v < hi; ++v) {
      component[v] = FindRoot(parent.get(), v);
      roots += component[v] == v;
    }
    roots_before[t + 1] = roots;
#pragma omp barrier
#pragma omp single
    {
      std::partial_sum(roots_before.begin(), roots_before.end(), roots_before.begin());
      components.count = roots_before[team];
    }
    // Roots now hold their component's number instead of themselves.
    int id = roots_before[t];
    for (int v = lo; v < hi; ++v) {
      if (component[v] == v) parent[v].store(id++, std::memory_order_relaxed);
    }
#pragma omp barrier
    for (int v = lo; v < hi; ++v) {
      component[v] = parent[component[v]].load(std::memory_order_relaxed);
    }
  }
  return components;
}

Eigen::Matrix3Xd VertexNormals(const Mesh& mesh, int num_threads) {
  const int num_vertices = mesh.num_vertices(), num_faces = mesh.num_faces();
  Eigen::Matrix3Xd normals(3, num_vertices);  // zeroed by the threads below
#pragma omp parallel for num_threads(ThreadsFor(num_threads, num_vertices)) schedule(static)
  for (int v = 0; v < num_vertices; ++v) normals.col(v).setZero();
  auto area_normal = [&mesh](int f) -> Eigen::Vector3d {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f));
    const Eigen::Vector3d b = mesh.vertices.col(mesh.faces(1, f));
    const Eigen::Vector3d c = mesh.vertices.col(mesh.faces(2, f));
    return (b - a).cross(c - a);  // 2 x area.
  };
  const int threads = ThreadsFor(num_threads, num_faces);
  if (threads == 1) {
    for (int f = 0; f < num_faces; ++f) {
      const Eigen::Vector3d term = area_normal(f);
      for (int k = 0; k < 3; ++k) normals.col(mesh.faces(k, f)) += term;
    }
  } else {
    // A vertex's terms are added in face order, as on one thread, so the
    // sums are the same bits: each face's term goes to the threads owning
    // its corners (OrderedScatter).
    OrderedScatter<Eigen::Vector3d, 3>(
        num_faces, num_threads,
        [&](int64_t begin, int64_t end, const auto& push) {
          for (int64_t f = begin; f < end; ++f) {
            const Eigen::Vector3d term = area_normal(static_cast<int>(f));
            for (int k = 0; k < 3; ++k) push(mesh.faces(k, f), term);
          }
        },
        [&](int v, const Eigen::Vector3d& term) { normals.col(v) += term; });
  }
#pragma omp parallel for num_threads(ThreadsFor(num_threads, num_vertices)) schedule(static)
  for (int v = 0; v < num_vertices; ++v) {
    const double norm = normals.col(v).norm();
    if (norm > 0.0) normals.col(v) /= norm;
  }
  return normals;
}

bool ValidateMesh(const Mesh& mesh, std::string* error) {
  std::ostringstream message;
  if (mesh.num_vertices() == 0 || mesh.num_faces() == 0) {
    message << "mesh has " << mesh.num_vertices() << " vertices and "
            << mesh.num_faces() << " faces; need at least one triangle";
    *error = message.str();
    return false;
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.vertices.col(v).allFinite()) {
      message << "vertex " << v << " has a non-finite coordinate";
      *error = message.str();
      return false;
    }
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int id = mesh.faces(c, f);
      if (id < 0 || id >= mesh.num_vertices()) {
        message << "face " << f << " refers to vertex " << id
                << " outside 0.." << mesh.num_vertices() - 1;
        *error = message.str();
        return false;
      }
    }
    if (mesh.faces(0, f) == mesh.faces(1, f) || mesh.faces(1, f) == mesh.faces(2, f) ||
        mesh.faces(0, f) == mesh.faces(2, f)) {
      message << "face " << f << " repeats a vertex";
      *error = message.str();
      return false;
    }
  }
  return true;
}

}  // namespace msdeform
