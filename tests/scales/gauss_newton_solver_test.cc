#include "scales/gauss_newton_solver.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/drag_path.h"
#include "core/handles.h"
#include "core/mesh_io.h"
#include "core/procedural_meshes.h"
#include "scales/deformer.h"

namespace msdeform {
namespace {

struct Edit {
  Mesh mesh;
  HandleLayout layout;
  std::vector<Eigen::Affine3d> path;
};

// A 12 x 1 x 1 bar, the first voxel fixed, the last bent up and twisted.
Edit BarEdit(int frames) {
  Edit edit;
  edit.mesh = MakeBar(12, 1.0, 4);
  for (int v = 0; v < edit.mesh.num_vertices(); ++v) {
    if (edit.mesh.vertices(0, v) <= 1.0) edit.layout.fixed.push_back(v);
    if (edit.mesh.vertices(0, v) >= 11.0) edit.layout.moveable.push_back(v);
  }
  Eigen::Affine3d target = Eigen::Affine3d::Identity();
  target.linear() = Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.3, 0.2, 1.0).normalized())
                        .toRotationMatrix();
  target.translation() = Eigen::Vector3d(-2.0, 4.0, 1.0);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : edit.layout.moveable) centroid += edit.mesh.vertices.col(v);
  centroid /= static_cast<double>(edit.layout.moveable.size());
  edit.path = InterpolateDragPath(target, centroid, frames);
  return edit;
}

Edit CactusEdit(int frames) {
  Edit edit;
  const std::string data = MSDEFORM_DATA_DIR;
  std::string error;
  Eigen::Affine3d target;
  EXPECT_TRUE(ReadMesh(data + "/meshes/cactus.off", &edit.mesh, &error)) << error;
  EXPECT_TRUE(ReadSel(data + "/meshes/cactus.sel", edit.mesh.num_vertices(), &edit.layout, &error))
      << error;
  EXPECT_TRUE(ReadDef(data + "/meshes/cactus.def", &target, &error)) << error;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : edit.layout.moveable) centroid += edit.mesh.vertices.col(v);
  centroid /= static_cast<double>(edit.layout.moveable.size());
  edit.path = InterpolateDragPath(target, centroid, frames);
  return edit;
}

// Tight stopping rules so that both backends run to the minimum itself.
DeformerOptions TightOptions(Method method, Solver backend) {
  DeformerOptions options;
  options.method = method;
  options.backend = backend;
  options.num_threads = 1;
  options.static_nodes = 40;
  options.solver.max_num_iterations = 200;
  options.solver.function_tolerance = 1e-15;
  options.solver.gradient_tolerance = 1e-13;
  options.solver.parameter_tolerance = 1e-15;
  return options;
}

struct Result {
  Eigen::Matrix3Xd vertices;
  std::vector<char> gauge_vertex;  // skinned by a node whose R is not unique
  double energy = 0.0;       // EvaluateEnergy at the last frame
  double reported = 0.0;     // DragStats::final_cost of the last frame
  double diagonal = 0.0;
};

// Nodes whose R the energy does not pin down: the 9x9 block of J^T J on R_j
// (Rot, plus the Coherence and Position terms that read R_j) is singular. A
// Half Free node with a single coherence edge (j, k) is one: turning R_j about
// g_k - g_j changes no term, so Eq. 17 has a family of minima there and the
// backends may land on different members (same energy, different vertices).
std::vector<char> GaugeNodes(const DeformationEnergy& energy, const NodeTransforms& transforms) {
  const int n = transforms.num_nodes();
  std::vector<Eigen::Matrix<double, 9, 9>> blocks(n, Eigen::Matrix<double, 9, 9>::Zero());
  for (int j : energy.rot_nodes) {
    const double* R = transforms.rotations.col(j).data();
    static constexpr int kFirst[6] = {0, 0, 1, 0, 1, 2};
    static constexpr int kSecond[6] = {1, 2, 2, 0, 1, 2};
    Eigen::Matrix<double, 6, 9> jacobian = Eigen::Matrix<double, 6, 9>::Zero();
    for (int r = 0; r < 6; ++r)
      for (int i = 0; i < 3; ++i) {
        jacobian(r, kFirst[r] * 3 + i) += energy.sqrt_rot * R[kSecond[r] * 3 + i];
        jacobian(r, kSecond[r] * 3 + i) += energy.sqrt_rot * R[kFirst[r] * 3 + i];
      }
    blocks[j] += jacobian.transpose() * jacobian;
  }
  auto add_linear = [&](int j, const Eigen::Vector3d& vector, double scale) {
    Eigen::Matrix<double, 3, 9> jacobian = Eigen::Matrix<double, 3, 9>::Zero();
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) jacobian(a, c * 3 + a) = scale * vector[c];
    blocks[j] += jacobian.transpose() * jacobian;
  };
  for (const auto& term : energy.coherence) add_linear(term.j, term.edge, term.sqrt_weight);
  for (const auto& term : energy.positions)
    for (size_t i = 0; i < term.nodes.size(); ++i)
      add_linear(term.nodes[i], term.terms[i].offset, term.sqrt_weight * term.terms[i].weight);
  std::vector<char> gauge(n, 0);
  for (int j : energy.rot_nodes) {
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>>(blocks[j]).eigenvalues();
    gauge[j] = lambda[0] <= 1e-9 * lambda[8];
  }
  return gauge;
}

Result RunEdit(const Edit& edit, DeformerOptions options) {
  Deformer deformer;
  std::string error;
  Result result;
  EXPECT_TRUE(deformer.Init(edit.mesh, options, &error)) << error;
  EXPECT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  DragStats stats;
  for (const Eigen::Affine3d& frame : edit.path) {
    EXPECT_TRUE(deformer.Drag(frame, &stats, &error)) << error;
  }
  result.vertices = deformer.deformed_vertices();
  result.energy = EvaluateEnergy(deformer.energy(), deformer.transforms(), edit.path.back());
  result.reported = stats.final_cost;
  result.diagonal = deformer.diagonal();
  const std::vector<char> gauge = GaugeNodes(deformer.energy(), deformer.transforms());
  const SkinningWeights& weights = deformer.active().weights;
  result.gauge_vertex.assign(edit.mesh.num_vertices(), 0);
  for (int v = 0; v < edit.mesh.num_vertices(); ++v)
    for (int slot = 0; slot < weights.k; ++slot)
      if (weights.weights(slot, v) > 0.0 && gauge[weights.nodes(slot, v)]) result.gauge_vertex[v] = 1;
  return result;
}

// Largest vertex distance, over the vertices the energy determines.
double MaxDistance(const Result& a, const Result& b, int* num_gauge) {
  double distance = 0.0;
  *num_gauge = 0;
  for (int v = 0; v < a.vertices.cols(); ++v) {
    if (a.gauge_vertex[v] || b.gauge_vertex[v]) {
      ++*num_gauge;
      continue;
    }
    distance = std::max(distance, (a.vertices.col(v) - b.vertices.col(v)).norm());
  }
  return distance;
}

void ExpectSameMinimum(const Result& a, const Result& b, const std::string& what) {
  EXPECT_NEAR(a.energy, b.energy, 1e-6 * std::abs(a.energy)) << what;
  int num_gauge = 0;
  EXPECT_LT(MaxDistance(a, b, &num_gauge), 1e-5 * a.diagonal) << what;
  EXPECT_LT(num_gauge, a.vertices.cols() / 4) << what;
  // Each backend reports the true Eq. 17 cost (grouped blocks add their constant).
  EXPECT_NEAR(a.reported, a.energy, 1e-8 * (1.0 + a.energy)) << what;
  EXPECT_NEAR(b.reported, b.energy, 1e-8 * (1.0 + b.energy)) << what;
}

TEST(GaussNewtonSolverTest, BothBackendsReachTheSameMinimumOnTheBar) {
  const Edit edit = BarEdit(4);
  for (Method method : {Method::kMultiScale, Method::kStatic, Method::kStaticDense}) {
    DeformerOptions ceres = TightOptions(method, Solver::kCeres);
    ceres.graph.nodes_per_scale = 20;
    DeformerOptions gauss_newton = TightOptions(method, Solver::kGaussNewton);
    gauss_newton.graph.nodes_per_scale = 20;
    ExpectSameMinimum(RunEdit(edit, ceres), RunEdit(edit, gauss_newton), MethodName(method));
  }
}

TEST(GaussNewtonSolverTest, BothBackendsReachTheSameMinimumOnTheCactus) {
  const Edit edit = CactusEdit(5);
  const Result ceres = RunEdit(edit, TightOptions(Method::kMultiScale, Solver::kCeres));
  const Result gauss_newton = RunEdit(edit, TightOptions(Method::kMultiScale, Solver::kGaussNewton));
  ExpectSameMinimum(ceres, gauss_newton, "cactus");
  EXPECT_GT(ceres.energy, 0.0);
}

TEST(GaussNewtonSolverTest, DefaultTolerancesStayCloseToTheMinimum) {
  // With the default stopping rules (those of Ceres's defaults in
  // DeformerOptions) both backends end within 1e-4 relative energy.
  const Edit edit = CactusEdit(5);
  DeformerOptions ceres, gauss_newton;
  ceres.num_threads = gauss_newton.num_threads = 1;
  gauss_newton.backend = Solver::kGaussNewton;
  const Result a = RunEdit(edit, ceres), b = RunEdit(edit, gauss_newton);
  EXPECT_NEAR(a.energy, b.energy, 1e-4 * a.energy);
  int num_gauge = 0;
  EXPECT_LT(MaxDistance(a, b, &num_gauge), 1e-4 * a.diagonal);
}

TEST(GaussNewtonSolverTest, GroupedPositionBlocksChangeNothing) {
  const Edit edit = BarEdit(3);
  for (Method method : {Method::kMultiScale, Method::kStatic}) {
    DeformerOptions grouped = TightOptions(method, Solver::kCeres);
    grouped.graph.nodes_per_scale = 20;
    DeformerOptions per_vertex = grouped;
    per_vertex.group_position_terms = false;
    ExpectSameMinimum(RunEdit(edit, grouped), RunEdit(edit, per_vertex), MethodName(method));
  }
}

// Every linear solver and Hessian-reuse policy reaches the same minimum,
// straight on the solver with the bar's energy.
TEST(GaussNewtonSolverTest, LinearSolversAndReusePoliciesAgree) {
  const Edit edit = BarEdit(3);
  DeformerOptions options = TightOptions(Method::kMultiScale, Solver::kCeres);
  options.graph.nodes_per_scale = 20;
  Deformer deformer;
  std::string error;
  ASSERT_TRUE(deformer.Init(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  const DeformationEnergy& energy = deformer.energy();
  ASSERT_GT(energy.num_variables(), 0);
  double reference = -1.0;
  using LinearSolver = GaussNewtonOptions::LinearSolver;
  using Reuse = GaussNewtonOptions::HessianReuse;
  for (LinearSolver linear : {LinearSolver::kEigenLLT, LinearSolver::kEigenLDLT,
                              LinearSolver::kCholmod}) {
    for (Reuse reuse : {Reuse::kEveryIteration, Reuse::kPerFrame, Reuse::kLagged}) {
      GaussNewtonOptions gn;
      gn.linear_solver = linear;
      gn.hessian_reuse = reuse;
      gn.max_iterations = 500;
      gn.function_tolerance = 1e-15;
      gn.gradient_tolerance = 1e-13;
      gn.parameter_tolerance = 1e-15;
      NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
      GaussNewtonSolver solver;
      ASSERT_TRUE(solver.Setup(energy, transforms, gn, &error)) << error;
      EXPECT_EQ(solver.num_variables(), deformer.num_variables());
      GaussNewtonSummary summary;
      for (const Eigen::Affine3d& frame : edit.path) summary = solver.Solve(frame, &transforms);
      EXPECT_TRUE(summary.converged) << summary.message;
      const double value = EvaluateEnergy(energy, transforms, edit.path.back());
      EXPECT_NEAR(summary.final_cost, value, 1e-8 * (1.0 + value));
      if (reference < 0.0) reference = value;
      EXPECT_NEAR(value, reference, 1e-9 * reference)
          << static_cast<int>(linear) << " " << static_cast<int>(reuse);
    }
  }
}

TEST(GaussNewtonSolverTest, OptionsCheckAndSolverNames) {
  std::string error;
  GaussNewtonOptions options;
  EXPECT_TRUE(options.Check(&error));
  options.min_damping = 0.0;
  EXPECT_FALSE(options.Check(&error));
  Solver solver;
  EXPECT_TRUE(ParseSolver("gauss_newton", &solver));
  EXPECT_EQ(solver, Solver::kGaussNewton);
  EXPECT_TRUE(ParseSolver("ceres", &solver));
  EXPECT_EQ(solver, Solver::kCeres);
  EXPECT_FALSE(ParseSolver("lbfgs", &solver));
}

}  // namespace
}  // namespace msdeform
