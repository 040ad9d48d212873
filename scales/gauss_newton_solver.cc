#include "scales/gauss_newton_solver.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <glog/logging.h>
#ifdef MSDEFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "energies/gauge_cost.h"

namespace msdeform {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Vector12d = Eigen::Matrix<double, 12, 1>;

// The 12 numbers tau of a handle transform: matrix column-major, translation.
Vector12d HandleParameters(const Eigen::Affine3d& handle) {
  Vector12d tau;
  Eigen::Map<Eigen::Matrix3d>(tau.data()) = handle.linear();
  tau.tail<3>() = handle.translation();
  return tau;
}

// Rot residuals (Eq. 12) of R (9 doubles, column-major) scaled by s; with
// jacobian != nullptr also the 6x9 Jacobian.
void RotResiduals(const double* R, double s, double* residuals,
                  Eigen::Matrix<double, 6, 9>* jacobian) {
  static constexpr int kFirst[6] = {0, 0, 1, 0, 1, 2};
  static constexpr int kSecond[6] = {1, 2, 2, 0, 1, 2};
  for (int r = 0; r < 6; ++r) {
    const double* a = R + 3 * kFirst[r];
    const double* b = R + 3 * kSecond[r];
    residuals[r] = s * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] - (r >= 3 ? 1.0 : 0.0));
  }
  if (jacobian == nullptr) return;
  jacobian->setZero();
  for (int r = 0; r < 6; ++r) {
    const int a = kFirst[r], b = kSecond[r];
    for (int i = 0; i < 3; ++i) {
      (*jacobian)(r, a * 3 + i) += s * R[b * 3 + i];
      (*jacobian)(r, b * 3 + i) += s * R[a * 3 + i];
    }
  }
}

// Position of `index` in the column `col` of a compressed matrix.
int ValueIndex(const SparseMatrix& matrix, int row, int col) {
  const int* begin = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col];
  const int* end = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col + 1];
  const int* found = std::lower_bound(begin, end, row);
  CHECK(found != end && *found == row) << "entry (" << row << ", " << col << ") not in pattern";
  return static_cast<int>(found - matrix.innerIndexPtr());
}

}  // namespace

int DeformationEnergy::num_variables() const {
  int variables = 0;
  for (NodeClass c : node_class)
    variables += c == NodeClass::kTotallyFree ? 12 : c == NodeClass::kHalfFree ? 9 : 0;
  return variables;
}

std::vector<DeformationEnergy::Gauge> GaugeTerms(const DeformationEnergy& energy) {
  std::vector<DeformationEnergy::Gauge> gauge;
  if (!(energy.sqrt_rot > 0.0)) return gauge;
  const int num_nodes = static_cast<int>(energy.node_class.size());
  std::vector<Eigen::Matrix3d> scatter(num_nodes, Eigen::Matrix3d::Zero());
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    const Eigen::Vector3d u = term.sqrt_weight * term.edge;
    scatter[term.j] += u * u.transpose();
  }
  for (const DeformationEnergy::Position& term : energy.positions) {
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const Eigen::Vector3d u = term.sqrt_weight * term.terms[i].weight * term.terms[i].offset;
      scatter[term.nodes[i]] += u * u.transpose();
    }
  }
  for (int j : energy.rot_nodes) {
    if (energy.node_class[j] == NodeClass::kFixed) continue;
    const Eigen::Matrix3d& S = scatter[j];
    if (S.trace() == 0.0) {
      for (int axis = 0; axis < 3; ++axis)
        gauge.push_back({j, Eigen::Vector3d::Unit(axis), energy.sqrt_rot});
      continue;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(S);
    const Eigen::Vector3d lambda = eigen.eigenvalues();  // ascending
    if (lambda[1] <= 1e-12 * lambda[2])
      gauge.push_back({j, eigen.eigenvectors().col(2).normalized(), energy.sqrt_rot});
  }
  return gauge;
}

double EvaluateEnergy(const DeformationEnergy& energy, const NodeTransforms& transforms,
                      const Eigen::Affine3d& handle) {
  double sum = 0.0;
  for (int j : energy.rot_nodes) {
    double r[6];
    RotResiduals(transforms.rotations.col(j).data(), energy.sqrt_rot, r, nullptr);
    for (double value : r) sum += value * value;
  }
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    const Eigen::Vector3d r =
        term.sqrt_weight * (transforms.rotation(term.j) * term.edge - term.edge +
                            transforms.translations.col(term.j) -
                            transforms.translations.col(term.k));
    sum += r.squaredNorm();
  }
  for (const DeformationEnergy::Position& term : energy.positions) {
    Eigen::Vector3d skinned = term.follows_handle ? Eigen::Vector3d(-(handle * term.rest))
                                                  : Eigen::Vector3d(-term.rest);
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const int j = term.nodes[i];
      skinned += term.terms[i].weight * (transforms.rotation(j) * term.terms[i].offset +
                                         term.terms[i].position + transforms.translations.col(j));
    }
    sum += (term.sqrt_weight * skinned).squaredNorm();
  }
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    const double r = GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight)
                         .dot(transforms.rotations.col(term.node));
    sum += r * r;
  }
  return 0.5 * sum;
}

bool GaussNewtonOptions::Check(std::string* error) const {
  if (max_iterations < 0) {
    *error = "Gauss-Newton max_iterations must be >= 0";
    return false;
  }
  for (double tolerance : {function_tolerance, gradient_tolerance, parameter_tolerance}) {
    if (!(tolerance >= 0.0)) {
      *error = "Gauss-Newton tolerances must be >= 0";
      return false;
    }
  }
  if (!(min_damping > 0.0)) {
    *error = "Gauss-Newton min_damping must be > 0";
    return false;
  }
  return true;
}

bool GaussNewtonHasCholmod() {
#ifdef MSDEFORM_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

struct GaussNewtonSolver::Impl {
  GaussNewtonOptions options;
  std::vector<int> offset;  // first variable of node j, or -1
  std::vector<char> totally_free;  // node j has t among the variables
  std::vector<int> rot_nodes;
  double sqrt_rot = 1.0;
  SparseMatrix hessian;        // H = A^T A (linear terms only)
  Eigen::VectorXd linear_gradient;  // A^T c
  SparseMatrix handle_gradient;     // A^T P, #variables by 12
  Eigen::Matrix<double, 13, 13> constant_gram;  // [-P c]^T [-P c]
  SparseMatrix system;              // pattern of J^T J, full (both triangles)
  std::vector<double> base_values;  // H on that pattern
  std::vector<int> rot_value_index;  // 81 per rot node, column-major 9x9
  std::vector<int> diagonal_index;   // per variable
  bool factor_valid = false;        // a factorisation from an earlier iteration exists
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
#ifdef MSDEFORM_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholmod;
#endif

  GaussNewtonOptions::LinearSolver Backend() const {
#ifdef MSDEFORM_HAVE_CHOLMOD
    return options.linear_solver;
#else
    return options.linear_solver == GaussNewtonOptions::LinearSolver::kCholmod
               ? GaussNewtonOptions::LinearSolver::kEigenLLT
               : options.linear_solver;
#endif
  }

  void Analyze() {
    switch (Backend()) {
      case GaussNewtonOptions::LinearSolver::kEigenLLT:
        llt.analyzePattern(system);
        break;
      case GaussNewtonOptions::LinearSolver::kEigenLDLT:
        ldlt.analyzePattern(system);
        break;
      case GaussNewtonOptions::LinearSolver::kCholmod:
#ifdef MSDEFORM_HAVE_CHOLMOD
        cholmod.analyzePattern(system);
#endif
        break;
    }
  }

  // Numeric factorisation of `system`; false when it is not (numerically)
  // positive definite.
  bool Factorize() {
    switch (Backend()) {
      case GaussNewtonOptions::LinearSolver::kEigenLLT:
        llt.factorize(system);
        return llt.info() == Eigen::Success;
      case GaussNewtonOptions::LinearSolver::kEigenLDLT:
        ldlt.factorize(system);
        return ldlt.info() == Eigen::Success && (ldlt.vectorD().array() > 0.0).all();
      case GaussNewtonOptions::LinearSolver::kCholmod:
#ifdef MSDEFORM_HAVE_CHOLMOD
        cholmod.factorize(system);
        return cholmod.info() == Eigen::Success;
#endif
        break;
    }
    return false;
  }

  // Solves with the last factorisation.
  bool SolveFactored(const Eigen::VectorXd& rhs, Eigen::VectorXd* delta) {
    switch (Backend()) {
      case GaussNewtonOptions::LinearSolver::kEigenLLT:
        *delta = llt.solve(rhs);
        break;
      case GaussNewtonOptions::LinearSolver::kEigenLDLT:
        *delta = ldlt.solve(rhs);
        break;
      case GaussNewtonOptions::LinearSolver::kCholmod:
#ifdef MSDEFORM_HAVE_CHOLMOD
        *delta = cholmod.solve(rhs);
#endif
        break;
    }
    return delta->allFinite();
  }

  // Rot cost at x; with gradient/blocks != nullptr also J_rot^T r (added to
  // *gradient) and J_rot^T J_rot per rot node (9x9 each).
  double RotCost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                 std::vector<Matrix9d>* blocks) const {
    double sum = 0.0;
    Eigen::Matrix<double, 6, 9> jacobian;
    Eigen::Matrix<double, 6, 1> r;
    for (size_t i = 0; i < rot_nodes.size(); ++i) {
      const int o = offset[rot_nodes[i]];
      RotResiduals(x.data() + o, sqrt_rot, r.data(), gradient != nullptr ? &jacobian : nullptr);
      sum += r.squaredNorm();
      if (gradient != nullptr) {
        gradient->segment<9>(o) += jacobian.transpose() * r;
        (*blocks)[i].noalias() = jacobian.transpose() * jacobian;
      }
    }
    return 0.5 * sum;
  }
};

GaussNewtonSolver::GaussNewtonSolver() = default;
GaussNewtonSolver::~GaussNewtonSolver() = default;

bool GaussNewtonSolver::Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
                              const GaussNewtonOptions& options, std::string* error) {
  if (!options.Check(error)) return false;
  CHECK_EQ(static_cast<int>(energy.node_class.size()), transforms.num_nodes());
  impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  impl.options = options;
  const int num_nodes = transforms.num_nodes();
  impl.offset.assign(num_nodes, -1);
  impl.totally_free.assign(num_nodes, 0);
  int n = 0;
  for (int j = 0; j < num_nodes; ++j) {
    if (energy.node_class[j] == NodeClass::kFixed) continue;
    impl.offset[j] = n;
    impl.totally_free[j] = energy.node_class[j] == NodeClass::kTotallyFree;
    n += energy.node_class[j] == NodeClass::kTotallyFree ? 12 : 9;
  }
  num_variables_ = n;
  impl.sqrt_rot = energy.sqrt_rot;
  for (int j : energy.rot_nodes) {
    CHECK_GE(impl.offset[j], 0) << "Rot term on a Fixed node";
    impl.rot_nodes.push_back(j);
  }
  auto rotation_variable = [&](int j) { return impl.offset[j]; };
  auto translation_variable = [&](int j) {
    return energy.node_class[j] == NodeClass::kTotallyFree ? impl.offset[j] + 9 : -1;
  };

  // Linear residuals r = A x + c - P tau, row by row.
  std::vector<Eigen::Triplet<double, int>> a_entries, p_entries;
  std::vector<double> constant;
  int row = 0;
  auto add_rotation = [&](int j, const Eigen::Vector3d& vector, double scale) {
    // scale * R_j * vector into rows row..row+2.
    if (rotation_variable(j) >= 0) {
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
          a_entries.emplace_back(row + a, rotation_variable(j) + c * 3 + a, scale * vector[c]);
    } else {
      const Eigen::Vector3d value = scale * (transforms.rotation(j) * vector);
      for (int a = 0; a < 3; ++a) constant[row + a] += value[a];
    }
  };
  auto add_translation = [&](int j, double scale) {
    if (translation_variable(j) >= 0) {
      for (int a = 0; a < 3; ++a) a_entries.emplace_back(row + a, translation_variable(j) + a, scale);
    } else {
      for (int a = 0; a < 3; ++a) constant[row + a] += scale * transforms.translations(a, j);
    }
  };
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    constant.resize(row + 3, 0.0);
    add_rotation(term.j, term.edge, term.sqrt_weight);
    for (int a = 0; a < 3; ++a) constant[row + a] -= term.sqrt_weight * term.edge[a];
    add_translation(term.j, term.sqrt_weight);
    add_translation(term.k, -term.sqrt_weight);
    row += 3;
  }
  for (const DeformationEnergy::Position& term : energy.positions) {
    constant.resize(row + 3, 0.0);
    const double s = term.sqrt_weight;
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const SkinningTerm& skin = term.terms[i];
      add_rotation(term.nodes[i], skin.offset, s * skin.weight);
      for (int a = 0; a < 3; ++a) constant[row + a] += s * skin.weight * skin.position[a];
      add_translation(term.nodes[i], s * skin.weight);
    }
    if (term.follows_handle) {
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) p_entries.emplace_back(row + a, c * 3 + a, s * term.rest[c]);
        p_entries.emplace_back(row + a, 9 + a, s);
      }
    } else {
      for (int a = 0; a < 3; ++a) constant[row + a] -= s * term.rest[a];
    }
    row += 3;
  }
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    // Linear in R with no constant: one row of A.
    CHECK_GE(rotation_variable(term.node), 0) << "gauge term on a Fixed node";
    constant.resize(row + 1, 0.0);
    const Eigen::Matrix<double, 1, 9> jacobian =
        GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight);
    for (int i = 0; i < 9; ++i) {
      if (jacobian[i] != 0.0)
        a_entries.emplace_back(row, rotation_variable(term.node) + i, jacobian[i]);
    }
    row += 1;
  }
  SparseMatrix a_matrix(row, n), p_matrix(row, 13);
  a_matrix.setFromTriplets(a_entries.begin(), a_entries.end());
  for (int r = 0; r < row; ++r) {
    if (constant[r] != 0.0) p_entries.emplace_back(r, 12, -constant[r]);
  }
  // p_matrix = [P, -c]: the residual is A x - p_matrix [tau; 1].
  p_matrix.setFromTriplets(p_entries.begin(), p_entries.end());
  const SparseMatrix a_transposed = a_matrix.transpose();
  impl.hessian = (a_transposed * a_matrix).pruned();
  const SparseMatrix atp = a_transposed * p_matrix;  // n by 13
  impl.handle_gradient = atp.leftCols(12);
  impl.linear_gradient = -Eigen::VectorXd(atp.col(12));
  impl.constant_gram = Eigen::MatrixXd(SparseMatrix(p_matrix.transpose() * p_matrix));

  // The pattern of J^T J: H plus the 9x9 rotation blocks plus the diagonal.
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(impl.hessian.nonZeros() + 81 * impl.rot_nodes.size() + n);
  for (int col = 0; col < n; ++col)
    for (SparseMatrix::InnerIterator it(impl.hessian, col); it; ++it)
      entries.emplace_back(it.row(), col, it.value());
  for (int j : impl.rot_nodes)
    for (int c = 0; c < 9; ++c)
      for (int r = 0; r < 9; ++r) entries.emplace_back(impl.offset[j] + r, impl.offset[j] + c, 0.0);
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, 0.0);
  impl.system.resize(n, n);
  impl.system.setFromTriplets(entries.begin(), entries.end());
  impl.system.makeCompressed();
  impl.base_values.assign(impl.system.valuePtr(), impl.system.valuePtr() + impl.system.nonZeros());
  impl.rot_value_index.clear();
  for (int j : impl.rot_nodes)
    for (int c = 0; c < 9; ++c)
      for (int r = 0; r < 9; ++r)
        impl.rot_value_index.push_back(
            ValueIndex(impl.system, impl.offset[j] + r, impl.offset[j] + c));
  impl.diagonal_index.resize(n);
  for (int i = 0; i < n; ++i) impl.diagonal_index[i] = ValueIndex(impl.system, i, i);
  if (n > 0) impl.Analyze();
  return true;
}

GaussNewtonSummary GaussNewtonSolver::Solve(const Eigen::Affine3d& handle,
                                            NodeTransforms* transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  Impl& impl = *impl_;
  GaussNewtonSummary summary;
  const int n = num_variables_;
  const int num_nodes = transforms->num_nodes();
  CHECK_EQ(static_cast<int>(impl.offset.size()), num_nodes);

  // Gather x.
  Eigen::VectorXd x(n);
  for (int j = 0; j < num_nodes; ++j) {
    const int o = impl.offset[j];
    if (o < 0) continue;
    x.segment<9>(o) = transforms->rotations.col(j);
    if (impl.totally_free[j]) x.segment<3>(o + 9) = transforms->translations.col(j);
  }

  Eigen::Matrix<double, 13, 1> tau1;
  tau1.head<12>() = HandleParameters(handle);
  tau1[12] = 1.0;
  const Eigen::VectorXd g0 = impl.linear_gradient - impl.handle_gradient * tau1.head<12>();
  const double kappa = tau1.dot(impl.constant_gram * tau1);

  Eigen::VectorXd hx = impl.hessian * x;
  double linear_cost = 0.5 * (x.dot(hx) + 2.0 * g0.dot(x) + kappa);
  std::vector<Matrix9d> blocks(impl.rot_nodes.size());
  Eigen::VectorXd gradient = hx + g0;
  double cost = linear_cost + impl.RotCost(x, &gradient, &blocks);
  summary.initial_cost = cost;

  double mu = impl.options.min_damping;
  Eigen::VectorXd delta, x_new, h_delta;
  double* values = impl.system.valuePtr();
  bool done = n == 0;
  double gradient_norm = gradient.lpNorm<Eigen::Infinity>();
  if (!done && gradient_norm <= impl.options.gradient_tolerance) {
    summary.converged = true;
    summary.message = "gradient tolerance";
    done = true;
  }
  using Reuse = GaussNewtonOptions::HessianReuse;
  bool need_factor = !impl.factor_valid || impl.options.hessian_reuse != Reuse::kLagged;
  bool fresh = false;  // the factorisation is of J^T J at the current x and mu
  while (!done && summary.iterations < impl.options.max_iterations) {
    if (need_factor) {
      std::copy(impl.base_values.begin(), impl.base_values.end(), values);
      const int* index = impl.rot_value_index.data();
      for (const Matrix9d& block : blocks) {
        for (int k = 0; k < 81; ++k) values[index[k]] += block.data()[k];
        index += 81;
      }
      for (int i = 0; i < n; ++i) {
        double& diagonal = values[impl.diagonal_index[i]];
        diagonal += mu * std::min(std::max(diagonal, 1e-6), 1e32);
      }
      ++summary.factorizations;
      need_factor = false;
      impl.factor_valid = impl.Factorize();
      fresh = true;
      if (!impl.factor_valid) {
        ++summary.iterations;
        mu *= 10.0;
        need_factor = true;
        if (mu > 1e32) {
          summary.message = "the damped normal equations could not be factorised";
          break;
        }
        continue;
      }
    }
    ++summary.iterations;
    if (!impl.SolveFactored(-gradient, &delta)) {
      impl.factor_valid = false;
      need_factor = true;
      if (fresh) mu *= 10.0;
      continue;
    }
    if (delta.norm() <= impl.options.parameter_tolerance *
                            (x.norm() + impl.options.parameter_tolerance)) {
      summary.converged = true;
      summary.message = "parameter tolerance";
      break;
    }
    x_new = x + delta;
    h_delta = impl.hessian * delta;
    const double new_linear_cost = linear_cost + delta.dot(hx + g0) + 0.5 * delta.dot(h_delta);
    const double new_cost = new_linear_cost + impl.RotCost(x_new, nullptr, nullptr);
    if (new_cost < cost) {
      const double decrease = cost - new_cost;
      x.swap(x_new);
      hx += h_delta;
      linear_cost = new_linear_cost;
      gradient = hx + g0;
      cost = linear_cost + impl.RotCost(x, &gradient, &blocks);
      mu = std::max(mu / 10.0, impl.options.min_damping);
      const double new_gradient_norm = gradient.lpNorm<Eigen::Infinity>();
      if (decrease <= impl.options.function_tolerance * (cost + decrease)) {
        summary.converged = true;
        summary.message = "function tolerance";
        break;
      }
      if (new_gradient_norm <= impl.options.gradient_tolerance) {
        summary.converged = true;
        summary.message = "gradient tolerance";
        break;
      }
      fresh = false;
      // Pure Gauss-Newton refactorises every iteration; the lagged variants
      // keep the factorisation while the gradient shrinks at least 4x a step.
      need_factor = impl.options.hessian_reuse == Reuse::kEveryIteration ||
                    new_gradient_norm > 0.25 * gradient_norm;
      gradient_norm = new_gradient_norm;
    } else {
      // A stale factorisation is refreshed first; a fresh one is damped more.
      if (fresh) mu *= 10.0;
      need_factor = true;
    }
  }
  if (!done && summary.message.empty()) summary.message = "iteration cap";
  summary.final_cost = cost;

  // Scatter x.
  for (int j = 0; j < num_nodes; ++j) {
    const int o = impl.offset[j];
    if (o < 0) continue;
    transforms->rotations.col(j) = x.segment<9>(o);
    if (impl.totally_free[j]) transforms->translations.col(j) = x.segment<3>(o + 9);
  }
  return summary;
}

}  // namespace msdeform
