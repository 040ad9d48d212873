#include "msdeform/methods/rigid_cells.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "msdeform/core/parallel.h"
#include "msdeform/core/timing.h"
#include "msdeform/energies/rigid_cell_coupling_cost.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/solvers/subspace_arap.h"

namespace msdeform {
namespace {

using Clock = std::chrono::steady_clock;

// Vertices per task of the RBF evaluation (each costs #cells kernel terms).
constexpr int64_t kVerticesPerChunk = 256;

// phi(r) = r^3, the triharmonic kernel in 3D.
inline double Kernel(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double r = (a - b).norm();
  return r * r * r;
}

// Below this reciprocal condition number the RBF system is taken as singular.
constexpr double kMinRbfReciprocalCondition = 1e-15;

// The principal axes of the centres (about their mean, the origin) whose
// spread is above 1e-6 of the largest (an axis kept at spread e makes the
// system's condition about 1/e^2): three for a solid, two for centres in
// a plane, one on a line, none for one centre. Three are returned as x, y, z.
Eigen::Matrix3Xd PolynomialAxes(const Eigen::Matrix3Xd& centres) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(centres * centres.transpose());
  const Eigen::Vector3d spread = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  std::vector<int> kept;
  for (int a = 2; a >= 0; --a) {
    if (spread(a) > 1e-6 * spread(2)) kept.push_back(a);
  }
  if (kept.size() == 3) return Eigen::Matrix3d::Identity();
  Eigen::Matrix3Xd axes(3, kept.size());
  for (size_t i = 0; i < kept.size(); ++i) axes.col(i) = eigen.eigenvectors().col(kept[i]);
  return axes;
}

}  // namespace

bool RigidCellsOptions::Check(std::string* error) const {
  if (!(cells_per_diagonal >= 2.0 && cells_per_diagonal <= 64.0)) {
    *error = "rigid_cells.cells_per_diagonal=" + std::to_string(cells_per_diagonal) +
             ": expected a number in [2, 64]";
    return false;
  }
  if (max_cells < 1 || max_cells > 20000) {
    *error = "rigid_cells.max_cells=" + std::to_string(max_cells) +
             ": expected an integer in [1, 20000]";
    return false;
  }
  std::string solver_error;
  if (!solver.IsValid(&solver_error)) {
    *error = "rigid_cells.solver: " + solver_error;
    return false;
  }
  return true;
}

ceres::Solver::Options RigidCellsOptions::DefaultSolverOptions() {
  ceres::Solver::Options solver;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solver.max_num_iterations = 50;
  solver.function_tolerance = 1e-10;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-14;
  solver.logging_type = ceres::SILENT;
  return solver;
}

Eigen::Affine3d RigidCells::cell_transform(int cell) const {
  const Eigen::Quaterniond q(rotations_(3, cell), rotations_(0, cell), rotations_(1, cell),
                             rotations_(2, cell));
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  transform.linear() = q.toRotationMatrix();
  transform.translation() =
      positions_.col(cell) - transform.linear() * lattice_.rest_positions().col(cell);
  return transform;
}

bool RigidCells::DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) {
  const auto start = Clock::now();
  precompute_stages_ = StageTimes();
  stages_ = StageTimes();
  if (!options.rigid_cells.Check(error)) return false;
  options_ = options.rigid_cells;
  num_threads_ = options.deformer.num_threads;
  if (!ValidateMesh(mesh, error)) return false;
  {
    ScopedStage stage(&precompute_stages_, "precompute.lattice");
    LatticeOptions lattice_options = options.deformer.lattice;
    lattice_options.cells_per_diagonal = options_.cells_per_diagonal;
    if (!Lattice::Build(mesh, lattice_options, &lattice_, error)) return false;
  }
  const int n = lattice_.num_particles();
  if (n > options_.max_cells) {
    *error = "rigid_cells: the lattice has " + std::to_string(n) +
             " cells, more than rigid_cells.max_cells=" + std::to_string(options_.max_cells) +
             " (the dense RBF system); lower rigid_cells.cells_per_diagonal";
    return false;
  }
  // The RBF centres: a surface piece's vertex centroid, an interior cell's centre.
  rbf_centres_ = lattice_.rest_positions();
  const CompressedLists& vertices_of = lattice_.vertices_of_particle();
  for (int p = 0; p < lattice_.num_surface_particles(); ++p) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int* v = vertices_of.begin(p); v != vertices_of.end(p); ++v) {
      sum += mesh.vertices.col(*v);
    }
    if (vertices_of.size(p) > 0) rbf_centres_.col(p) = sum / vertices_of.size(p);
  }
  {
    // [Phi P; P^T 0] on centres shifted to their mean and scaled by the
    // lattice's extent (conditioning), factorised once.
    ScopedStage stage(&precompute_stages_, "precompute.rbf_factorization");
    rbf_origin_ = rbf_centres_.rowwise().mean();
    rbf_scale_ = std::max(lattice_.cell_width() * lattice_.dims().maxCoeff(), 1e-300);
    const Eigen::Matrix3Xd centres = (rbf_centres_.colwise() - rbf_origin_) / rbf_scale_;
    rbf_axes_ = PolynomialAxes(centres);
    const int r = static_cast<int>(rbf_axes_.cols());
    const Eigen::MatrixXd along_axes = rbf_axes_.transpose() * centres;  // r by n
    rbf_matrix_ = Eigen::MatrixXd::Zero(n + 1 + r, n + 1 + r);
    for (int j = 0; j < n; ++j) {
      for (int i = j + 1; i < n; ++i) {
        rbf_matrix_(i, j) = rbf_matrix_(j, i) = Kernel(centres.col(i), centres.col(j));
      }
      rbf_matrix_(n, j) = rbf_matrix_(j, n) = 1.0;
      for (int a = 0; a < r; ++a) {
        rbf_matrix_(n + 1 + a, j) = rbf_matrix_(j, n + 1 + a) = along_axes(a, j);
      }
    }
    rbf_lu_.compute(rbf_matrix_);
    // Distinct centres in general position make the system non-singular (the
    // kernel is conditionally positive definite of order 2); coinciding
    // centres do not.
    if (!(rbf_lu_.rcond() > kMinRbfReciprocalCondition)) {
      *error = "rigid_cells: the RBF system of the " + std::to_string(n) +
               " cell centres is singular or nearly (reciprocal condition " +
               std::to_string(rbf_lu_.rcond()) + "): two centres coincide or nearly";
      return false;
    }
  }
  mesh_ = mesh;
  deformed_vertices_ = mesh.vertices;
  kind_.assign(n, Kind::kFree);
  num_free_ = n;
  rotations_ = Eigen::Matrix4Xd::Zero(4, n);
  rotations_.row(3).setOnes();
  positions_ = lattice_.rest_positions();
  problem_.reset();
  stages_ = precompute_stages_;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool RigidCells::DoSetHandles(const HandleLayout& layout, std::string* error) {
  const auto start = Clock::now();
  StageTimes layout_stages;
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  // Each handle group drives the cells of its vertices; a cell holding a
  // fixed vertex stays at rest.
  if (!HandleGroupOfParticles(lattice_, layout, &driven_group_, error)) return false;
  const int n = lattice_.num_particles();
  kind_.assign(n, Kind::kFree);
  for (int p = 0; p < n; ++p) {
    kind_[p] = driven_group_[p] == kFixedParticle ? Kind::kFixed
               : driven_group_[p] >= 0            ? Kind::kDriven
                                                  : Kind::kFree;
  }
  num_free_ = static_cast<int>(std::count(kind_.begin(), kind_.end(), Kind::kFree));
  vertex_kind_.assign(mesh_.num_vertices(), static_cast<char>(Kind::kFree));
  vertex_group_.assign(mesh_.num_vertices(), -1);
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    vertex_kind_[layout.moveable[i]] = static_cast<char>(Kind::kDriven);
    vertex_group_[layout.moveable[i]] = layout.group_of(i);
  }
  for (int v : layout.fixed) vertex_kind_[v] = static_cast<char>(Kind::kFixed);
  rotations_ = Eigen::Matrix4Xd::Zero(4, n);
  rotations_.row(3).setOnes();
  positions_ = lattice_.rest_positions();
  {
    // One coupling term per neighbouring pair with a free cell; every block
    // in the problem, the driven and fixed ones constant.
    ScopedStage stage(&layout_stages, "layout.problem");
    problem_ = std::make_unique<ceres::Problem>();
    ceres::Manifold* quaternion = new ceres::EigenQuaternionManifold;  // owned by the problem
    for (int k = 0; k < n; ++k) {
      problem_->AddParameterBlock(rotations_.col(k).data(), 4, quaternion);
      problem_->AddParameterBlock(positions_.col(k).data(), 3);
    }
    const Eigen::Matrix3Xd& rest = lattice_.rest_positions();
    const CompressedLists& adjacency = lattice_.particle_adjacency();
    for (int i = 0; i < n; ++i) {
      for (const int* j = adjacency.begin(i); j != adjacency.end(i); ++j) {
        if (*j < i || (kind_[i] != Kind::kFree && kind_[*j] != Kind::kFree)) continue;
        problem_->AddResidualBlock(
            RigidCellCouplingCost::CreateForCubes(rest.col(i), rest.col(*j),
                                                  lattice_.cell_width()),
            nullptr, rotations_.col(i).data(), positions_.col(i).data(),
            rotations_.col(*j).data(), positions_.col(*j).data());
      }
    }
    for (int k = 0; k < n; ++k) {
      if (kind_[k] == Kind::kFree) continue;
      problem_->SetParameterBlockConstant(rotations_.col(k).data());
      problem_->SetParameterBlockConstant(positions_.col(k).data());
    }
  }
  deformed_vertices_ = mesh_.vertices;
  constraint_gap_ = 0.0;
  stages_ = precompute_stages_;
  stages_.Append(layout_stages);
  setup_ms_ = MillisecondsSince(start);
  return true;
}

bool RigidCells::DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                        std::string* error) {
  const auto frame_start = Clock::now();
  *stats = MethodStats();
  const Eigen::Matrix3Xd& rest = lattice_.rest_positions();
  // The driven cells' rotation: their handle's, or for a handle that scales
  // or shears, the rotation nearest its linear part (its polar factor).
  std::vector<Eigen::Quaterniond> handle_rotation;
  for (int g = 0; g < std::max(1, deformed_from_rest.size()); ++g) {
    handle_rotation.emplace_back(BestRotation(deformed_from_rest[g].linear()));
  }
  for (int k = 0; k < lattice_.num_particles(); ++k) {
    if (kind_[k] != Kind::kDriven) continue;
    const int g = driven_group_[k];
    rotations_.col(k) = handle_rotation[deformed_from_rest.size() == 1 ? 0 : g].coeffs();
    positions_.col(k) = deformed_from_rest[g] * rest.col(k);
  }
  ceres::Solver::Options solver = options_.solver;
  solver.num_threads = std::max(1, num_threads_);
  stats->initial_cost = stats->final_cost = 0.0;
  stats->converged = true;
  if (num_free_ > 0 && problem_->NumResidualBlocks() > 0) {
    ceres::Solver::Summary summary;
    ceres::Solve(solver, problem_.get(), &summary);
    if (summary.termination_type == ceres::FAILURE) {
      *error = "rigid_cells: the Ceres solve failed: " + summary.message;
      return false;
    }
    stats->iterations = static_cast<int>(summary.iterations.size()) - 1;
    stats->factorizations = summary.num_linear_solves;
    stats->initial_cost = summary.initial_cost;
    stats->final_cost = summary.final_cost;
    stats->converged = summary.termination_type == ceres::CONVERGENCE;
  }
  stats->iterations = std::max(stats->iterations, 1);  // the RBF step at least
  stats->solve_ms = MillisecondsSince(frame_start);
  const auto skin_start = Clock::now();
  Interpolate(deformed_from_rest);
  stats->skin_ms = MillisecondsSince(skin_start);
  if (!deformed_vertices_.allFinite()) {
    *error = "rigid_cells produced non-finite positions";
    return false;
  }
  stats->frame_ms = MillisecondsSince(frame_start);
  return true;
}

void RigidCells::Interpolate(const HandleTransforms& deformed_from_rest) {
  const int n = lattice_.num_particles();
  // Right-hand sides: each centre's displacement T_k(r_k) - r_k, then the
  // polynomial's zero rows (one and one an axis).
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(rbf_matrix_.rows(), 3);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d r = rbf_centres_.col(k);
    // A driven cell moves with the handle itself, which need not be rigid.
    const Eigen::Vector3d moved =
        kind_[k] == Kind::kDriven ? Eigen::Vector3d(deformed_from_rest[driven_group_[k]] * r)
                                  : cell_transform(k) * r;
    rhs.row(k) = (moved - r).transpose();
  }
  Eigen::MatrixXd coefficients = rbf_lu_.solve(rhs);
  coefficients += rbf_lu_.solve(rhs - rbf_matrix_ * coefficients);  // one refinement step
  const Eigen::Matrix3Xd centres = (rbf_centres_.colwise() - rbf_origin_) / rbf_scale_;
  const Eigen::Matrix3Xd weights = coefficients.topRows(n).transpose();
  const Eigen::Vector3d constant = coefficients.row(n).transpose();
  // The linear part over the axes: B (A^T x), folded into one 3 by 3 map.
  const Eigen::Matrix3d linear =
      coefficients.middleRows(n + 1, rbf_axes_.cols()).transpose() * rbf_axes_.transpose();
  const int num_vertices = mesh_.num_vertices();
  std::vector<double> chunk_gap(NumChunks(num_vertices, kVerticesPerChunk), 0.0);
  ForEachChunk(num_vertices, kVerticesPerChunk,
               ThreadsFor(num_threads_, static_cast<int64_t>(num_vertices) * n),
               [&](int64_t begin, int64_t end, int64_t chunk) {
                 for (int64_t v = begin; v < end; ++v) {
                   const Eigen::Vector3d x0 = mesh_.vertices.col(v);
                   const Eigen::Vector3d x = (x0 - rbf_origin_) / rbf_scale_;
                   Eigen::Vector3d u = constant + linear * x;
                   for (int k = 0; k < n; ++k) u += Kernel(x, centres.col(k)) * weights.col(k);
                   const Eigen::Vector3d interpolated = x0 + u;
                   const Kind kind = static_cast<Kind>(vertex_kind_[v]);
                   if (kind == Kind::kFree) {
                     deformed_vertices_.col(v) = interpolated;
                     continue;
                   }
                   const Eigen::Vector3d target =
                       kind == Kind::kFixed
                           ? x0
                           : Eigen::Vector3d(deformed_from_rest[vertex_group_[v]] * x0);
                   chunk_gap[chunk] = std::max(chunk_gap[chunk], (interpolated - target).norm());
                   deformed_vertices_.col(v) = target;
                 }
               });
  constraint_gap_ = 0.0;
  for (double gap : chunk_gap) constraint_gap_ = std::max(constraint_gap_, gap);
}

MSDEFORM_REGISTER_METHODS(rigid_cells, registry) {
  MethodDescriptor rigid_cells;
  rigid_cells.name = "rigid_cells";
  rigid_cells.energy = "rigid_cells";
  // Its own cells_per_diagonal replaces the lattice's (RigidCellsOptions).
  rigid_cells.deformer_rows = {"lattice.cell_width", "lattice.max_grid_cells",
                               "lattice.split_cells", "lattice.piece_margin", "num_threads"};
  rigid_cells.create = [] { return std::make_unique<RigidCells>(); };
  registry->push_back(std::move(rigid_cells));
}

}  // namespace msdeform
