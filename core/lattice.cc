#include "msdeform/core/lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <glog/logging.h>

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
CompressedLists ListsFromPairs(int num_rows, const std::vector<std::pair<int, int>>& pairs) {
  CompressedLists lists;
  lists.offsets.assign(num_rows + 1, 0);
  for (const auto& [row, value] : pairs) ++lists.offsets[row + 1];
  for (int r = 0; r < num_rows; ++r) lists.offsets[r + 1] += lists.offsets[r];
  std::vector<int>& values = lists.values;
  values.resize(pairs.size());
  {
    std::vector<int64_t> fill(lists.offsets.begin(), lists.offsets.end() - 1);
    for (const auto& [row, value] : pairs) values[fill[row]++] = value;
  }
  // Sort each row and drop its repeats, moving the rows down over the gaps:
  // row r's old bounds are read before offsets[r] is rewritten.
  int64_t kept = 0;
  for (int r = 0; r < num_rows; ++r) {
    const int64_t begin = lists.offsets[r], end = lists.offsets[r + 1];
    std::sort(values.begin() + begin, values.begin() + end);
    lists.offsets[r] = kept;
    for (int64_t i = begin; i < end; ++i) {
      if (i == begin || values[i] != values[i - 1]) values[kept++] = values[i];
    }
  }
  lists.offsets[num_rows] = kept;
  values.resize(kept);
  return lists;
}

// The pieces of each surface cell (lattice.h): vertex v of cell c gets the
// index, among the pieces of c, of the piece holding it, pieces numbered by
// their smallest vertex; vertices in no face join the cell's first piece.
// Mesh edges join a piece's vertices first within the
// cell itself; only a cell that this leaves in several pieces is searched
// again within the cell grown by `margin` cells on each side, which merges
// the parts of one sheet that the cell's walls cut apart.
template <typename CoordsOf>
void FindPieces(const Mesh& mesh, const Lattice& lattice,
                const std::vector<long long>& surface_grid_cells, const CoordsOf& coords_of,
                const std::vector<int>& cell_of_vertex, double margin,
                std::vector<int>* piece_of_vertex, std::vector<int>* num_pieces) {
  const int num_cells = static_cast<int>(surface_grid_cells.size());
  const VertexAdjacency adjacency = ComputeVertexAdjacency(mesh);
  std::vector<std::pair<int, int>> cell_vertex;
  cell_vertex.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) cell_vertex.emplace_back(cell_of_vertex[v], v);
  const CompressedLists vertices_of_cell = ListsFromPairs(num_cells, cell_vertex);
  // stamp[v] = the last search that reached v: 2 c (cell only) or 2 c + 1 (grown).
  std::vector<int64_t> stamp(mesh.num_vertices(), -1);
  std::vector<int> queue;
  const double w = lattice.cell_width();
  auto label = [&](int c, int64_t search, double half_width) {
    const Eigen::Vector3d centre =
        lattice.origin() + w * coords_of(surface_grid_cells[c]).template cast<double>();
    int pieces = 0;
    bool isolated = false;  // a vertex in no face: no piece of surface of its own
    for (const int* start = vertices_of_cell.begin(c); start != vertices_of_cell.end(c); ++start) {
      if (adjacency.offsets[*start] == adjacency.offsets[*start + 1]) {
        isolated = true;
        continue;
      }
      if (stamp[*start] == search) continue;
      stamp[*start] = search;
      queue.assign(1, *start);
      while (!queue.empty()) {
        const int u = queue.back();
        queue.pop_back();
        if (cell_of_vertex[u] == c) (*piece_of_vertex)[u] = pieces;
        for (int i = adjacency.offsets[u]; i < adjacency.offsets[u + 1]; ++i) {
          const int next = adjacency.neighbors[i];
          if (stamp[next] == search) continue;
          const bool inside =
              half_width == 0.0
                  ? cell_of_vertex[next] == c
                  : ((mesh.vertices.col(next) - centre).cwiseAbs().array() <= half_width).all();
          if (!inside) continue;
          stamp[next] = search;
          queue.push_back(next);
        }
      }
      ++pieces;
    }
    if (isolated) {  // into the cell's first piece
      for (const int* v = vertices_of_cell.begin(c); v != vertices_of_cell.end(c); ++v) {
        if (adjacency.offsets[*v] == adjacency.offsets[*v + 1]) (*piece_of_vertex)[*v] = 0;
      }
      pieces = std::max(pieces, 1);
    }
    return pieces;
  };
  for (int c = 0; c < num_cells; ++c) {
    (*num_pieces)[c] = label(c, 2 * static_cast<int64_t>(c), 0.0);
    if ((*num_pieces)[c] > 1 && margin > 0.0) {
      (*num_pieces)[c] = label(c, 2 * static_cast<int64_t>(c) + 1, (0.5 + margin) * w);
    }
  }
}

}  // namespace

bool LatticeOptions::Check(std::string* error) const {
  if (!(cell_width >= 0.0) || !std::isfinite(cell_width)) {
    *error = "cell_width must be a finite number >= 0 (0: diag / cells_per_diagonal)";
    return false;
  }
  if (cell_width == 0.0 && !(cells_per_diagonal > 0.0 && std::isfinite(cells_per_diagonal))) {
    *error = "cells_per_diagonal must be a finite number > 0";
    return false;
  }
  if (max_grid_cells <= 0) {
    *error = "max_grid_cells must be > 0";
    return false;
  }
  if (!(piece_margin >= 0.0 && piece_margin <= 2.0)) {
    *error = "piece_margin must be in [0, 2] (cell widths)";
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

bool Lattice::BuildWith(const Mesh& mesh, const LatticeOptions& options,
                        const Eigen::Matrix3Xd* vertex_normals, const Components* components,
                        Lattice* lattice, std::string* error) {
  CHECK(lattice != nullptr);
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  Lattice& l = *lattice;
  l = Lattice();

  const Eigen::AlignedBox3d box = BoundingBox(mesh);
  const double diagonal = box.diagonal().norm();
  l.cell_width_ = options.cell_width > 0.0 ? options.cell_width
                                           : diagonal / options.cells_per_diagonal;
  if (!(l.cell_width_ > 0.0)) {
    *error = "the mesh has a zero-size bounding box; cannot build a lattice";
    return false;
  }
  l.origin_ = box.min();
  // Cells per axis as doubles first: a tiny width must not overflow an int.
  const Eigen::Array3d cells_per_axis = (box.sizes().array() / l.cell_width_ + 0.5).floor() + 3.0;
  const double grid_cells = cells_per_axis.prod();
  if (!(grid_cells <= static_cast<double>(options.max_grid_cells))) {
    std::ostringstream message;
    message << "cell width " << l.cell_width_ << " gives a lattice of about " << grid_cells
            << " cells, more than max_grid_cells " << options.max_grid_cells
            << "; use a larger cell width";
    *error = message.str();
    return false;
  }
  l.dims_ = l.CellCoordsOf(box.max()) + Eigen::Vector3i::Ones();
  const Eigen::Vector3i padded = l.dims_ + Eigen::Vector3i::Constant(2);
  const long long grid_size = static_cast<long long>(padded.x()) * padded.y() * padded.z();
  if (grid_size > options.max_grid_cells) {
    std::ostringstream message;
    message << "cell width " << l.cell_width_ << " gives a " << l.dims_.transpose()
            << " lattice (" << grid_size << " cells), more than max_grid_cells "
            << options.max_grid_cells << "; use a larger cell width";
    *error = message.str();
    return false;
  }

  // Mark surface cells, then flood-fill the outside through empty cells.
  std::vector<int>& grid = l.particle_of_grid_cell_;
  grid.assign(grid_size, kEmpty);
  std::vector<long long> grid_cell_of_vertex(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    grid_cell_of_vertex[v] = l.GridIndex(l.CellCoordsOf(mesh.vertices.col(v)));
    grid[grid_cell_of_vertex[v]] = kSurfaceMark;
  }
  // Triangles longer than a cell leave gaps between the vertex cells through
  // which the flood fill would leak inside; the cells they cross close them.
  // Samples at most w/3 apart along both triangle directions hit every cell
  // the triangle crosses by more than a sliver.
  const double spacing = l.cell_width_ / 3.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
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
        const Eigen::Vector3i coords = l.CellCoordsOf(point)
                                           .cwiseMax(Eigen::Vector3i::Zero())
                                           .cwiseMin(l.dims_ - Eigen::Vector3i::Ones());
        int& cell = grid[l.GridIndex(coords)];
        if (cell == kEmpty) cell = kWallMark;
      }
    }
  }
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

  auto coords_of = [&](long long cell) {
    return Eigen::Vector3i(static_cast<int>(cell % padded.x()) - 1,
                           static_cast<int>((cell / padded.x()) % padded.y()) - 1,
                           static_cast<int>(cell / stride[2]) - 1);
  };
  // Surface cells in grid order, their vertices and their pieces.
  std::vector<long long> surface_grid_cells;
  for (long long cell = 0; cell < grid_size; ++cell) {
    if (grid[cell] == kSurfaceMark) surface_grid_cells.push_back(cell);
  }
  const int num_cells = static_cast<int>(surface_grid_cells.size());
  // Until the particles are numbered, a surface cell's grid entry is its index.
  for (int c = 0; c < num_cells; ++c) grid[surface_grid_cells[c]] = c;
  std::vector<int> cell_of_vertex(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) cell_of_vertex[v] = grid[grid_cell_of_vertex[v]];
  std::vector<int> piece_of_vertex(mesh.num_vertices(), 0);  // within its cell
  std::vector<int> num_pieces(num_cells, 1);
  if (options.split_cells) {
    FindPieces(mesh, l, surface_grid_cells, coords_of, cell_of_vertex, options.piece_margin,
               &piece_of_vertex, &num_pieces);
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
  std::vector<int> first_particle(num_cells);
  for (int c = 0; c < num_cells; ++c) {
    const long long cell = surface_grid_cells[c];
    first_particle[c] = static_cast<int>(l.cell_coords_.size());
    grid[cell] = first_particle[c];
    for (int piece = 0; piece < num_pieces[c]; ++piece) l.cell_coords_.push_back(coords_of(cell));
    l.num_split_cells_ += num_pieces[c] > 1;
  }
  l.num_surface_particles_ = static_cast<int>(l.cell_coords_.size());
  for (long long cell = 0; cell < grid_size; ++cell) {
    if (grid[cell] == kEmpty || grid[cell] == kWallMark) {
      grid[cell] = static_cast<int>(l.cell_coords_.size());
      l.cell_coords_.push_back(coords_of(cell));
    } else if (grid[cell] == kOutsideMark) {
      grid[cell] = kEmpty;
    }
  }
  l.rest_positions_.resize(3, l.num_particles());
  for (int p = 0; p < l.num_particles(); ++p) {
    l.rest_positions_.col(p) = l.origin_ + l.cell_width_ * l.cell_coords_[p].cast<double>();
  }

  // Vertex <-> particle maps.
  l.particle_of_vertex_.resize(mesh.num_vertices());
  std::vector<std::pair<int, int>> particle_vertex;
  particle_vertex.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    l.particle_of_vertex_[v] = first_particle[cell_of_vertex[v]] + piece_of_vertex[v];
    particle_vertex.emplace_back(l.particle_of_vertex_[v], v);
  }
  l.vertices_of_particle_ = ListsFromPairs(l.num_surface_particles_, particle_vertex);

  // L lists from mesh edges that join two surface particles.
  std::vector<std::pair<int, int>> surface_pairs;
  for (const auto& [a, b] : UniqueEdges(mesh)) {
    const int pa = l.particle_of_vertex_[a], pb = l.particle_of_vertex_[b];
    if (pa == pb) continue;
    surface_pairs.emplace_back(pa, pb);
    surface_pairs.emplace_back(pb, pa);
  }
  l.neighborhood_ = ListsFromPairs(l.num_surface_particles_, surface_pairs);

  // Whether a point lies behind a piece of surface: on the inner side of
  // the normal at the piece's vertex nearest to it. Normals point out of
  // their component's enclosed volume whatever the faces' orientation.
  // outward[c] is -1 where component c's faces wind inwards.
  Eigen::Matrix3Xd own_normals;
  Components own_components;
  std::vector<double> outward;
  if (options.split_cells) {
    if (vertex_normals == nullptr) {
      own_normals = VertexNormals(mesh);
      vertex_normals = &own_normals;
    }
    if (components == nullptr) {
      own_components = ConnectedComponents(mesh);
      components = &own_components;
    }
    std::vector<double> volume(components->count, 0.0);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Eigen::Vector3d a = mesh.vertices.col(mesh.faces(0, f));
      const Eigen::Vector3d b = mesh.vertices.col(mesh.faces(1, f));
      const Eigen::Vector3d c = mesh.vertices.col(mesh.faces(2, f));
      volume[components->component_of_vertex[mesh.faces(0, f)]] += a.dot(b.cross(c));
    }
    outward.resize(components->count);
    for (int c = 0; c < components->count; ++c) outward[c] = volume[c] < 0.0 ? -1.0 : 1.0;
  }
  // A piece of many vertices (a fine mesh: thousands in a cell) is searched
  // at a stride that leaves at most 64, which keeps the test's cost bounded
  // per pair and its answer that of a nearby vertex.
  auto behind = [&](const Eigen::Vector3d& point, int piece) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    const CompressedLists& vertices = l.vertices_of_particle_;
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
  };

  // Particle adjacency: L for surface-surface, 26 lattice neighbours when an
  // interior particle is involved (a surface particle only when the interior
  // cell lies behind it).
  std::vector<std::pair<int, int>> particle_pairs = std::move(surface_pairs);
  for (int p = l.num_surface_particles_; p < l.num_particles(); ++p) {
    const Eigen::Vector3i& c = l.cell_coords_[p];
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const Eigen::Vector3i neighbour = c + Eigen::Vector3i(dx, dy, dz);
          const int first = l.ParticleAt(neighbour);
          if (first < 0) continue;
          const int count = l.NumParticlesAt(neighbour);
          for (int q = first; q < first + count; ++q) {
            if (options.split_cells && q < l.num_surface_particles_ &&
                !behind(l.rest_positions_.col(p), q)) {
              continue;  // in front of this piece: another part of the surface
            }
            particle_pairs.emplace_back(p, q);
            if (q < l.num_surface_particles_) particle_pairs.emplace_back(q, p);
          }
        }
      }
    }
  }
  l.particle_adjacency_ = ListsFromPairs(l.num_particles(), particle_pairs);
  return true;
}

}  // namespace msdeform
