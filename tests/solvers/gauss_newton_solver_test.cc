#include "msdeform/solvers/gauss_newton_solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/energies/gauge_cost.h"
#include "msdeform/energies/rot_cost.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/scales/deformer_options.h"
#include "tests/solvers/frame_solver_test_util.h"

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

constexpr StoppingRule kTightStopping = TightStopping(/*max_iterations=*/1000);

// Tight stopping rules so that both backends run to the minimum itself. The
// cap is not meant to bind: with the Totally Free border ring
// (BorderRule::kTotallyFree) Gauss-Newton needs 475 iterations in the bar's
// last frame (Ceres 37) and stopped 2.7e-5 of the diagonal away at 200.
DeformerOptions TightOptions(Method method, Solver backend) {
  DeformerOptions options;
  options.method = method;
  options.backend = backend;
  options.num_threads = 1;
  options.static_nodes = 40;
  options.stopping = kTightStopping;
  return options;
}

// Two cactus configurations with Half Free rotations Eq. 17 leaves free, both
// with two of the paper's rules (no Position term on the fixed-handle
// vertices, the Fixed nodes next to the free region stay Fixed): with the
// other defaults, and with all the paper's rules (also every fixed-handle node
// Half Free, the shape-matching rigidity estimate). Both have Half Free nodes
// with a single edge direction; the second also nodes that are the source of
// no coherence term.
std::vector<std::pair<std::string, DeformerOptions>> CactusConfigurations(Solver backend) {
  DeformerOptions free_handles = TightOptions(Method::kMultiScale, backend);
  free_handles.hold_fixed_vertices = false;
  free_handles.selection.border = BorderRule::kFixed;
  // Half Free nodes (which the gauge terms are for) hold fixed vertices, so
  // the fixed region must not pin them.
  free_handles.selection.pin_fixed_region = false;
  DeformerOptions paper = free_handles;
  paper.selection.half_free = HalfFreeRule::kEveryFixedHandleNode;
  paper.rigidity.model = RigidityModel::kShapeMatching;
  return {{"no fixed Position terms", free_handles}, {"paper", paper}};
}

struct Result {
  Eigen::Matrix3Xd vertices;
  int singular_nodes = 0;    // nodes whose R the energy does not pin down
  int gauge_terms = 0;       // DeformationEnergy::gauge
  double energy = 0.0;       // EvaluateEnergy at the last frame
  double reported = 0.0;     // DragStats::final_cost of the last frame
  double diagonal = 0.0;
};

// Nodes whose R the energy does not pin down: the 9x9 block of J^T J on R_j
// (Rot, plus the Coherence, Position and gauge terms that read R_j) is
// singular. Without the gauge terms a Half Free node with a single coherence
// edge (j, k) is one: turning R_j about g_k - g_j changes no term, so Eq. 17
// has a family of minima there and the backends landed on different members
// (same energy, different vertices). The gauge terms must leave none.
std::vector<char> SingularRotationNodes(const DeformationEnergy& energy,
                                        const NodeTransforms& transforms) {
  const int n = transforms.num_nodes();
  std::vector<Eigen::Matrix<double, 9, 9>> blocks(n, Eigen::Matrix<double, 9, 9>::Zero());
  for (int j : energy.rot_nodes) {
    Eigen::Matrix<double, 6, 9> jacobian;
    double residuals[6];
    RotResiduals(transforms.rotations.col(j).data(), energy.sqrt_rot, residuals, &jacobian);
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
  for (const auto& term : energy.gauge) {
    const Eigen::Matrix<double, 1, 9> row =
        GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight);
    blocks[term.node] += row.transpose() * row;
  }
  std::vector<char> singular(n, 0);
  for (int j : energy.rot_nodes) {
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>>(blocks[j]).eigenvalues();
    singular[j] = lambda[0] <= 1e-9 * lambda[8];
  }
  return singular;
}

Result RunEdit(const Edit& edit, DeformerOptions options) {
  GraphMethod deformer(options.method);
  std::string error;
  Result result;
  EXPECT_TRUE(deformer.Precompute(edit.mesh, options, &error)) << error;
  EXPECT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  DragStats stats;
  for (const Eigen::Affine3d& frame : edit.path) {
    EXPECT_TRUE(deformer.Drag(frame, &stats, &error)) << error;
  }
  result.vertices = deformer.deformed_vertices();
  result.energy = EvaluateEnergy(deformer.energy(), deformer.transforms(), edit.path.back());
  result.reported = stats.final_cost;
  result.diagonal = deformer.diagonal();
  const std::vector<char> singular =
      SingularRotationNodes(deformer.energy(), deformer.transforms());
  result.singular_nodes = static_cast<int>(std::count(singular.begin(), singular.end(), 1));
  result.gauge_terms = static_cast<int>(deformer.energy().gauge.size());
  return result;
}

// Largest vertex distance, over all vertices.
double MaxDistance(const Result& a, const Result& b) {
  double distance = 0.0;
  for (int v = 0; v < a.vertices.cols(); ++v)
    distance = std::max(distance, (a.vertices.col(v) - b.vertices.col(v)).norm());
  return distance;
}

// Same energy (1e-6 relative) and the same vertices, all of them, to 1e-6 of
// the diagonal: with the gauge terms the minimiser is unique.
void ExpectSameMinimum(const Result& a, const Result& b, const std::string& what) {
  EXPECT_NEAR(a.energy, b.energy, 1e-6 * std::abs(a.energy)) << what;
  EXPECT_LT(MaxDistance(a, b), 1e-6 * a.diagonal) << what;
  EXPECT_EQ(a.singular_nodes, 0) << what;
  EXPECT_EQ(b.singular_nodes, 0) << what;
  // Each backend reports the true Eq. 17 cost (grouped blocks add their constant).
  EXPECT_NEAR(a.reported, a.energy, 1e-8 * (1.0 + a.energy)) << what;
  EXPECT_NEAR(b.reported, b.energy, 1e-8 * (1.0 + b.energy)) << what;
}

TEST(GaussNewtonSolverTest, BothBackendsReachTheSameMinimumOnTheBar) {
  const Edit edit = BarEdit(4);
  for (Method method : {Method::kMultiScale, Method::kStatic, Method::kStaticDense}) {
    // A lattice of 24 cells a diagonal: static_dense's graph (every surface
    // particle) has about a quarter of the default's nodes, and the tight
    // Ceres solve on it takes seconds instead of half a minute.
    DeformerOptions ceres = TightOptions(method, Solver::kCeres);
    ceres.graph.nodes_per_scale = 20;
    ceres.lattice.cells_per_diagonal = 24.0;
    DeformerOptions gauss_newton = ceres;
    gauss_newton.backend = Solver::kGaussNewton;
    ExpectSameMinimum(RunEdit(edit, ceres), RunEdit(edit, gauss_newton), MethodName(method));
  }
}

// The Botsch-Sorkine cactus has Half Free nodes with a single coherence edge
// (and, under the paper's rules, some with none): without the gauge terms
// their spin was free and the backends differed by up to 8e-5 and 5e-4 of
// the diagonal (same energy). Now every vertex agrees; the default
// configuration (fixed vertices held) has no gauge and must agree as well.
TEST(GaussNewtonSolverTest, BothBackendsReachTheSameMinimumOnTheCactus) {
  const Edit edit = CactusEdit(5);
  const auto ceres_configurations = CactusConfigurations(Solver::kCeres);
  const auto gauss_newton_configurations = CactusConfigurations(Solver::kGaussNewton);
  for (size_t c = 0; c < ceres_configurations.size(); ++c) {
    const std::string& what = ceres_configurations[c].first;
    const Result ceres = RunEdit(edit, ceres_configurations[c].second);
    const Result gauss_newton = RunEdit(edit, gauss_newton_configurations[c].second);
    EXPECT_GT(ceres.gauge_terms, 0) << what;
    EXPECT_EQ(ceres.gauge_terms, gauss_newton.gauge_terms) << what;
    ExpectSameMinimum(ceres, gauss_newton, what);
    EXPECT_GT(ceres.energy, 0.0) << what;
  }
  ExpectSameMinimum(RunEdit(edit, TightOptions(Method::kMultiScale, Solver::kCeres)),
                    RunEdit(edit, TightOptions(Method::kMultiScale, Solver::kGaussNewton)),
                    "default");
}

// The gauge terms only pick a member of each family of equal-energy minima:
// the minimum of Eq. 17 is the same with and without them, and they vanish at
// the minimiser.
TEST(GaussNewtonSolverTest, GaugeTermsLeaveTheMinimumUnchanged) {
  const Edit edit = CactusEdit(5);
  const DeformerOptions options = CactusConfigurations(Solver::kCeres).back().second;
  GraphMethod deformer(options.method);
  std::string error;
  ASSERT_TRUE(deformer.Precompute(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  const DeformationEnergy& with_gauge = deformer.energy();
  ASSERT_GT(with_gauge.gauge.size(), 0u);
  DeformationEnergy without_gauge = with_gauge;
  without_gauge.gauge.clear();

  GaussNewtonOptions gn;
  StoppingRule stopping = kTightStopping;
  stopping.max_iterations = 500;
  // Without the gauge terms J^T J is singular and only the damping floor
  // lets the factorisation through; the energy still reaches its minimum.
  auto minimise = [&](const DeformationEnergy& energy) {
    NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
    GaussNewtonSolver solver(gn, stopping);
    EXPECT_TRUE(solver.Setup(energy, transforms, &error)) << error;
    for (const Eigen::Affine3d& frame : edit.path) solver.Solve(frame, &transforms);
    return transforms;
  };
  const NodeTransforms gauged = minimise(with_gauge);
  const NodeTransforms free = minimise(without_gauge);
  const double minimum = EvaluateEnergy(without_gauge, free, edit.path.back());
  const double gauged_value = EvaluateEnergy(with_gauge, gauged, edit.path.back());
  EXPECT_GT(minimum, 0.0);
  EXPECT_NEAR(gauged_value, minimum, 1e-6 * minimum);
  // The gauge residuals are zero there: the same value without them.
  EXPECT_NEAR(EvaluateEnergy(without_gauge, gauged, edit.path.back()), gauged_value,
              1e-12 * gauged_value);
  // And Ceres, with the gauge terms, ends at the same value.
  for (const Eigen::Affine3d& frame : edit.path) ASSERT_TRUE(deformer.Drag(frame, nullptr, &error));
  EXPECT_NEAR(EvaluateEnergy(without_gauge, deformer.transforms(), edit.path.back()), minimum,
              1e-6 * minimum);
}

DeformationEnergy::Coherence Edge(int j, int k, const Eigen::Vector3d& edge) {
  return {j, k, edge, 2.0};
}

// Which nodes get gauge terms, on hand-made energies.
TEST(GaussNewtonSolverTest, GaugeTermsOnlyForTheSpinsTheEnergyLeavesFree) {
  DeformationEnergy energy;
  // 0: Half Free, one edge; 1: Half Free, two antiparallel edges; 2: Half
  // Free, two edges in different directions; 3: Half Free, no edge as source
  // (only as target); 4: Totally Free, one edge, and one Position share along
  // it; 5: Totally Free, one edge and a Position share across it; 6: Fixed.
  energy.node_class = {NodeClass::kHalfFree,    NodeClass::kHalfFree,    NodeClass::kHalfFree,
                       NodeClass::kHalfFree,    NodeClass::kTotallyFree, NodeClass::kTotallyFree,
                       NodeClass::kFixed};
  energy.rot_nodes = {0, 1, 2, 3, 4, 5};
  energy.sqrt_rot = 1.5;
  const Eigen::Vector3d e(1.0, 2.0, -0.5);
  energy.coherence = {Edge(0, 6, e),        Edge(1, 6, e),  Edge(1, 4, -3.0 * e),
                      Edge(2, 6, e),        Edge(2, 4, e + Eigen::Vector3d(0, 0, 1e-3)),
                      Edge(6, 3, e),        Edge(4, 6, e),  Edge(5, 6, e)};
  DeformationEnergy::Position position;
  position.nodes = {4, 5};
  position.terms = {{0.5, 0.25 * e, Eigen::Vector3d::Zero()},
                    {0.5, Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d::Zero()}};
  position.rest = Eigen::Vector3d::Zero();
  position.handle_group = 0;
  position.sqrt_weight = 10.0;
  energy.positions = {position};

  const std::vector<DeformationEnergy::Gauge> gauge = GaugeTerms(energy);
  std::vector<int> count(7, 0);
  for (const DeformationEnergy::Gauge& term : gauge) {
    ++count[term.node];
    EXPECT_EQ(term.sqrt_weight, 1.5);
    EXPECT_NEAR(term.axis.norm(), 1.0, 1e-15);
    if (term.node != 3) {
      EXPECT_NEAR(std::abs(term.axis.dot(e.normalized())), 1.0, 1e-12);
    }
  }
  EXPECT_EQ(count, (std::vector<int>{1, 1, 0, 3, 1, 0, 0}));
  // Node 3's axes are x, y and z.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  for (const DeformationEnergy::Gauge& term : gauge)
    if (term.node == 3) axes += term.axis * term.axis.transpose();
  EXPECT_TRUE(axes.isApprox(Eigen::Matrix3d::Identity()));

  // No Rot weight, no gauge.
  energy.sqrt_rot = 0.0;
  EXPECT_TRUE(GaugeTerms(energy).empty());
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
  EXPECT_LT(MaxDistance(a, b), 1e-4 * a.diagonal);
}

TEST(GaussNewtonSolverTest, GroupedPositionBlocksChangeNothing) {
  const Edit edit = BarEdit(3);
  for (Method method : {Method::kMultiScale, Method::kStatic}) {
    DeformerOptions grouped = TightOptions(method, Solver::kCeres);
    grouped.graph.nodes_per_scale = 20;
    DeformerOptions per_vertex = grouped;
    per_vertex.ceres.group_position_terms = false;
    ExpectSameMinimum(RunEdit(edit, grouped), RunEdit(edit, per_vertex), MethodName(method));
  }
}

// CeresOptions::jacobians: the autodiff functors and the analytic cost
// functions (both with one position block per vertex) reach the same
// minimum. On the multi-scale bar (a few coarse nodes) every vertex agrees to
// 1e-9 of the diagonal (measured: 3e-16). On the 40-node static graph the
// energies agree to 1e-12 (3e-15) but the vertices only to 6.4e-9 of the
// diagonal: a minimiser that accepts a step when the cost decreases is
// determined to about sqrt(1e-16) relative where the energy is not zero, so
// two Jacobians that differ in rounding stop that far apart; 1e-7 bounds it.
TEST(GaussNewtonSolverTest, CeresAutodiffJacobiansReachTheAnalyticMinimum) {
  const Edit edit = BarEdit(3);
  for (Method method : {Method::kMultiScale, Method::kStatic}) {
    DeformerOptions analytic = TightOptions(method, Solver::kCeres);
    analytic.graph.nodes_per_scale = 20;
    analytic.ceres.group_position_terms = false;  // as autodiff's: one block per vertex
    DeformerOptions autodiff = analytic;
    autodiff.ceres.jacobians = CeresOptions::Jacobians::kAutodiff;
    const Result a = RunEdit(edit, analytic), b = RunEdit(edit, autodiff);
    const double tolerance = method == Method::kMultiScale ? 1e-9 : 1e-7;
    EXPECT_LT(MaxDistance(a, b), tolerance * a.diagonal) << MethodName(method);
    EXPECT_NEAR(a.energy, b.energy, 1e-12 * a.energy) << MethodName(method);
    EXPECT_NEAR(b.reported, b.energy, 1e-8 * (1.0 + b.energy)) << MethodName(method);
  }
  for (auto jacobians : {CeresOptions::Jacobians::kAnalytic, CeresOptions::Jacobians::kAutodiff}) {
    CeresOptions::Jacobians parsed;
    EXPECT_TRUE(ParseJacobians(JacobiansName(jacobians), &parsed));
    EXPECT_EQ(parsed, jacobians);
  }
  CeresOptions::Jacobians parsed;
  EXPECT_FALSE(ParseJacobians("numeric", &parsed));
  EXPECT_STREQ(JacobiansName(CeresOptions::Jacobians::kAutodiff), "autodiff");
}

// Every Gauss-Newton variant (each sparse Cholesky, both PCG preconditioners,
// each factorisation policy, both dampings) reaches the same minimum, straight
// on the solver with the bar's energy, through the FrameSolver interface.
TEST(GaussNewtonSolverTest, EveryGaussNewtonVariantReachesTheSameMinimum) {
  const Edit edit = BarEdit(3);
  DeformerOptions options = TightOptions(Method::kMultiScale, Solver::kCeres);
  options.graph.nodes_per_scale = 20;
  GraphMethod deformer(options.method);
  std::string error;
  ASSERT_TRUE(deformer.Precompute(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  const DeformationEnergy& energy = deformer.energy();
  ASSERT_GT(energy.num_variables(), 0);
  double reference = -1.0;
  using LinearSolver = GaussNewtonOptions::LinearSolver;
  using Cholesky = GaussNewtonOptions::Cholesky;
  using Factorization = GaussNewtonOptions::Factorization;
  using Damping = GaussNewtonOptions::Damping;
  std::vector<GaussNewtonOptions> variants;
  for (Cholesky cholesky :
       {Cholesky::kSupernodal, Cholesky::kEigenLLT, Cholesky::kEigenLDLT, Cholesky::kCholmod}) {
    GaussNewtonOptions gn;
    gn.cholesky = cholesky;
    variants.push_back(gn);
  }
  for (LinearSolver linear : {LinearSolver::kPcgJacobi, LinearSolver::kPcgIncompleteCholesky}) {
    GaussNewtonOptions gn;
    gn.linear_solver = linear;
    variants.push_back(gn);
  }
  const size_t base_variants = variants.size();
  for (size_t i = 0; i < base_variants; ++i) {
    for (Factorization factorization : {Factorization::kEveryIteration, Factorization::kPerFrame}) {
      GaussNewtonOptions gn = variants[i];
      gn.factorization = factorization;
      variants.push_back(gn);
    }
    GaussNewtonOptions gn = variants[i];
    gn.damping = Damping::kLevenbergMarquardt;
    variants.push_back(gn);
  }
  for (const GaussNewtonOptions& gn : variants) {
    const std::string what = std::string(LinearSolverName(gn.linear_solver)) + " " +
                             CholeskyName(gn.cholesky) + " " +
                             FactorizationName(gn.factorization) + " " + DampingName(gn.damping);
    NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
    std::unique_ptr<FrameSolver> solver =
        std::make_unique<GaussNewtonSolver>(gn, kTightStopping);
    ASSERT_TRUE(solver->Setup(energy, transforms, &error)) << error;
    EXPECT_EQ(solver->num_variables(), deformer.variables());
    SolveSummary summary;
    for (const Eigen::Affine3d& frame : edit.path) summary = solver->Solve(frame, &transforms);
    EXPECT_TRUE(summary.converged) << what << ": " << summary.message;
    EXPECT_FALSE(summary.failed) << what;
    const double value = EvaluateEnergy(energy, transforms, edit.path.back());
    EXPECT_NEAR(summary.final_cost, value, 1e-8 * (1.0 + value)) << what;
    // Cost (for choosing an initial guess) is the same energy, also away
    // from the minimum.
    EXPECT_NEAR(solver->Cost(edit.path.back(), transforms), value, 1e-8 * (1.0 + value)) << what;
    const NodeTransforms rest = NodeTransforms::Identity(transforms.num_nodes());
    const double at_rest = EvaluateEnergy(energy, rest, edit.path.back());
    EXPECT_NEAR(solver->Cost(edit.path.back(), rest), at_rest, 1e-8 * (1.0 + at_rest)) << what;
    // The trace starts at the initial cost and ends at the final one.
    ASSERT_GE(summary.trace.size(), 2u) << what;
    EXPECT_EQ(summary.trace.front().cost, summary.initial_cost) << what;
    EXPECT_EQ(summary.trace.back().cost, summary.final_cost) << what;
    if (reference < 0.0) reference = value;
    EXPECT_NEAR(value, reference, 1e-9 * reference) << what;
  }
}

// The Ceres backend's Cost is Eq. 17 (grouped position blocks add their
// constant), at rest and away from it.
TEST(GaussNewtonSolverTest, CeresCostIsTheEnergy) {
  const Edit edit = BarEdit(3);
  DeformerOptions options = TightOptions(Method::kMultiScale, Solver::kCeres);
  options.graph.nodes_per_scale = 20;
  GraphMethod deformer(options.method);
  std::string error;
  ASSERT_TRUE(deformer.Precompute(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  for (bool grouped : {true, false}) {
    CeresOptions ceres;
    ceres.group_position_terms = grouped;
    NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
    CeresSolver solver(ceres, kTightStopping, 1);
    ASSERT_TRUE(solver.Setup(deformer.energy(), transforms, &error)) << error;
    const double at_rest = EvaluateEnergy(deformer.energy(), transforms, edit.path.back());
    EXPECT_NEAR(solver.Cost(edit.path.back(), transforms), at_rest, 1e-9 * at_rest);
    solver.Solve(edit.path.back(), &transforms);
    const double solved = EvaluateEnergy(deformer.energy(), transforms, edit.path.back());
    EXPECT_NEAR(solver.Cost(edit.path.back(), transforms), solved, 1e-9 * (1.0 + solved));
  }
}

// Ceres's variants (Levenberg-Marquardt and dogleg, each sparse library this
// Ceres has, CGNR) and the three initial guesses reach the Gauss-Newton
// backend's minimum through the Deformer.
TEST(GaussNewtonSolverTest, CeresVariantsAndInitialGuessesReachTheSameMinimum) {
  const Edit edit = BarEdit(3);
  DeformerOptions reference_options = TightOptions(Method::kMultiScale, Solver::kGaussNewton);
  reference_options.graph.nodes_per_scale = 20;
  const Result reference = RunEdit(edit, reference_options);
  std::vector<std::pair<std::string, DeformerOptions>> variants;
  for (auto library : CeresSparseLibraries()) {
    for (auto trust_region : {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}) {
      DeformerOptions o = reference_options;
      o.backend = Solver::kCeres;
      o.ceres.sparse_library = library;
      o.ceres.trust_region = trust_region;
      variants.push_back({TrustRegionName(trust_region) + " " + SparseLibraryName(library), o});
    }
  }
  EXPECT_GE(variants.size(), 2u);
  DeformerOptions cgnr = reference_options;
  cgnr.backend = Solver::kCeres;
  cgnr.ceres.linear_solver = ceres::CGNR;
  variants.push_back({"cgnr", cgnr});
  for (InitialGuess guess : {InitialGuess::kRest, InitialGuess::kExtrapolated}) {
    DeformerOptions o = reference_options;
    o.initial_guess = guess;
    variants.push_back({InitialGuessName(guess), o});
  }
  for (const auto& [what, options] : variants) {
    const Result result = RunEdit(edit, options);
    // CGNR's inexact steps stop on the function tolerance a little earlier.
    const double tolerance = what == "cgnr" ? 1e-4 : 1e-6;
    EXPECT_NEAR(result.energy, reference.energy, tolerance * reference.energy) << what;
    EXPECT_LT(MaxDistance(result, reference), tolerance * reference.diagonal) << what;
  }
}

// One Totally Free node far from the origin (1e3) pulled by 2N position
// terms: N follow a handle translated by d, N stay at rest, offsets in +/-
// pairs (sum zero in each half). With R = I, t the cost is
//   1/2 s^2 (N |t - d|^2 + N |t|^2),
// minimised at R = I, t = d / 2 with value 1/2 s^2 (N / 2) |d|^2. The old
// expanded form 1/2 (x^T H x + 2 g0^T x + kappa) lost about 1e-16 of kappa =
// |c - P tau|^2 ~ 2N s^2 |rest|^2: 4e-7 of this value, 40x the function
// tolerance (1e-8). Cost and the reported costs must be exact to 1e-10.
TEST(GaussNewtonSolverTest, CostIsExactFarFromTheOrigin) {
  const int kPairs = 500;  // N = 2 kPairs per half
  const double s = 10.0;
  const Eigen::Vector3d node(1e3, -1.7e3, 0.6e3);
  DeformationEnergy energy;
  energy.node_class = {NodeClass::kTotallyFree};
  energy.rot_nodes = {0};
  energy.sqrt_rot = 1.0;
  for (bool follows : {true, false}) {
    for (int l = 0; l < kPairs; ++l) {
      const Eigen::Vector3d o(std::cos(0.37 * l), std::sin(0.91 * l), 0.5 * std::cos(1.3 * l));
      for (double sign : {1.0, -1.0}) {
        DeformationEnergy::Position position;
        position.nodes = {0};
        position.terms = {{1.0, sign * o, node}};
        position.rest = node + sign * o;
        position.handle_group = follows ? 0 : -1;
        position.sqrt_weight = s;
        energy.positions.push_back(position);
      }
    }
  }
  const double n = 2.0 * kPairs;
  const Eigen::Vector3d d(0.06, -0.05, 0.07);
  const Eigen::Affine3d handle{Eigen::Translation3d(d)};
  GaussNewtonSolver solver(GaussNewtonOptions(), kTightStopping);
  NodeTransforms transforms = NodeTransforms::Identity(1);
  std::string error;
  ASSERT_TRUE(solver.Setup(energy, transforms, &error)) << error;
  // Away from the minimum (t = 0.3 d), by hand.
  transforms.translations.col(0) = 0.3 * d;
  const double away = 0.5 * s * s * n * ((0.3 * d - d).squaredNorm() + (0.3 * d).squaredNorm());
  EXPECT_NEAR(solver.Cost(handle, transforms), away, 1e-10 * away);
  EXPECT_NEAR(EvaluateEnergy(energy, transforms, handle), away, 1e-10 * away);
  const double minimum = 0.5 * s * s * (n / 2.0) * d.squaredNorm();
  const SolveSummary summary = solver.Solve(handle, &transforms);
  EXPECT_TRUE(summary.converged) << summary.message;
  EXPECT_NEAR(summary.initial_cost, away, 1e-10 * away);
  EXPECT_NEAR(summary.final_cost, minimum, 1e-10 * minimum);
  EXPECT_NEAR(solver.Cost(handle, transforms), minimum, 1e-10 * minimum);
  EXPECT_LT((transforms.translations.col(0) - 0.5 * d).norm(), 1e-9 * d.norm());
  EXPECT_LT((transforms.rotation(0) - Eigen::Matrix3d::Identity()).norm(), 1e-10);
}

// A coherence edge so stiff (sqrt weight 2^150) that every damping the solver
// can add (mu up to 1e32, times diag(J^T J) clamped at 1e32) is below the
// rounding of J^T J (2^300): R_j e and t_j enter only through their sum, so
// the system is singular and no factorisation succeeds. The cost (1/2 2^300
// |t_j|^2) is finite: the frame failed because nothing could be solved, and
// the summary must say so instead of returning the start as a result.
TEST(GaussNewtonSolverTest, AFrameThatNeverFactorisesFails) {
  DeformationEnergy energy;
  energy.node_class = {NodeClass::kTotallyFree, NodeClass::kFixed};
  energy.rot_nodes = {0};
  energy.sqrt_rot = 1.0;
  energy.coherence = {{0, 1, Eigen::Vector3d(1.0, 0.0, 0.0), std::ldexp(1.0, 150)}};
  for (int budget : {1, 20, 1000}) {
    for (GaussNewtonOptions::Cholesky cholesky :
         {GaussNewtonOptions::Cholesky::kSupernodal, GaussNewtonOptions::Cholesky::kEigenLLT,
          GaussNewtonOptions::Cholesky::kEigenLDLT}) {
      GaussNewtonOptions gn;
      gn.cholesky = cholesky;
      StoppingRule stopping;
      stopping.max_iterations = budget;
      GaussNewtonSolver solver(gn, stopping);
      NodeTransforms transforms = NodeTransforms::Identity(2);
      transforms.translations(0, 1) = 1.0;  // the Fixed node, read by Setup
      std::string error;
      ASSERT_TRUE(solver.Setup(energy, transforms, &error)) << error;
      const SolveSummary summary = solver.Solve(Eigen::Affine3d::Identity(), &transforms);
      const std::string what = std::string(CholeskyName(cholesky)) + " budget " +
                               std::to_string(budget) + ": " + summary.message;
      EXPECT_TRUE(std::isfinite(summary.final_cost)) << what;
      EXPECT_GT(summary.factorizations, 0) << what;
      EXPECT_TRUE(summary.failed) << what;
      EXPECT_FALSE(summary.converged) << what;
      EXPECT_NE(summary.message.find("factoris"), std::string::npos) << what;
    }
  }
}

// The default Cholesky (supernodal) against the one before it (Eigen's
// SimplicialLLT) at the default stopping rule: the same steps, so the same
// iterations, factorisations and minimum up to round-off.
TEST(GaussNewtonSolverTest, SupernodalCholeskyTakesTheStepsOfEigensLLT) {
  const Edit edit = BarEdit(6);
  DeformerOptions options;
  options.num_threads = 1;
  ASSERT_EQ(options.gauss_newton.cholesky, GaussNewtonOptions::Cholesky::kSupernodal);
  DeformerOptions eigen = options;
  eigen.gauss_newton.cholesky = GaussNewtonOptions::Cholesky::kEigenLLT;
  GraphMethod a(options.method), b(eigen.method);
  std::string error;
  ASSERT_TRUE(a.Precompute(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(b.Precompute(edit.mesh, eigen, &error)) << error;
  ASSERT_TRUE(a.SetHandles(edit.layout, &error)) << error;
  ASSERT_TRUE(b.SetHandles(edit.layout, &error)) << error;
  for (const Eigen::Affine3d& frame : edit.path) {
    DragStats sa, sb;
    ASSERT_TRUE(a.Drag(frame, &sa, &error)) << error;
    ASSERT_TRUE(b.Drag(frame, &sb, &error)) << error;
    EXPECT_EQ(sa.iterations, sb.iterations);
    EXPECT_EQ(sa.factorizations, sb.factorizations);
    EXPECT_NEAR(sa.final_cost, sb.final_cost, 1e-12 * sb.final_cost);
  }
  EXPECT_GT(a.variables(), 100);
  const Eigen::Matrix3Xd& va = a.deformed_vertices();
  const Eigen::Matrix3Xd& vb = b.deformed_vertices();
  EXPECT_LE((va - vb).cwiseAbs().maxCoeff(), 1e-12 * a.diagonal());
}

// The Rot terms' assembly over fixed chunks: 1, 2 and 3 threads (chunks of
// 4 nodes, parallel from one node, so the bar's nodes split over them) take
// the same steps to the same bits as the serial one-chunk path up to the
// order of the chunk sums; each frame's J^T J and right-hand side must be
// bit-identical for the trajectories to be.
TEST(GaussNewtonSolverTest, ChunkedRotAssemblyIsTheSameForAnyThreadCount) {
  const Edit edit = BarEdit(4);
  DeformerOptions options;
  options.num_threads = 1;
  GraphMethod deformer(options.method);
  std::string error;
  ASSERT_TRUE(deformer.Precompute(edit.mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(edit.layout, &error)) << error;
  const DeformationEnergy& energy = deformer.energy();
  ASSERT_GT(energy.rot_nodes.size(), 8u);
  std::vector<NodeTransforms> results;
  std::vector<std::vector<double>> costs;
  for (int num_threads : {1, 2, 3}) {
    GaussNewtonThreads threads;
    threads.num_threads = num_threads;
    threads.chunk_size = 4;
    threads.min_parallel_terms = 1;
    GaussNewtonSolver solver(GaussNewtonOptions(), StoppingRule(), threads);
    NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
    ASSERT_TRUE(solver.Setup(energy, transforms, &error)) << error;
    std::vector<double> cost;
    for (const Eigen::Affine3d& frame : edit.path) {
      const SolveSummary summary = solver.Solve(frame, &transforms);
      ASSERT_FALSE(summary.failed) << summary.message;
      for (const auto& point : summary.trace) cost.push_back(point.cost);
    }
    results.push_back(transforms);
    costs.push_back(cost);
  }
  for (size_t t = 1; t < results.size(); ++t) {
    EXPECT_EQ(costs[t], costs[0]) << t + 1 << " threads";
    EXPECT_EQ(0, std::memcmp(results[t].rotations.data(), results[0].rotations.data(),
                             sizeof(double) * results[0].rotations.size()));
    EXPECT_EQ(0, std::memcmp(results[t].translations.data(), results[0].translations.data(),
                             sizeof(double) * results[0].translations.size()));
  }
  // The serial one-chunk path reaches the same minimum (its sums in another order).
  GaussNewtonSolver serial{GaussNewtonOptions(), StoppingRule()};
  NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());
  ASSERT_TRUE(serial.Setup(energy, transforms, &error)) << error;
  SolveSummary summary;
  for (const Eigen::Affine3d& frame : edit.path) summary = serial.Solve(frame, &transforms);
  EXPECT_NEAR(summary.final_cost, costs[0].back(), 1e-12 * summary.final_cost);
}

TEST(GaussNewtonSolverTest, BadCholeskyNameIsOneLineNamingTheOption) {
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(DeformerOptionTable().Set("gauss_newton.cholesky", "block", &options, &error));
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_NE(error.find("gauss_newton.cholesky"), std::string::npos) << error;
  EXPECT_NE(error.find("supernodal"), std::string::npos) << error;
  GaussNewtonOptions::Cholesky parsed;
  EXPECT_TRUE(ParseCholesky("supernodal", &parsed));
  EXPECT_EQ(parsed, GaussNewtonOptions::Cholesky::kSupernodal);
}

TEST(GaussNewtonSolverTest, OptionsCheckAndSolverNames) {
  std::string error;
  GaussNewtonOptions options;
  EXPECT_TRUE(options.Check(&error));
  options.min_damping = 0.0;
  EXPECT_FALSE(options.Check(&error));
  StoppingRule stopping;
  EXPECT_TRUE(stopping.Check(&error));
  stopping.max_iterations = 0;
  EXPECT_FALSE(stopping.Check(&error));
  EXPECT_NE(error.find("max_iterations"), std::string::npos) << error;
  for (GaussNewtonOptions::LinearSolver linear :
       {GaussNewtonOptions::LinearSolver::kCholesky, GaussNewtonOptions::LinearSolver::kPcgJacobi,
        GaussNewtonOptions::LinearSolver::kPcgIncompleteCholesky}) {
    GaussNewtonOptions::LinearSolver parsed;
    EXPECT_TRUE(ParseLinearSolver(LinearSolverName(linear), &parsed));
    EXPECT_EQ(parsed, linear);
  }
  ceres::SparseLinearAlgebraLibraryType library;
  EXPECT_TRUE(ParseSparseLibrary("eigen_sparse", &library));
  EXPECT_EQ(library, ceres::EIGEN_SPARSE);
  EXPECT_FALSE(ParseSparseLibrary("accelerate_sparse", &library));
  Solver solver;
  EXPECT_TRUE(ParseSolver("gauss_newton", &solver));
  EXPECT_EQ(solver, Solver::kGaussNewton);
  EXPECT_TRUE(ParseSolver("ceres", &solver));
  EXPECT_EQ(solver, Solver::kCeres);
  EXPECT_FALSE(ParseSolver("lbfgs", &solver));
}

}  // namespace
}  // namespace msdeform
