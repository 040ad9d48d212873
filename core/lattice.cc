#include "msdeform/core/lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <utility>

#include <glog/logging.h>
#include <omp.h>

#include "msdeform/core/nearest_nodes.h"  // kMaxThreads
#include "msdeform/core/parallel.h"

namespace msdeform {
namespace {

constexpr int kEmpty = -1;
constexpr int kSurfaceMark = -2;
constexpr int kOutsideMark = -3;
// A cell without a vertex that a triangle crosses: a wall for the flood fill
// only (it becomes an interior particle, being inside the surface).
constexpr int kWallMark = -4;

// Builds compressed lists from (row, value) pairs: each row's values
// ascending, duplicates removed. A counting sort by row, then a sort of each
// (short) row: linear in the pairs, where one sort of all of them (1.66M
// vertex-cell pairs on the 1.66M armadillo) was a tenth of the lattice's time.
// On several threads each takes a slice of the pairs with its own row counts
// (as many slices as leave the counts no bigger than the pairs); rows are
// sorted at the end, so the lists are the same for every thread count.
CompressedLists ListsFromPairs(int num_rows, const std::vector<std::pair<int, int>>& pairs,
                               int num_threads) {
  const int64_t num_pairs = static_cast<int64_t>(pairs.size());
  const int slices = static_cast<int>(std::max<int64_t>(
      1, std::min<int64_t>(ThreadsFor(num_threads, num_pairs),
                           num_pairs / std::max(num_rows, 1))));
  // count[s * num_rows + r]: pairs of row r in slice s, then where they go.
  std::vector<int64_t> count(static_cast<size_t>(slices) * num_rows, 0);
  auto slice_begin = [&](int s) { return num_pairs * s / slices; };
#pragma omp parallel for num_threads(slices) schedule(static)
  for (int s = 0; s < slices; ++s) {
    int64_t* own = count.data() + static_cast<size_t>(s) * num_rows;
    for (int64_t i = slice_begin(s); i < slice_begin(s + 1); ++i) ++own[pairs[i].first];
  }
  CompressedLists lists;
  lists.offsets.assign(num_rows + 1, 0);
  const int row_threads = ThreadsFor(num_threads, static_cast<int64_t>(num_rows) * slices);
#pragma omp parallel for num_threads(row_threads) schedule(static)
  for (int r = 0; r < num_rows; ++r) {
    int64_t total = 0;
    for (int s = 0; s < slices; ++s) {
      const int64_t in_slice = count[static_cast<size_t>(s) * num_rows + r];
      count[static_cast<size_t>(s) * num_rows + r] = total;
      total += in_slice;
    }
    lists.offsets[r + 1] = total;
  }
  for (int r = 0; r < num_rows; ++r) lists.offsets[r + 1] += lists.offsets[r];
  std::vector<int> values(num_pairs);
#pragma omp parallel for num_threads(slices) schedule(static)
  for (int s = 0; s < slices; ++s) {
    int64_t* next = count.data() + static_cast<size_t>(s) * num_rows;
    for (int64_t i = slice_begin(s); i < slice_begin(s + 1); ++i) {
      const auto& [row, value] = pairs[i];
      values[lists.offsets[row] + next[row]++] = value;
    }
  }
  std::vector<int64_t>().swap(count);
  // Sort each row and count its distinct values, then copy them down.
  std::vector<int64_t> kept(num_rows + 1, 0);
  const int sort_threads = ThreadsFor(num_threads, num_pairs);
#pragma omp parallel for num_threads(sort_threads) schedule(dynamic, 256)
  for (int r = 0; r < num_rows; ++r) {
    const auto first = values.begin() + lists.offsets[r];
    const auto last = values.begin() + lists.offsets[r + 1];
    std::sort(first, last);
    kept[r + 1] = std::unique(first, last) - first;
  }
  for (int r = 0; r < num_rows; ++r) kept[r + 1] += kept[r];
  if (kept[num_rows] == num_pairs) {
    lists.values = std::move(values);
    return lists;
  }
  lists.values.resize(kept[num_rows]);
#pragma omp parallel for num_threads(sort_threads) schedule(static)
  for (int r = 0; r < num_rows; ++r) {
    std::copy(values.begin() + lists.offsets[r],
              values.begin() + lists.offsets[r] + (kept[r + 1] - kept[r]),
              lists.values.begin() + kept[r]);
  }
  lists.offsets = std::move(kept);
  return lists;
}

// The lists one after another, in list order; empties them.
std::vector<std::pair<int, int>> Concatenate(
    std::vector<std::vector<std::pair<int, int>>>* lists) {
  size_t total = 0;
  for (const auto& list : *lists) total += list.size();
  std::vector<std::pair<int, int>> all;
  all.reserve(total);
  for (auto& list : *lists) {
    all.insert(all.end(), list.begin(), list.end());
    std::vector<std::pair<int, int>>().swap(list);
  }
  return all;
}

// Six times the signed volume each component encloses: the sum over its
// faces of a . (b x c). Only its sign is read. A mesh of fewer than
// kParallelMinItems faces is summed in face order; a larger one in blocks of
// kVolumeBlock faces, each a sum per run of faces of one component, the runs
// then added in face order: the same sums on any number of threads.
constexpr int kVolumeBlock = 1 << 16;

std::vector<double> ComponentVolumes(const Mesh& mesh, const Components& components,
                                     int num_threads) {
  const int num_faces = mesh.num_faces();
  auto term = [&mesh](int f) {
    const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f));
    const Eigen::Vector3d b = mesh.vertices.col(mesh.faces(1, f));
    const Eigen::Vector3d c = mesh.vertices.col(mesh.faces(2, f));
    return a.dot(b.cross(c));
  };
  auto component_of = [&](int f) { return components.component_of_vertex[mesh.faces(0, f)]; };
  std::vector<double> volume(components.count, 0.0);
  if (num_faces < kParallelMinItems) {
    for (int f = 0; f < num_faces; ++f) volume[component_of(f)] += term(f);
    return volume;
  }
  const int num_blocks = (num_faces + kVolumeBlock - 1) / kVolumeBlock;
  std::vector<std::vector<std::pair<int, double>>> runs(num_blocks);
#pragma omp parallel for num_threads(ThreadsFor(num_threads, num_faces)) schedule(static)
  for (int block = 0; block < num_blocks; ++block) {
    const int end = std::min(num_faces, (block + 1) * kVolumeBlock);
    for (int f = block * kVolumeBlock; f < end; ++f) {
      const int component = component_of(f);
      if (runs[block].empty() || runs[block].back().first != component) {
        runs[block].emplace_back(component, 0.0);
      }
      runs[block].back().second += term(f);
    }
  }
  for (const auto& block_runs : runs) {
    for (const auto& [component, sum] : block_runs) volume[component] += sum;
  }
  return volume;
}

// The pieces of each surface cell (lattice.h): vertex v of cell c gets the
// index, among the pieces of c, of the piece holding it, pieces numbered by
// their smallest vertex; vertices in no face join the cell's first piece.
// Mesh edges join a piece's vertices first within the
// cell itself; only a cell that this leaves in several pieces is searched
// again within the cell grown by `margin` cells on each side, which merges
// the parts of one sheet that the cell's walls cut apart. Every cell is
// searched on its own (its vertices' piece numbers and its count are written
// by it alone), so the cells are shared out among the threads.
template <typename CoordsOf>
void FindPieces(const Mesh& mesh, const Lattice& lattice, const VertexAdjacency& adjacency,
                const std::vector<long long>& surface_grid_cells, const CoordsOf& coords_of,
                const std::vector<int>& cell_of_vertex, double margin, int num_threads,
                std::vector<int>* piece_of_vertex, std::vector<int>* num_pieces) {
  const int num_cells = static_cast<int>(surface_grid_cells.size());
  const int num_vertices = mesh.num_vertices();
  std::vector<std::pair<int, int>> cell_vertex(num_vertices);
  const int vertex_threads = ThreadsFor(num_threads, num_vertices);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) cell_vertex[v] = {cell_of_vertex[v], v};
  const CompressedLists vertices_of_cell = ListsFromPairs(num_cells, cell_vertex, num_threads);
  std::vector<std::pair<int, int>>().swap(cell_vertex);
  // rank[v]: v's place in its cell's list, the index of its mark in the
  // cell's search.
  std::vector<int> rank(num_vertices);
#pragma omp parallel for num_threads(ThreadsFor(num_threads, num_vertices)) schedule(dynamic, 64)
  for (int c = 0; c < num_cells; ++c) {
    for (int i = 0; i < vertices_of_cell.size(c); ++i) rank[vertices_of_cell.begin(c)[i]] = i;
  }
  const double w = lattice.cell_width();
  auto is_isolated = [&](int v) { return adjacency.offsets[v] == adjacency.offsets[v + 1]; };
  // One search of cell c: within the cell itself (grown = false, marks by
  // rank) or within the grown cell (marks in a set).
  struct Search {
    std::vector<char> seen;          // by rank, within the cell
    std::unordered_set<int> grown;   // vertices reached, within the grown cell
    std::vector<int> queue;
  };
  auto label = [&](int c, bool grown_cell, Search& search) {
    const Eigen::Vector3d centre =
        lattice.origin() + w * coords_of(surface_grid_cells[c]).template cast<double>();
    const double half_width = (0.5 + margin) * w;
    search.seen.assign(vertices_of_cell.size(c), 0);
    search.grown.clear();
    // Marks v reached; false if it was already.
    auto visit = [&](int v) {
      if (!grown_cell) {
        char& seen = search.seen[rank[v]];
        if (seen) return false;
        return seen = 1, true;
      }
      return search.grown.insert(v).second;
    };
    int pieces = 0;
    bool isolated = false;  // a vertex in no face: no piece of surface of its own
    for (const int* start = vertices_of_cell.begin(c); start != vertices_of_cell.end(c); ++start) {
      if (is_isolated(*start)) {
        isolated = true;
        continue;
      }
      if (!visit(*start)) continue;
      search.queue.assign(1, *start);
      while (!search.queue.empty()) {
        const int u = search.queue.back();
        search.queue.pop_back();
        if (cell_of_vertex[u] == c) (*piece_of_vertex)[u] = pieces;
        for (int i = adjacency.offsets[u]; i < adjacency.offsets[u + 1]; ++i) {
          const int next = adjacency.neighbors[i];
          const bool inside =
              !grown_cell
                  ? cell_of_vertex[next] == c
                  : ((mesh.vertices.col(next) - centre).cwiseAbs().array() <= half_width).all();
          if (inside && visit(next)) search.queue.push_back(next);
        }
      }
      ++pieces;
    }
    if (isolated) {  // into the cell's first piece
      for (const int* v = vertices_of_cell.begin(c); v != vertices_of_cell.end(c); ++v) {
        if (is_isolated(*v)) (*piece_of_vertex)[*v] = 0;
      }
      pieces = std::max(pieces, 1);
    }
    return pieces;
  };
#pragma omp parallel num_threads(vertex_threads)
  {
    Search search;
#pragma omp for schedule(dynamic, 16)
    for (int c = 0; c < num_cells; ++c) {
      (*num_pieces)[c] = label(c, false, search);
      if ((*num_pieces)[c] > 1 && margin > 0.0) (*num_pieces)[c] = label(c, true, search);
    }
  }
}

// L-list pairs (both directions) from the mesh edges that join two surface
// particles: each thread gathers the pairs of a slice of the vertices (both
// directions of an edge come from its two ends); the lists are sorted by
// ListsFromPairs, so their order is free.
std::vector<std::pair<int, int>> SurfaceParticlePairs(const std::vector<int>& particle_of_vertex,
                                                      const VertexAdjacency& adjacency,
                                                      int vertex_threads) {
  const int num_vertices = static_cast<int>(particle_of_vertex.size());
  std::vector<std::vector<std::pair<int, int>>> thread_pairs(vertex_threads);
#pragma omp parallel num_threads(vertex_threads)
  {
    std::vector<std::pair<int, int>> own;  // not in thread_pairs: no shared cache line
#pragma omp for schedule(static) nowait
    for (int a = 0; a < num_vertices; ++a) {
      const int pa = particle_of_vertex[a];
      for (int i = adjacency.offsets[a]; i < adjacency.offsets[a + 1]; ++i) {
        const int pb = particle_of_vertex[adjacency.neighbors[i]];
        if (pa != pb) own.emplace_back(pa, pb);
      }
    }
    thread_pairs[omp_get_thread_num()] = std::move(own);
  }
  return Concatenate(&thread_pairs);
}

// Whether a point lies behind a piece of surface: on the inner side of the
// normal at the piece's vertex nearest to it. Normals point out of their
// component's enclosed volume whatever the faces' orientation: outward[c]
// is -1 where component c's faces wind inwards. A piece of many vertices (a
// fine mesh: thousands in a cell) is searched at a stride that leaves at
// most 64, which keeps the test's cost bounded per pair and its answer that
// of a nearby vertex.
struct BehindPiece {
  const Mesh& mesh;
  const CompressedLists& vertices;  // of each surface particle
  const Eigen::Matrix3Xd* vertex_normals;
  const Components* components;
  const std::vector<double>& outward;

  bool operator()(const Eigen::Vector3d& point, int piece) const {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    const int stride = (vertices.size(piece) + 63) / 64;
    for (const int* v = vertices.begin(piece); v < vertices.end(piece); v += stride) {
      const double d = (mesh.vertices.col(*v) - point).squaredNorm();
      if (d < best) {
        best = d;
        nearest = *v;
      }
    }
    const Eigen::Vector3d normal =
        outward[components->component_of_vertex[nearest]] * vertex_normals->col(nearest);
    return (point - mesh.vertices.col(nearest)).dot(normal) < 0.0;
  }
};

// Particle adjacency pairs: `surface_pairs` (L, surface-surface) first, then
// the 26 lattice neighbours of each interior particle (a surface particle
// only when, with split cells, the interior cell lies behind it; both
// directions for a surface one).
std::vector<std::pair<int, int>> ParticlePairs(const Lattice& l, bool split_cells,
                                               const BehindPiece& behind, int threads,
                                               std::vector<std::pair<int, int>> surface_pairs) {
  const int num_surface = l.num_surface_particles();
  const int num_interior = l.num_particles() - num_surface;
  const int interior_threads = ThreadsFor(threads, 64 * static_cast<int64_t>(num_interior));
  std::vector<std::vector<std::pair<int, int>>> thread_pairs(interior_threads);
  thread_pairs[0] = std::move(surface_pairs);
#pragma omp parallel num_threads(interior_threads)
  {
    std::vector<std::pair<int, int>> own;
#pragma omp for schedule(dynamic, 64) nowait
    for (int p = num_surface; p < l.num_particles(); ++p) {
      const Eigen::Vector3i& c = l.cell_coords(p);
      for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            if (dx == 0 && dy == 0 && dz == 0) continue;
            const Eigen::Vector3i neighbour = c + Eigen::Vector3i(dx, dy, dz);
            const int first = l.ParticleAt(neighbour);
            if (first < 0) continue;
            const int count = l.NumParticlesAt(neighbour);
            for (int q = first; q < first + count; ++q) {
              if (split_cells && q < num_surface && !behind(l.rest_positions().col(p), q)) {
                continue;  // in front of this piece: another part of the surface
              }
              own.emplace_back(p, q);
              if (q < num_surface) own.emplace_back(q, p);
            }
          }
        }
      }
    }
    auto& slot = thread_pairs[omp_get_thread_num()];
    slot.insert(slot.end(), own.begin(), own.end());  // thread 0's starts with the L pairs
  }
  return Concatenate(&thread_pairs);
}

}  // namespace

bool LatticeOptions::Check(std::string* error) const {
  // The rows' ranges (LatticeOptionTable(), lattice.h), then what a row
  // cannot say.
  if (!LatticeOptionTable().CheckRanges(*this, error)) return false;
  if (cell_width == 0.0 && !(cells_per_diagonal > 0.0 && std::isfinite(cells_per_diagonal))) {
    *error = "cells_per_diagonal must be a finite number > 0 (cell_width is 0)";
    return false;
  }
  if (num_threads < 1 || num_threads > kMaxThreads) {
    *error = "num_threads must be in 1.." + std::to_string(kMaxThreads);
    return false;
  }
  return true;
}

Eigen::Vector3i Lattice::CellCoordsOf(const Eigen::Vector3d& point) const {
  return ((point - origin_).array() / cell_width_ + 0.5).floor().cast<int>();
}

long long Lattice::GridIndex(const Eigen::Vector3i& coords) const {
  const Eigen::Vector3i padded = dims_ + Eigen::Vector3i::Constant(2);
  return (coords.x() + 1) +
         static_cast<long long>(padded.x()) *
             ((coords.y() + 1) + static_cast<long long>(padded.y()) * (coords.z() + 1));
}

int Lattice::ParticleAt(const Eigen::Vector3i& coords) const {
  if ((coords.array() < -1).any() || (coords.array() > dims_.array()).any()) return -1;
  const int particle = particle_of_grid_cell_[GridIndex(coords)];
  return particle >= 0 ? particle : -1;
}

int Lattice::NumParticlesAt(const Eigen::Vector3i& coords) const {
  const int first = ParticleAt(coords);
  if (first < 0) return 0;
  int last = first;
  while (last + 1 < num_surface_particles_ && cell_coords_[last + 1] == coords) ++last;
  return last - first + 1;
}

bool Lattice::Build(const Mesh& mesh, const LatticeOptions& options, Lattice* lattice,
                    std::string* error) {
  return BuildWith(mesh, options, nullptr, nullptr, lattice, error);
}

bool Lattice::Build(const Mesh& mesh, const LatticeOptions& options,
                    const Eigen::Matrix3Xd& vertex_normals, const Components& components,
                    Lattice* lattice, std::string* error) {
  CHECK_EQ(vertex_normals.cols(), mesh.num_vertices());
  CHECK_EQ(static_cast<int>(components.component_of_vertex.size()), mesh.num_vertices());
  return BuildWith(mesh, options, &vertex_normals, &components, lattice, error);
}

Eigen::Vector3i Lattice::GridCoords(long long cell) const {
  const Eigen::Vector3i padded = dims_ + Eigen::Vector3i::Constant(2);
  const long long layer = static_cast<long long>(padded.x()) * padded.y();
  return Eigen::Vector3i(static_cast<int>(cell % padded.x()) - 1,
                         static_cast<int>((cell / padded.x()) % padded.y()) - 1,
                         static_cast<int>(cell / layer) - 1);
}

bool Lattice::SizeGrid(const Mesh& mesh, const LatticeOptions& options, long long* grid_size,
                       std::string* error) {
  const Eigen::AlignedBox3d box = BoundingBox(mesh, options.num_threads);
  const double diagonal = box.diagonal().norm();
  cell_width_ = options.cell_width > 0.0 ? options.cell_width
                                         : diagonal / options.cells_per_diagonal;
  if (!(cell_width_ > 0.0)) {
    *error = "the mesh has a zero-size bounding box; cannot build a lattice";
    return false;
  }
  origin_ = box.min();
  // Cells per axis as doubles first: a tiny width must not overflow an int.
  const Eigen::Array3d cells_per_axis = (box.sizes().array() / cell_width_ + 0.5).floor() + 3.0;
  const double grid_cells = cells_per_axis.prod();
  if (!(grid_cells <= static_cast<double>(options.max_grid_cells))) {
    std::ostringstream message;
    message << "cell width " << cell_width_ << " gives a lattice of about " << grid_cells
            << " cells, more than max_grid_cells " << options.max_grid_cells
            << "; use a larger cell width";
    *error = message.str();
    return false;
  }
  dims_ = CellCoordsOf(box.max()) + Eigen::Vector3i::Ones();
  const Eigen::Vector3i padded = dims_ + Eigen::Vector3i::Constant(2);
  *grid_size = static_cast<long long>(padded.x()) * padded.y() * padded.z();
  if (*grid_size > options.max_grid_cells) {
    std::ostringstream message;
    message << "cell width " << cell_width_ << " gives a " << dims_.transpose()
            << " lattice (" << *grid_size << " cells), more than max_grid_cells "
            << options.max_grid_cells << "; use a larger cell width";
    *error = message.str();
    return false;
  }
  return true;
}

std::vector<long long> Lattice::MarkSurfaceCells(const Mesh& mesh, long long grid_size,
                                                 int threads) {
  // Threads mark cells concurrently with atomic writes; each cell's mark is
  // the same whichever thread writes it, or in what order.
  const int num_vertices = mesh.num_vertices(), num_faces = mesh.num_faces();
  const int vertex_threads = ThreadsFor(threads, num_vertices);
  const int face_threads = ThreadsFor(threads, num_faces);
  std::vector<int>& grid = particle_of_grid_cell_;
  grid.assign(grid_size, kEmpty);
  std::vector<long long> grid_cell_of_vertex(num_vertices);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) {
    grid_cell_of_vertex[v] = GridIndex(CellCoordsOf(mesh.vertices.col(v)));
#pragma omp atomic write
    grid[grid_cell_of_vertex[v]] = kSurfaceMark;
  }
  // Triangles longer than a cell leave gaps between the vertex cells through
  // which the flood fill would leak inside; the cells they cross close them.
  // Samples at most w/3 apart along both triangle directions hit every cell
  // the triangle crosses by more than a sliver.
  const double spacing = cell_width_ / 3.0;
#pragma omp parallel for num_threads(face_threads) schedule(dynamic, 4096)
  for (int f = 0; f < num_faces; ++f) {
    const long long c0 = grid_cell_of_vertex[mesh.faces(0, f)];
    if (c0 == grid_cell_of_vertex[mesh.faces(1, f)] &&
        c0 == grid_cell_of_vertex[mesh.faces(2, f)]) {
      continue;  // A cell is convex: the triangle lies inside it.
    }
    const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f));
    const Eigen::Vector3d b = mesh.vertices.col(mesh.faces(1, f));
    const Eigen::Vector3d c = mesh.vertices.col(mesh.faces(2, f));
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int steps = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
    for (int i = 0; i <= steps; ++i) {
      for (int j = 0; i + j <= steps; ++j) {
        const Eigen::Vector3d point = a + (static_cast<double>(i) / steps) * (b - a) +
                                      (static_cast<double>(j) / steps) * (c - a);
        const Eigen::Vector3i coords = CellCoordsOf(point)
                                           .cwiseMax(Eigen::Vector3i::Zero())
                                           .cwiseMin(dims_ - Eigen::Vector3i::Ones());
        int& cell = grid[GridIndex(coords)];
        int mark;
#pragma omp atomic read
        mark = cell;
        if (mark == kEmpty) {
#pragma omp atomic write
          cell = kWallMark;
        }
      }
    }
  }
  return grid_cell_of_vertex;
}

void Lattice::FloodFillOutside() {
  std::vector<int>& grid = particle_of_grid_cell_;
  const Eigen::Vector3i padded = dims_ + Eigen::Vector3i::Constant(2);
  const long long stride[3] = {1, padded.x(), static_cast<long long>(padded.x()) * padded.y()};
  std::vector<long long> queue = {0};  // The padded corner is always outside.
  grid[0] = kOutsideMark;
  while (!queue.empty()) {
    const long long cell = queue.back();
    queue.pop_back();
    long long rest = cell;
    const int coord[3] = {static_cast<int>(rest % padded.x()),
                          static_cast<int>((rest / padded.x()) % padded.y()),
                          static_cast<int>(rest / stride[2])};
    for (int axis = 0; axis < 3; ++axis) {
      for (int step : {-1, 1}) {
        const int moved = coord[axis] + step;
        if (moved < 0 || moved >= padded[axis]) continue;
        const long long next = cell + step * stride[axis];
        if (grid[next] != kEmpty) continue;
        grid[next] = kOutsideMark;
        queue.push_back(next);
      }
    }
  }
}

std::vector<int> Lattice::NumberParticles(const std::vector<long long>& surface_grid_cells,
                                          const std::vector<int>& num_pieces) {
  std::vector<int>& grid = particle_of_grid_cell_;
  const long long grid_size = static_cast<long long>(grid.size());
  const int num_cells = static_cast<int>(surface_grid_cells.size());
  std::vector<int> first_particle(num_cells);
  for (int c = 0; c < num_cells; ++c) {
    const long long cell = surface_grid_cells[c];
    first_particle[c] = static_cast<int>(cell_coords_.size());
    grid[cell] = first_particle[c];
    for (int piece = 0; piece < num_pieces[c]; ++piece) cell_coords_.push_back(GridCoords(cell));
    num_split_cells_ += num_pieces[c] > 1;
  }
  num_surface_particles_ = static_cast<int>(cell_coords_.size());
  for (long long cell = 0; cell < grid_size; ++cell) {
    if (grid[cell] == kEmpty || grid[cell] == kWallMark) {
      grid[cell] = static_cast<int>(cell_coords_.size());
      cell_coords_.push_back(GridCoords(cell));
    } else if (grid[cell] == kOutsideMark) {
      grid[cell] = kEmpty;
    }
  }
  rest_positions_.resize(3, num_particles());
  for (int p = 0; p < num_particles(); ++p) {
    rest_positions_.col(p) = origin_ + cell_width_ * cell_coords_[p].cast<double>();
  }
  return first_particle;
}

bool Lattice::BuildWith(const Mesh& mesh, const LatticeOptions& options,
                        const Eigen::Matrix3Xd* vertex_normals, const Components* components,
                        Lattice* lattice, std::string* error) {
  CHECK(lattice != nullptr);
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  Lattice& l = *lattice;
  l = Lattice();

  const int threads = options.num_threads;
  long long grid_size = 0;
  if (!l.SizeGrid(mesh, options, &grid_size, error)) return false;

  // Mark surface cells (and the walls that the triangles crossing empty
  // cells make), then flood-fill the outside through empty cells.
  const int num_vertices = mesh.num_vertices();
  const int vertex_threads = ThreadsFor(threads, num_vertices);
  std::vector<long long> grid_cell_of_vertex = l.MarkSurfaceCells(mesh, grid_size, threads);
  l.FloodFillOutside();
  std::vector<int>& grid = l.particle_of_grid_cell_;

  auto coords_of = [&l](long long cell) { return l.GridCoords(cell); };
  // Surface cells in grid order, their vertices and their pieces.
  std::vector<long long> surface_grid_cells;
  for (long long cell = 0; cell < grid_size; ++cell) {
    if (grid[cell] == kSurfaceMark) surface_grid_cells.push_back(cell);
  }
  const int num_cells = static_cast<int>(surface_grid_cells.size());
  // Until the particles are numbered, a surface cell's grid entry is its index.
  for (int c = 0; c < num_cells; ++c) grid[surface_grid_cells[c]] = c;
  std::vector<int> cell_of_vertex(num_vertices);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) cell_of_vertex[v] = grid[grid_cell_of_vertex[v]];
  std::vector<long long>().swap(grid_cell_of_vertex);
  // The mesh's edges, for the pieces and the L lists.
  const VertexAdjacency adjacency = ComputeVertexAdjacency(mesh, threads);
  std::vector<int> piece_of_vertex(num_vertices, 0);  // within its cell
  std::vector<int> num_pieces(num_cells, 1);
  if (options.split_cells) {
    FindPieces(mesh, l, adjacency, surface_grid_cells, coords_of, cell_of_vertex,
               options.piece_margin, threads, &piece_of_vertex, &num_pieces);
  }

  // Refuse a lattice too fine for the rigidity estimate before numbering it.
  long long num_particles = 0;
  for (long long cell = 0; cell < grid_size; ++cell) num_particles += grid[cell] != kOutsideMark;
  for (int c = 0; c < num_cells; ++c) num_particles += num_pieces[c] - 1;
  if (num_particles > kMaxLatticeParticles) {
    std::ostringstream message;
    message << "the lattice has " << num_particles << " particles, more than "
            << kMaxLatticeParticles
            << "; use a larger cell width (--cell_width, or lattice.cells_per_diagonal)";
    *error = message.str();
    l = Lattice();
    return false;
  }

  // Number particles: surface pieces in grid order of their cells, then
  // interior cells.
  const std::vector<int> first_particle = l.NumberParticles(surface_grid_cells, num_pieces);

  // Vertex <-> particle maps.
  l.particle_of_vertex_.resize(num_vertices);
  std::vector<std::pair<int, int>> particle_vertex(num_vertices);
#pragma omp parallel for num_threads(vertex_threads) schedule(static)
  for (int v = 0; v < num_vertices; ++v) {
    l.particle_of_vertex_[v] = first_particle[cell_of_vertex[v]] + piece_of_vertex[v];
    particle_vertex[v] = {l.particle_of_vertex_[v], v};
  }
  l.vertices_of_particle_ = ListsFromPairs(l.num_surface_particles_, particle_vertex, threads);
  std::vector<std::pair<int, int>>().swap(particle_vertex);

  // L lists from mesh edges that join two surface particles.
  std::vector<std::pair<int, int>> surface_pairs =
      SurfaceParticlePairs(l.particle_of_vertex_, adjacency, vertex_threads);
  l.neighborhood_ = ListsFromPairs(l.num_surface_particles_, surface_pairs, threads);

  // What tells which side of a piece of surface an interior cell is on (with
  // split cells): the vertex normals, the components and which way each
  // component's faces wind.
  Eigen::Matrix3Xd own_normals;
  Components own_components;
  std::vector<double> outward;
  if (options.split_cells) {
    if (vertex_normals == nullptr) {
      own_normals = VertexNormals(mesh, threads);
      vertex_normals = &own_normals;
    }
    if (components == nullptr) {
      own_components = ConnectedComponents(mesh, threads);
      components = &own_components;
    }
    const std::vector<double> volume = ComponentVolumes(mesh, *components, threads);
    outward.resize(components->count);
    for (int c = 0; c < components->count; ++c) outward[c] = volume[c] < 0.0 ? -1.0 : 1.0;
  }
  const BehindPiece behind{mesh, l.vertices_of_particle_, vertex_normals, components, outward};

  // Particle adjacency: L for surface-surface, 26 lattice neighbours when an
  // interior particle is involved.
  const std::vector<std::pair<int, int>> particle_pairs =
      ParticlePairs(l, options.split_cells, behind, threads, std::move(surface_pairs));
  l.particle_adjacency_ = ListsFromPairs(l.num_particles(), particle_pairs, threads);
  return true;
}

const OptionTable<LatticeOptions>& LatticeOptionTable() {
  static const OptionTable<LatticeOptions>& table =
      MakeOptionTable<LatticeOptions>([](auto& t) { DeclareLatticeOptionRows(t); });
  return table;
}

}  // namespace msdeform
