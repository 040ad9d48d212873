// The lattice over a mesh (paper §3.1, Eq. 1; docs/method.md §1).
//
// Cells have width w. Vertex i lies in cell (a, b, c) with
//   a = floor((x_i - x_min + w/2) / w)   (likewise b from y, c from z),
// and cell (a, b, c) has its centre at (x_min + a w, y_min + b w, z_min + c w).
// Surface cells hold at least one vertex. Interior cells are the empty cells
// that a 6-connected flood fill from outside the padded lattice cannot reach
// (surface cells are walls), so a watertight mesh is filled solid and a mesh
// with holes simply fills less.
//
// A surface cell has one particle per piece of the surface inside it (Rivers
// and James 2007's FastLSM lattice; LatticeOptions::split_cells): two of its
// vertices are in one piece when mesh edges join them without leaving the
// cell grown by piece_margin cells on every side (vertices in no face join the
// cell's first piece). Two limbs that touch inside a cell are two particles
// there, so the L lists, DG1, the coarse graphs and the skinning candidates
// never join them. Every interior cell is one particle. A particle's rest
// position is its cell's centre (the pieces of a cell share it).
//
// Particles 0 .. num_surface_particles()-1 are the surface pieces, in grid
// order of their cells and, within a cell, by their smallest vertex id (DG1
// node i is surface particle i); the interior particles follow.
//
// The neighbourhood list L_i of surface particle i holds the surface
// particles j != i that a mesh edge joins to it: geometrically touching but
// geodesically far parts (two teeth of a comb in touching cells, two limbs
// touching in one cell) are not L-neighbours. Particle adjacency:
// surface-surface by L, interior-interior by the 26 lattice neighbours, and
// interior-surface by the 26 lattice neighbours when the interior cell lies
// behind the surface particle: on the inner side of the normal at the
// particle's vertex nearest to the cell's centre (normals taken outward by
// the sign of each component's enclosed volume), so the inside of one limb
// does not reach the surface of another that touches it. Interior cells of two
// limbs whose surfaces pass within a cell can still be diagonal neighbours,
// and a vertex-free cell that triangles of both cross is one particle.

#ifndef MSDEFORM_CORE_LATTICE_H_
#define MSDEFORM_CORE_LATTICE_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/mesh.h"
#include "msdeform/core/option_table.h"

namespace msdeform {

struct LatticeOptions {
  // Cell width w in mesh units; 0 means diag / cells_per_diagonal.
  double cell_width = 0.0;
  // Used when cell_width is 0: w = bounding-box diagonal / this (docs/method.md: 48).
  double cells_per_diagonal = 48.0;
  // Upper bound on the number of cells of the padded grid (memory guard).
  long long max_grid_cells = 1LL << 28;
  // The topology-aware lattice (true; docs/decisions/lattice.md):
  // one particle per piece of surface in a cell, and interior cells joined
  // only to the surface particles they lie behind. False: the paper's, one
  // particle per cell and the 26 lattice neighbours.
  bool split_cells = true;
  // Pieces are found within the cell grown by this many cell widths on each
  // side, so that a surface crossing a cell corner is not cut in two by the
  // cell's walls (0.5: a box two cells wide). In [0, 2].
  double piece_margin = 0.5;
  // OpenMP threads for the build, 1..kMaxThreads (nearest_nodes.h). The
  // lattice is the same for every count.
  int num_threads = 1;

  bool Check(std::string* error) const;
};

// The most particles a lattice may have. The harmonic rigidity estimate
// factorises a Laplacian over the particles with Eigen's SimplicialLDLT, whose
// 32-bit indices overflow when the factor passes INT_MAX nonzeros: on the
// cactus the factor (AMD ordering) has 0.23 x INT_MAX nonzeros at 374K
// particles, 0.53 x at 638K and 1.05 x at 1.0M (it grows as particles^1.55),
// and 1.58M particles (the cactus at cell width 0.003) crashed. 500K keeps a
// margin of more than 2 for shapes that fill worse; the default lattices (48
// cells per diagonal) of every mesh have at most about 25K particles, whatever
// the vertex count.
constexpr int kMaxLatticeParticles = 500000;

// A compressed list of lists: the entries of row r are
// values[offsets[r] .. offsets[r + 1]). Offsets are 64-bit: the particle
// adjacency of a grid of max_grid_cells = 2^28 cells (26 neighbours each)
// passes INT_MAX entries in all, though every row is short.
struct CompressedLists {
  std::vector<int64_t> offsets{0};
  std::vector<int> values;

  int num_rows() const { return static_cast<int>(offsets.size()) - 1; }
  int size(int row) const { return static_cast<int>(offsets[row + 1] - offsets[row]); }
  const int* begin(int row) const { return values.data() + offsets[row]; }
  const int* end(int row) const { return values.data() + offsets[row + 1]; }
};

class Lattice {
 public:
  // Builds the lattice of `mesh` (which must pass ValidateMesh). Returns false
  // with a message when the options are invalid or the grid would be too big.
  static bool Build(const Mesh& mesh, const LatticeOptions& options,
                    Lattice* lattice, std::string* error);
  // The same with the mesh's VertexNormals and ConnectedComponents given, for
  // a caller that has them already (the split_cells test reads them); the
  // same lattice.
  static bool Build(const Mesh& mesh, const LatticeOptions& options,
                    const Eigen::Matrix3Xd& vertex_normals, const Components& components,
                    Lattice* lattice, std::string* error);

  double cell_width() const { return cell_width_; }
  const Eigen::Vector3d& origin() const { return origin_; }  // (x_min, y_min, z_min)
  // Cells per axis, of the unpadded lattice: indices 0 .. dims - 1.
  const Eigen::Vector3i& dims() const { return dims_; }

  int num_surface_particles() const { return num_surface_particles_; }
  int num_interior_particles() const { return num_particles() - num_surface_particles_; }
  int num_particles() const { return static_cast<int>(cell_coords_.size()); }
  // Surface cells holding more than one particle (pieces of surface).
  int num_split_cells() const { return num_split_cells_; }

  // Integer cell coordinates (a, b, c) of particle p.
  const Eigen::Vector3i& cell_coords(int p) const { return cell_coords_[p]; }
  // Rest positions of all particles (cell centres). 3 by #particles.
  const Eigen::Matrix3Xd& rest_positions() const { return rest_positions_; }

  // The surface particle (piece of a surface cell) holding vertex v. O(1).
  int particle_of_vertex(int v) const { return particle_of_vertex_[v]; }
  const std::vector<int>& particle_of_vertex() const { return particle_of_vertex_; }
  // Vertices of each surface particle, in increasing id order.
  const CompressedLists& vertices_of_particle() const { return vertices_of_particle_; }
  // L lists of the surface particles (sorted, without the particle itself).
  const CompressedLists& neighborhood() const { return neighborhood_; }
  // Particle adjacency as above (sorted, without the particle itself).
  const CompressedLists& particle_adjacency() const { return particle_adjacency_; }

  // Eq. 1 for an arbitrary point.
  Eigen::Vector3i CellCoordsOf(const Eigen::Vector3d& point) const;
  // The first particle of the cell with the given coordinates, or -1 if that
  // cell is neither surface nor interior (or outside the lattice). The
  // cell's other pieces, if any, are the next NumParticlesAt(coords) - 1.
  int ParticleAt(const Eigen::Vector3i& coords) const;
  // Particles of the cell: 0 (none), 1, or its number of surface pieces.
  int NumParticlesAt(const Eigen::Vector3i& coords) const;

 private:
  // Build's body; the normals and components are computed when null.
  static bool BuildWith(const Mesh& mesh, const LatticeOptions& options,
                        const Eigen::Matrix3Xd* vertex_normals, const Components* components,
                        Lattice* lattice, std::string* error);
  long long GridIndex(const Eigen::Vector3i& coords) const;  // padded grid
  Eigen::Vector3i GridCoords(long long grid_index) const;     // its inverse
  // BuildWith's steps, in order. The cell width, origin and dims, and the
  // padded grid's size; false with a message when the grid is too big.
  bool SizeGrid(const Mesh& mesh, const LatticeOptions& options, long long* grid_size,
                std::string* error);
  // Marks the vertices' cells and, as walls, the empty cells that the
  // triangles cross; returns each vertex's grid index.
  std::vector<long long> MarkSurfaceCells(const Mesh& mesh, long long grid_size, int threads);
  // Marks outside the empty cells reachable from the padded corner.
  void FloodFillOutside();
  // Numbers the particles: the pieces of each surface cell (in grid order),
  // then the interior cells; returns each surface cell's first particle.
  std::vector<int> NumberParticles(const std::vector<long long>& surface_grid_cells,
                                   const std::vector<int>& num_pieces);

  double cell_width_ = 0.0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  int num_surface_particles_ = 0;
  int num_split_cells_ = 0;
  std::vector<Eigen::Vector3i> cell_coords_;
  Eigen::Matrix3Xd rest_positions_;
  std::vector<int> particle_of_vertex_;
  CompressedLists vertices_of_particle_;
  CompressedLists neighborhood_;
  CompressedLists particle_adjacency_;
  std::vector<int> particle_of_grid_cell_;  // padded grid: first particle, -1 for empty/outside.
};

// LatticeOptions' rows (core/option_table.h), declared in its header beside the fields: a new field
// is the field above and its row here. LatticeOptionTable() (lattice.cc) builds the table from them
// once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareLatticeOptionRows(Table& t) {
  using L = LatticeOptions;
  t.Double("cell_width", &L::cell_width,
           "Lattice cell width in mesh units (0: bounding-box diagonal / 48).")
      .AtLeast(0, "a length >= 0 in mesh units (0: diagonal / 48)");
  t.Double("cells_per_diagonal", &L::cells_per_diagonal,
           "Used when cell_width is 0: w = bounding-box diagonal / this.");
  t.Int("max_grid_cells", &L::max_grid_cells,
        "Upper bound on the cells of the padded grid (memory guard).")
      .AtLeast(1, "an integer >= 1");
  t.Bool("split_cells", &L::split_cells,
         "One lattice particle per piece of surface in a cell, interior cells joined only to "
         "surfaces they lie behind: touching parts stay apart (the paper: one particle per "
         "cell, 26 neighbours).");
  t.Double("piece_margin", &L::piece_margin,
           "Pieces of surface in a lattice cell are found within the cell grown by this many "
           "cell widths on each side (split_cells).")
      .Range(0, 2, "a number of cell widths in [0, 2]");
}
const OptionTable<LatticeOptions>& LatticeOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_CORE_LATTICE_H_
