#include "msdeform/methods/rigid_cells.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/method_options.h"

namespace msdeform {
namespace {

double Diagonal(const Mesh& mesh) {
  return (mesh.vertices.rowwise().maxCoeff() - mesh.vertices.rowwise().minCoeff()).norm();
}

// The vertices of a bar (length x 1 x 1 along x) with x >= from (or <= to).
std::vector<int> VerticesWithX(const Mesh& mesh, double from, double to) {
  std::vector<int> vertices;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(0, v) >= from && mesh.vertices(0, v) <= to) vertices.push_back(v);
  }
  return vertices;
}

// Precomputes at 16 cells per diagonal (153 on the bar: a quick test) and
// sets the layout.
void SetUpQuick(const Mesh& mesh, const HandleLayout& layout, RigidCells* method) {
  MethodOptions options;
  options.rigid_cells.cells_per_diagonal = 16.0;
  std::string error;
  ASSERT_TRUE(method->Precompute(mesh, options, &error)) << error;
  ASSERT_TRUE(method->SetHandles(layout, &error)) << error;
}

Eigen::Affine3d RigidMotion() {
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()));
  motion.pretranslate(Eigen::Vector3d(0.3, -1.2, 2.0));
  return motion;
}

// Rotation by `angle` about the y axis through `pivot`.
Eigen::Affine3d Bend(double angle, const Eigen::Vector3d& pivot) {
  Eigen::Affine3d bend = Eigen::Affine3d::Identity();
  bend.translate(pivot);
  bend.rotate(Eigen::AngleAxisd(angle, -Eigen::Vector3d::UnitY()));
  bend.translate(-pivot);
  return bend;
}

// A handle at one end, nothing fixed: the minimum of the coupling energy is
// the handle's rigid motion for every cell (E = 0), which Levenberg-Marquardt
// reaches from rest; the RBF reproduces a rigid motion (its linear part)
// exactly, so every vertex moves by it.
TEST(RigidCellsTest, RigidMotionOfTheHandleWithNothingFixedMovesEveryVertex) {
  const Mesh bar = MakeBar(8, 1.0, 4);
  HandleLayout layout;
  layout.moveable = VerticesWithX(bar, 7.0, 8.0);
  RigidCells method;
  ASSERT_NO_FATAL_FAILURE(SetUpQuick(bar, layout, &method));
  std::string error;
  MethodStats stats;
  ASSERT_TRUE(method.Drag(RigidMotion(), &stats, &error)) << error;
  EXPECT_TRUE(stats.converged);
  EXPECT_GT(method.nodes_optimized(), 0);
  const Eigen::Matrix3Xd expected = RigidMotion() * bar.vertices;
  EXPECT_LT((method.deformed_vertices() - expected).colwise().norm().maxCoeff(),
            1e-9 * Diagonal(bar));
  EXPECT_LT(method.constraint_gap(), 1e-9 * Diagonal(bar));
}

// A flat sheet (a 12 x 6 grid in the plane z = 0): its cell centres are
// coplanar, so a linear polynomial in x, y and z would make the RBF system
// singular; the polynomial over the centres' two axes keeps it regular and
// still reproduces a rigid motion, one that turns the sheet out of its plane
// included.
TEST(RigidCellsTest, FlatSheetMovesRigidlyWithTheHandle) {
  constexpr int kColumns = 12, kRows = 6;
  Mesh sheet;
  sheet.vertices.resize(3, (kColumns + 1) * (kRows + 1));
  for (int j = 0; j <= kRows; ++j) {
    for (int i = 0; i <= kColumns; ++i) sheet.vertices.col(j * (kColumns + 1) + i) << i, j, 0.0;
  }
  sheet.faces.resize(3, 2 * kColumns * kRows);
  for (int j = 0, f = 0; j < kRows; ++j) {
    for (int i = 0; i < kColumns; ++i) {
      const int v = j * (kColumns + 1) + i;
      sheet.faces.col(f++) << v, v + 1, v + kColumns + 2;
      sheet.faces.col(f++) << v, v + kColumns + 2, v + kColumns + 1;
    }
  }
  HandleLayout layout;
  layout.moveable = VerticesWithX(sheet, 11.0, 12.0);
  RigidCells method;
  ASSERT_NO_FATAL_FAILURE(SetUpQuick(sheet, layout, &method));
  std::string error;
  ASSERT_TRUE(method.Drag(RigidMotion(), nullptr, &error)) << error;
  const Eigen::Matrix3Xd expected = RigidMotion() * sheet.vertices;
  EXPECT_LT((method.deformed_vertices() - expected).colwise().norm().maxCoeff(),
            1e-9 * Diagonal(sheet));
  EXPECT_LT(method.constraint_gap(), 1e-9 * Diagonal(sheet));
}

// A handle transform that scales by 1.5 after a rotation: the handle's cells
// take the rotation (the polar factor of the linear part) as a unit
// quaternion, and its vertices land exactly on the scaled targets.
TEST(RigidCellsTest, HandleThatScalesGivesItsCellsItsRotation) {
  const Mesh bar = MakeBar(8, 1.0, 4);
  HandleLayout layout;
  layout.fixed = VerticesWithX(bar, -1.0, 1.0);
  layout.moveable = VerticesWithX(bar, 7.0, 9.0);
  RigidCells method;
  ASSERT_NO_FATAL_FAILURE(SetUpQuick(bar, layout, &method));
  std::string error;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.0, 1.0, 1.0).normalized()).toRotationMatrix();
  Eigen::Affine3d grow = Eigen::Affine3d::Identity();
  grow.linear() = 1.5 * rotation;
  grow.translation() << 0.0, 0.0, 1.0;
  ASSERT_TRUE(method.Drag(grow, nullptr, &error)) << error;
  // The driven cells: those holding a handle vertex (and no fixed one).
  std::vector<char> is_handle(bar.num_vertices(), 0);
  for (int v : layout.moveable) is_handle[v] = 1;
  const CompressedLists& vertices_of = method.lattice()->vertices_of_particle();
  int handle_cells = 0;
  for (int p = 0; p < method.lattice()->num_surface_particles(); ++p) {
    if (vertices_of.size(p) == 0 || !is_handle[*vertices_of.begin(p)]) continue;
    ++handle_cells;
    EXPECT_LT((method.cell_transform(p).linear() - rotation).norm(), 1e-12) << p;
  }
  EXPECT_GT(handle_cells, 0);
  const Eigen::Matrix3Xd& deformed = method.deformed_vertices();
  for (int v : layout.moveable) {
    EXPECT_LT((deformed.col(v) - grow * bar.vertices.col(v)).norm(), 1e-12 * Diagonal(bar)) << v;
  }
  EXPECT_TRUE(deformed.allFinite());
}

// Two copies of a bar in the same place: each cell holds one piece of each,
// and the pieces' centres (their vertices' centroids) coincide, so the RBF
// system is singular: Precompute says so instead of interpolating garbage.
TEST(RigidCellsTest, CoincidingCellCentresAreAnError) {
  const Mesh bar = MakeBar(4, 1.0, 2);
  Mesh twice;
  twice.vertices.resize(3, 2 * bar.num_vertices());
  twice.vertices << bar.vertices, bar.vertices;
  twice.faces.resize(3, 2 * bar.num_faces());
  twice.faces << bar.faces, (bar.faces.array() + bar.num_vertices()).matrix();
  RigidCells method;
  MethodOptions options;
  options.rigid_cells.cells_per_diagonal = 8.0;
  std::string error;
  EXPECT_FALSE(method.Precompute(twice, options, &error));
  EXPECT_NE(error.find("two centres coincide"), std::string::npos) << error;
}

// Handle and fixed cells are constant blocks: their vertices are at their
// targets exactly, the free vertices in between follow the cells.
TEST(RigidCellsTest, HandleAndFixedVerticesAreExact) {
  const Mesh bar = MakeBar(8, 1.0, 4);
  HandleLayout layout;
  layout.fixed = VerticesWithX(bar, -1.0, 1.0);
  layout.moveable = VerticesWithX(bar, 7.0, 9.0);
  RigidCells method;
  ASSERT_NO_FATAL_FAILURE(SetUpQuick(bar, layout, &method));
  std::string error;
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  for (int frame = 1; frame <= 3; ++frame) {
    lift.translation() << 0.0, 0.0, 0.5 * frame;
    ASSERT_TRUE(method.Drag(lift, nullptr, &error)) << error;
  }
  const Eigen::Matrix3Xd& deformed = method.deformed_vertices();
  for (int v : layout.fixed) EXPECT_EQ(deformed.col(v), bar.vertices.col(v)) << v;
  for (int v : layout.moveable) {
    EXPECT_LT((deformed.col(v) - lift * bar.vertices.col(v)).norm(), 1e-9 * Diagonal(bar)) << v;
  }
  // The RBF alone had them within 2% of the lift (the seam inside their cells).
  EXPECT_GT(method.constraint_gap(), 0.0);
  EXPECT_LT(method.constraint_gap(), 0.02 * 1.5);
}

// A bar bent by 0.6 rad from its far end with its near end fixed, over 6
// frames: the far end follows, the near end stays, the middle bends smoothly
// (no edge stretched or squashed by more than 25%, the rise grows along the
// bar) and a repeated frame is a fixed point of the warm-started solve.
TEST(RigidCellsTest, BarBentFromOneEndDeformsSmoothly) {
  const Mesh bar = MakeBar(8, 1.0, 4);
  HandleLayout layout;
  layout.fixed = VerticesWithX(bar, -1.0, 1.0);
  layout.moveable = VerticesWithX(bar, 7.0, 9.0);
  RigidCells method;
  ASSERT_NO_FATAL_FAILURE(SetUpQuick(bar, layout, &method));
  std::string error;
  const Eigen::Vector3d pivot(1.0, 0.5, 0.5);
  MethodStats stats;
  for (int frame = 1; frame <= 6; ++frame) {
    ASSERT_TRUE(method.Drag(Bend(0.1 * frame, pivot), &stats, &error)) << error;
  }
  const Eigen::Affine3d bend = Bend(0.6, pivot);
  const Eigen::Matrix3Xd deformed = method.deformed_vertices();
  for (int v : layout.fixed) EXPECT_EQ(deformed.col(v), bar.vertices.col(v));
  for (int v : layout.moveable) {
    EXPECT_LT((deformed.col(v) - bend * bar.vertices.col(v)).norm(), 1e-9 * Diagonal(bar));
  }
  double longest = 0.0, shortest = 1e300;
  for (int f = 0; f < bar.num_faces(); ++f) {
    for (int e = 0; e < 3; ++e) {
      const int a = bar.faces(e, f), b = bar.faces((e + 1) % 3, f);
      const double ratio = (deformed.col(a) - deformed.col(b)).norm() /
                           (bar.vertices.col(a) - bar.vertices.col(b)).norm();
      longest = std::max(longest, ratio);
      shortest = std::min(shortest, ratio);
    }
  }
  EXPECT_LT(longest, 1.25);
  EXPECT_GT(shortest, 0.8);
  // Along the bottom centre line (y = 0.5, z = 0) the rise grows with x.
  std::vector<std::pair<double, double>> rise;
  for (int v = 0; v < bar.num_vertices(); ++v) {
    if (std::abs(bar.vertices(1, v) - 0.5) < 1e-9 && bar.vertices(2, v) == 0.0) {
      rise.emplace_back(bar.vertices(0, v), deformed(2, v));
    }
  }
  std::sort(rise.begin(), rise.end());
  ASSERT_GT(rise.size(), 8u);
  for (size_t i = 1; i < rise.size(); ++i) {
    if (rise[i].first > 1.0) {
      EXPECT_GT(rise[i].second, rise[i - 1].second) << rise[i].first;
    }
  }
  // The same frame again: the warm start is the minimum.
  MethodStats again;
  ASSERT_TRUE(method.Drag(bend, &again, &error)) << error;
  EXPECT_LE(again.final_cost, stats.final_cost * (1 + 1e-9));
  EXPECT_LT((method.deformed_vertices() - deformed).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(RigidCellsTest, InvalidOptionsAndTooManyCellsAreErrors) {
  const Mesh bar = MakeBar(8, 1.0, 2);
  std::string error;
  MethodOptions options;
  options.rigid_cells.cells_per_diagonal = 1.0;
  RigidCells method;
  EXPECT_FALSE(method.Precompute(bar, options, &error));
  EXPECT_EQ(error, "rigid_cells.cells_per_diagonal=1.000000: expected a number in [2, 64]");
  options = MethodOptions();
  options.rigid_cells.max_cells = 10;
  EXPECT_FALSE(method.Precompute(bar, options, &error));
  EXPECT_NE(error.find("more than rigid_cells.max_cells=10"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
