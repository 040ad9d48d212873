#include "msdeform/core/lattice.h"

#include <climits>
#include <cstdint>
#include <set>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "tests/core/lattice_test_util.h"

namespace msdeform {
namespace {

// A padded grid of max_grid_cells = 2^28 cells has up to 26 neighbours per
// particle: lists of more than INT_MAX entries. Their offsets hold such
// totals (the rows stay small); with int offsets they wrapped negative.
TEST(LatticeTest, CompressedListsOffsetsPassIntMax) {
  const int64_t big = int64_t{26} << 28;  // 26 neighbours of 2^28 particles
  ASSERT_GT(big, INT_MAX);
  CompressedLists lists;
  lists.offsets.push_back(big - 4);
  lists.offsets.push_back(big + 3);
  EXPECT_EQ(lists.num_rows(), 2);
  EXPECT_EQ(lists.offsets.back(), big + 3);
  EXPECT_EQ(lists.size(1), 7);
}

TEST(LatticeTest, Eq1CoordinatesOnHandCheckedPoints) {
  // One triangle spanning x in [1, 3.2], y in [-1, 0], z = 5; w = 1.
  Mesh mesh;
  mesh.vertices.resize(3, 3);
  mesh.vertices << 1.0, 3.2, 1.49,  //
      -1.0, 0.0, -0.49,             //
      5.0, 5.0, 5.0;
  mesh.faces.resize(3, 1);
  mesh.faces << 0, 1, 2;
  const Lattice lattice = BuildTestLattice(mesh, 1.0);
  // a = floor((x - 1 + 0.5) / 1): x = 1 -> 0, 3.2 -> 2, 1.49 -> 0.
  // b = floor((y + 1 + 0.5) / 1): y = -1 -> 0, 0 -> 1, -0.49 -> 1.
  EXPECT_EQ(lattice.cell_coords(lattice.particle_of_vertex(0)), Eigen::Vector3i(0, 0, 0));
  EXPECT_EQ(lattice.cell_coords(lattice.particle_of_vertex(1)), Eigen::Vector3i(2, 1, 0));
  EXPECT_EQ(lattice.cell_coords(lattice.particle_of_vertex(2)), Eigen::Vector3i(0, 1, 0));
  EXPECT_EQ(lattice.CellCoordsOf(Eigen::Vector3d(1.51, -0.51, 5.0)), Eigen::Vector3i(1, 0, 0));
  EXPECT_EQ(lattice.dims(), Eigen::Vector3i(3, 2, 1));
  // Cell centre of (2, 1, 0) is (x_min + 2w, y_min + w, z_min).
  EXPECT_TRUE(lattice.rest_positions()
                  .col(lattice.particle_of_vertex(1))
                  .isApprox(Eigen::Vector3d(3.0, 0.0, 5.0)));
  EXPECT_EQ(lattice.num_surface_particles(), 3);
  // A flat triangle has no inside, but the two vertex-free cells it crosses
  // between its vertices' cells are walls of the flood fill and so particles.
  EXPECT_EQ(lattice.num_interior_particles(), 2);
}

TEST(LatticeTest, DefaultCellWidthIsDiagonalOver48) {
  const Mesh bar = MakeBar(8);
  LatticeOptions options;
  Lattice lattice;
  std::string error;
  ASSERT_TRUE(Lattice::Build(bar, options, &lattice, &error)) << error;
  EXPECT_DOUBLE_EQ(lattice.cell_width(), BoundingBoxDiagonal(bar) / 48.0);
}

TEST(LatticeTest, ClosedBarIsFilledSolid) {
  // A 12 x 3 x 3 bar (voxels of 3) with w = 0.5: every lattice cell whose
  // centre is strictly inside the bar is either surface or interior.
  const Mesh bar = MakeBar(4, 3.0, 6);
  const Lattice lattice = BuildTestLattice(bar, 0.5);
  EXPECT_GT(lattice.num_interior_particles(), 0);
  int inside_centres = 0;
  for (int a = 0; a < lattice.dims().x(); ++a)
    for (int b = 0; b < lattice.dims().y(); ++b)
      for (int c = 0; c < lattice.dims().z(); ++c) {
        const Eigen::Vector3d centre =
            lattice.origin() + 0.5 * Eigen::Vector3d(a, b, c);
        if ((centre.array() > 0.0).all() && centre.x() < 12.0 && centre.y() < 3.0 &&
            centre.z() < 3.0) {
          ++inside_centres;
          EXPECT_GE(lattice.ParticleAt({a, b, c}), 0) << a << " " << b << " " << c;
        }
      }
  EXPECT_EQ(lattice.num_particles(), (12 * 2 + 1) * (3 * 2 + 1) * (3 * 2 + 1));
  // The bar's sides sit on cell centres, so the strictly inside centres are
  // exactly the interior cells.
  EXPECT_EQ(inside_centres, lattice.num_interior_particles());
}

TEST(LatticeTest, EdgesLongerThanACellStillCloseTheSurface) {
  // MakeBar(12) has edges of 0.5 and a default cell width of about 0.26: the
  // vertex cells alone leave gaps, and the flood fill used to leak through
  // them and leave the bar hollow. The triangles' cells close them.
  const Mesh bar = MakeBar(12);
  Lattice lattice;
  std::string error;
  ASSERT_TRUE(Lattice::Build(bar, LatticeOptions(), &lattice, &error)) << error;
  EXPECT_GT(lattice.num_interior_particles(), 0);

  // Coarse triangles (one quad per voxel face), much finer cells: every cell
  // whose centre is inside the bar by more than a cell is a particle.
  const Mesh coarse = MakeBar(6, 1.0, 1);
  const double w = 0.1;
  const Lattice fine = BuildTestLattice(coarse, w);
  int inside = 0;
  for (int a = 0; a < fine.dims().x(); ++a)
    for (int b = 0; b < fine.dims().y(); ++b)
      for (int c = 0; c < fine.dims().z(); ++c) {
        const Eigen::Vector3d centre = fine.origin() + w * Eigen::Vector3d(a, b, c);
        if ((centre.array() > w).all() && centre.x() < 6.0 - w && centre.y() < 1.0 - w &&
            centre.z() < 1.0 - w) {
          ++inside;
          EXPECT_GE(fine.ParticleAt({a, b, c}), 0) << a << " " << b << " " << c;
        }
      }
  EXPECT_GT(inside, 0);
  EXPECT_GE(fine.num_interior_particles(), inside);
}

TEST(LatticeTest, FlatMeshAndSingleTriangleBuild) {
  Mesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0, 1, 0,  //
      0, 0, 1,                   //
      0, 0, 0;
  triangle.faces.resize(3, 1);
  triangle.faces << 0, 1, 2;
  Lattice lattice;
  std::string error;
  ASSERT_TRUE(Lattice::Build(triangle, LatticeOptions(), &lattice, &error)) << error;
  EXPECT_EQ(lattice.num_surface_particles(), 3);
  EXPECT_EQ(lattice.dims().z(), 1);
  // The cells the triangle crosses join the particles; every particle is
  // connected to another one.
  EXPECT_GT(lattice.num_interior_particles(), 0);
  EXPECT_TRUE(lattice.rest_positions().allFinite());
  for (int p = 0; p < lattice.num_particles(); ++p) {
    EXPECT_GT(lattice.particle_adjacency().size(p), 0) << p;
  }
}

TEST(LatticeTest, AbsurdlyFineCellWidthIsAnErrorNotAnOverflow) {
  LatticeOptions options;
  options.cell_width = 1e-15;
  Lattice lattice;
  std::string error;
  EXPECT_FALSE(Lattice::Build(MakeBar(4), options, &lattice, &error));
  EXPECT_NE(error.find("max_grid_cells"), std::string::npos) << error;
}

TEST(LatticeTest, OpenTubeIsNotFilled) {
  const Mesh tube = MakeOpenTube(1.0, 4.0, 64, 32);
  const Lattice lattice = BuildTestLattice(tube, 0.25);
  EXPECT_EQ(lattice.num_interior_particles(), 0);
  EXPECT_GT(lattice.num_surface_particles(), 0);
}

TEST(LatticeTest, EveryVertexIsInItsSurfaceCell) {
  const Mesh sphere = MakeSphere(1.0, 40, 20);
  const Lattice lattice = BuildTestLattice(sphere, 0.2);
  int listed = 0;
  for (int cell = 0; cell < lattice.num_surface_particles(); ++cell) {
    ASSERT_GT(lattice.vertices_of_particle().size(cell), 0);
    for (const int* v = lattice.vertices_of_particle().begin(cell);
         v != lattice.vertices_of_particle().end(cell); ++v) {
      EXPECT_EQ(lattice.particle_of_vertex(*v), cell);
      EXPECT_EQ(lattice.CellCoordsOf(sphere.vertices.col(*v)), lattice.cell_coords(cell));
      ++listed;
    }
  }
  EXPECT_EQ(listed, sphere.num_vertices());
}

TEST(LatticeTest, CombTeethInTouchingCellsAreNotNeighbours) {
  // Teeth 1 wide with 1-wide gaps; cells of 0.6 put the facing sides of
  // neighbouring teeth into touching cells.
  const Mesh comb = MakeComb(3, 6, 1.0, 5);
  const Lattice lattice = BuildTestLattice(comb, 0.6);
  std::vector<std::set<int>> cells_of_tooth(3);
  for (int t = 0; t < 3; ++t)
    for (int v : CombToothVertices(comb, t)) {
      if (comb.vertices(1, v) > 2.5) cells_of_tooth[t].insert(lattice.particle_of_vertex(v));
    }
  int touching_pairs = 0;
  for (int t = 0; t + 1 < 3; ++t) {
    for (int a : cells_of_tooth[t]) {
      ASSERT_EQ(cells_of_tooth[t + 1].count(a), 0u) << "teeth share a cell";
      for (int b : cells_of_tooth[t + 1]) {
        const Eigen::Vector3i gap = lattice.cell_coords(a) - lattice.cell_coords(b);
        if (gap.cwiseAbs().maxCoeff() == 1) {
          ++touching_pairs;
          const auto& l = lattice.neighborhood();
          EXPECT_EQ(std::find(l.begin(a), l.end(a), b), l.end(a));
        }
      }
    }
  }
  EXPECT_GT(touching_pairs, 0) << "the test geometry should put teeth in touching cells";
}

// Whether, in the particle adjacency restricted to particles whose cell
// centre lies at least `min_y` high, a particle holding a vertex of prong 0
// of the fork reaches one holding a vertex of prong 1.
bool ProngsJoinAbove(const Mesh& fork, const Lattice& lattice, double min_y) {
  std::vector<int> prong_of(lattice.num_particles(), -1);
  for (int prong = 0; prong < 2; ++prong) {
    for (int v : ForkProngVertices(fork, prong)) prong_of[lattice.particle_of_vertex(v)] = prong;
  }
  auto high = [&](int p) { return lattice.rest_positions()(1, p) >= min_y; };
  std::vector<char> seen(lattice.num_particles(), 0);
  std::vector<int> stack;
  for (int p = 0; p < lattice.num_particles(); ++p) {
    if (prong_of[p] == 0 && high(p)) {
      seen[p] = 1;
      stack.push_back(p);
    }
  }
  const CompressedLists& adjacency = lattice.particle_adjacency();
  while (!stack.empty()) {
    const int p = stack.back();
    stack.pop_back();
    if (prong_of[p] == 1) return true;
    for (const int* q = adjacency.begin(p); q != adjacency.end(p); ++q) {
      if (!seen[*q] && high(*q)) {
        seen[*q] = 1;
        stack.push_back(*q);
      }
    }
  }
  return false;
}

TEST(LatticeTest, TouchingProngsAreSeparatePartsOfTheLattice) {
  // The fork's prongs pass 0.1 apart over their first 3 units; cells of
  // width 1 hold both. Above the base's reach (a cell grown by half a cell
  // on each side, centres 2 above the base), each piece of surface is one
  // prong's, and no chain of adjacent particles there joins the prongs.
  const Mesh fork = MakeFork(0.1);
  const double above_base = kForkBaseHeight + 2.0;
  LatticeOptions options;
  options.cell_width = 1.0;
  options.split_cells = false;
  Lattice per_cell;
  std::string error;
  ASSERT_TRUE(Lattice::Build(fork, options, &per_cell, &error)) << error;
  EXPECT_EQ(per_cell.num_split_cells(), 0);
  EXPECT_TRUE(ProngsJoinAbove(fork, per_cell, above_base)) << "the prongs should share cells";

  const Lattice lattice = BuildTestLattice(fork, 1.0);
  EXPECT_GT(lattice.num_split_cells(), 0);
  EXPECT_EQ(lattice.num_surface_particles(),
            per_cell.num_surface_particles() + lattice.num_split_cells());
  std::vector<int> prong_of(lattice.num_surface_particles(), -1);
  for (int prong = 0; prong < 2; ++prong) {
    for (int v : ForkProngVertices(fork, prong)) {
      const int p = lattice.particle_of_vertex(v);
      if (lattice.rest_positions()(1, p) < above_base) continue;
      EXPECT_NE(prong_of[p], 1 - prong) << "particle " << p << " holds both prongs";
      prong_of[p] = prong;
    }
  }
  EXPECT_FALSE(ProngsJoinAbove(fork, lattice, above_base));
  // The pieces of a split cell share its centre and are consecutive.
  for (int p = 0; p < lattice.num_surface_particles(); ++p) {
    const Eigen::Vector3i& coords = lattice.cell_coords(p);
    const int first = lattice.ParticleAt(coords);
    EXPECT_LE(first, p);
    EXPECT_LT(p, first + lattice.NumParticlesAt(coords));
  }
}

TEST(LatticeTest, OneSheetIsOnePiecePerCellWithTheMargin) {
  // A sphere has no touching parts: every cell holds one piece of it. Cut at
  // the cell walls alone (margin 0), the sheet falls apart where it crosses a
  // cell's corner; grown by half a cell it does not.
  const Mesh sphere = MakeSphere(1.0, 40, 20);
  LatticeOptions options;
  options.cell_width = 0.1;
  options.piece_margin = 0.0;
  Lattice cut;
  std::string error;
  ASSERT_TRUE(Lattice::Build(sphere, options, &cut, &error)) << error;
  EXPECT_GT(cut.num_split_cells(), 0);
  options.piece_margin = 0.5;
  Lattice grown;
  ASSERT_TRUE(Lattice::Build(sphere, options, &grown, &error)) << error;
  EXPECT_EQ(grown.num_split_cells(), 0);
  options.piece_margin = 2.5;
  EXPECT_FALSE(Lattice::Build(sphere, options, &grown, &error));
  EXPECT_NE(error.find("piece_margin"), std::string::npos) << error;
}

TEST(LatticeTest, InsideAndOutsideDoNotDependOnFaceOrientation) {
  // The fork with every face flipped: the same particles and adjacency.
  const Mesh fork = MakeFork(0.1);
  Mesh flipped = fork;
  flipped.faces.row(1).swap(flipped.faces.row(2));
  const Lattice lattice = BuildTestLattice(fork, 1.0);
  const Lattice from_flipped = BuildTestLattice(flipped, 1.0);
  EXPECT_EQ(from_flipped.particle_of_vertex(), lattice.particle_of_vertex());
  EXPECT_EQ(from_flipped.particle_adjacency().offsets, lattice.particle_adjacency().offsets);
  EXPECT_EQ(from_flipped.particle_adjacency().values, lattice.particle_adjacency().values);
  EXPECT_FALSE(ProngsJoinAbove(flipped, from_flipped, kForkBaseHeight + 2.0));
}

// The overload that takes the mesh's normals and components (the Deformer's
// precompute has them) builds the same lattice, faces flipped or not, and the
// prongs stay apart.
TEST(LatticeTest, GivenNormalsAndComponentsBuildTheSameLattice) {
  const Mesh fork = MakeFork(0.1);
  Mesh flipped = fork;
  flipped.faces.row(1).swap(flipped.faces.row(2));
  LatticeOptions options;
  options.cell_width = 1.0;
  for (const Mesh* mesh : {&fork, static_cast<const Mesh*>(&flipped)}) {
    const Lattice computed = BuildTestLattice(*mesh, 1.0);
    Lattice given;
    std::string error;
    ASSERT_TRUE(Lattice::Build(*mesh, options, VertexNormals(*mesh), ConnectedComponents(*mesh),
                               &given, &error))
        << error;
    EXPECT_GT(given.num_split_cells(), 0);
    EXPECT_EQ(given.num_split_cells(), computed.num_split_cells());
    EXPECT_EQ(given.particle_of_vertex(), computed.particle_of_vertex());
    EXPECT_EQ(given.rest_positions(), computed.rest_positions());
    EXPECT_EQ(given.particle_adjacency().offsets, computed.particle_adjacency().offsets);
    EXPECT_EQ(given.particle_adjacency().values, computed.particle_adjacency().values);
    EXPECT_FALSE(ProngsJoinAbove(*mesh, given, kForkBaseHeight + 2.0));
  }
}

TEST(LatticeTest, AdjacencyIsSymmetricAndFollowsMethod) {
  const Mesh bar = MakeBar(4, 3.0, 6);
  const Lattice lattice = BuildTestLattice(bar, 0.5);
  const CompressedLists& adjacency = lattice.particle_adjacency();
  for (int p = 0; p < lattice.num_particles(); ++p) {
    for (const int* q = adjacency.begin(p); q != adjacency.end(p); ++q) {
      EXPECT_NE(*q, p);
      EXPECT_NE(std::find(adjacency.begin(*q), adjacency.end(*q), p), adjacency.end(*q));
      EXPECT_LE((lattice.cell_coords(p) - lattice.cell_coords(*q)).cwiseAbs().maxCoeff(), 1);
      if (p < lattice.num_surface_particles() && *q < lattice.num_surface_particles()) {
        const auto& l = lattice.neighborhood();
        EXPECT_NE(std::find(l.begin(p), l.end(p), *q), l.end(p));
      }
    }
  }
}

// A solid bar 4 x 1 x 1 at cell width 0.0185 holds about 4 / 0.0185^3 = 632K
// particles, more than kMaxLatticeParticles: refused after the flood fill,
// before the particles are numbered (a 1.58M-particle lattice crashed the
// harmonic rigidity factorisation after minutes).
TEST(LatticeTest, TooManyParticlesIsAnError) {
  LatticeOptions options;
  options.cell_width = 0.0185;
  Lattice lattice;
  std::string error;
  EXPECT_FALSE(Lattice::Build(MakeBar(4), options, &lattice, &error));
  EXPECT_NE(error.find("particles, more than 500000; use a larger cell width "
                       "(--cell_width, or lattice.cells_per_diagonal)"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.rfind("the lattice has ", 0), 0u) << error;
  EXPECT_EQ(lattice.num_particles(), 0);
  // A cell twice as wide (1/8 of the particles) is accepted.
  options.cell_width = 0.037;
  ASSERT_TRUE(Lattice::Build(MakeBar(4), options, &lattice, &error)) << error;
  EXPECT_GT(lattice.num_particles(), 60000);
  EXPECT_LE(lattice.num_particles(), kMaxLatticeParticles);
}

TEST(LatticeTest, TooFineCellWidthIsAnError) {
  LatticeOptions options;
  options.cell_width = 1e-6;
  Lattice lattice;
  std::string error;
  EXPECT_FALSE(Lattice::Build(MakeBar(4), options, &lattice, &error));
  EXPECT_NE(error.find("cell width"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
