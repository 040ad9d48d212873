#include "msdeform/scales/gauss_newton_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>

#include <Eigen/Householder>
#include <Eigen/QR>
#include <glog/logging.h>

#include "msdeform/energies/gauge_cost.h"
#include "msdeform/energies/rot_cost.h"
#include "msdeform/scales/gauss_newton_linear_solver.h"
#include "msdeform/scales/gauss_newton_terms.h"

namespace msdeform {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Factorization = GaussNewtonOptions::Factorization;
using Damping = GaussNewtonOptions::Damping;

// The 12 numbers tau of a handle transform: matrix column-major, translation.
Vector12d HandleParameters(const Eigen::Affine3d& handle) {
  Vector12d tau;
  Eigen::Map<Eigen::Matrix3d>(tau.data()) = handle.linear();
  tau.tail<3>() = handle.translation();
  return tau;
}

// [tau; 1].
Eigen::Matrix<double, 13, 1> HandleParametersAndOne(const Eigen::Affine3d& handle) {
  Eigen::Matrix<double, 13, 1> tau1;
  tau1.head<12>() = HandleParameters(handle);
  tau1[12] = 1.0;
  return tau1;
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

struct GaussNewtonSolver::Impl {
  GaussNewtonOptions options;
  std::vector<int> offset;  // first variable of node j, or -1
  std::vector<char> totally_free;  // node j has t among the variables
  std::vector<int> rot_nodes;
  double sqrt_rot = 1.0;
  SparseMatrix hessian;        // H = A^T A (linear terms only)
  Eigen::VectorXd linear_gradient;  // A^T c
  SparseMatrix handle_gradient;     // A^T P, #variables by 12
  // The linear residuals in a compressed form that keeps their sum of
  // squares: |root x + root_handle [tau; 1]|^2 = |A x + c - P tau|^2. The
  // Coherence and gauge rows of A as they are; per group of position terms
  // with the same variable nodes, the triangular factor of a QR of their rows.
  // The cost is evaluated from these residuals, not from H, g0 and a Gram
  // matrix of the constant: that expanded form loses about 1e-16 of
  // |c - P tau|^2, which grows with the handle's size and its distance from
  // the origin (4e-7 of the energy on the 416K claw).
  RowSparseMatrix root;         // m by #variables
  RowSparseMatrix root_handle;  // m by 13
  SparseMatrix system;              // pattern of J^T J, full (both triangles)
  std::vector<double> base_values;  // H on that pattern
  std::vector<int> rot_value_index;  // 81 per rot node, column-major 9x9
  std::vector<int> diagonal_index;   // per variable
  // DeformationEnergy::terms: linear ones are rows of A; nonlinear ones write
  // term_values (their J^T J entries at the last evaluation with a gradient).
  GaussNewtonTerms terms;
  mutable std::vector<double> term_values;
  bool factor_valid = false;        // a factorisation from an earlier iteration exists
  // The last Solve ended wanting a new factorisation (its last step was
  // rejected, or did not shrink the gradient enough): a lagged factor is not
  // carried into the next frame then, so a small iteration budget cannot keep
  // reusing a factor that already failed.
  bool refactor_next = false;
  std::unique_ptr<GaussNewtonLinearSolver> linear_solver;  // gauss_newton_linear_solver.h
  double forcing_reference = 0.0;  // max |g_0| of the frame

  // Writes J^T J + mu D at the rotation blocks `blocks` into `system`.
  void Assemble(const std::vector<Matrix9d>& blocks, double mu) {
    double* values = system.valuePtr();
    std::copy(base_values.begin(), base_values.end(), values);
    const int* index = rot_value_index.data();
    for (const Matrix9d& block : blocks) {
      for (int k = 0; k < 81; ++k) values[index[k]] += block.data()[k];
      index += 81;
    }
    terms.AddValues(term_values, values);
    for (int index : diagonal_index) {
      double& diagonal = values[index];
      diagonal += mu * std::min(std::max(diagonal, 1e-6), 1e32);
    }
  }

  // The variables of `transforms`.
  Eigen::VectorXd Gather(const NodeTransforms& transforms) const {
    Eigen::VectorXd x(hessian.rows());
    for (int j = 0; j < static_cast<int>(offset.size()); ++j) {
      const int o = offset[j];
      if (o < 0) continue;
      x.segment<9>(o) = transforms.rotations.col(j);
      if (totally_free[j]) x.segment<3>(o + 9) = transforms.translations.col(j);
    }
    return x;
  }

  // g0 = A^T c - A^T P tau: the gradient of the linear terms at x = 0.
  Eigen::VectorXd HandleGradient(const Eigen::Affine3d& handle) const {
    return linear_gradient - handle_gradient * HandleParameters(handle);
  }

  // root_handle [tau; 1]: the frame's part of the compressed residuals.
  Eigen::VectorXd RootOffset(const Eigen::Affine3d& handle) const {
    return root_handle * HandleParametersAndOne(handle);
  }

  // 1/2 |A x + c - P tau|^2 from the compressed residuals (`offset`:
  // RootOffset of the frame): one pass over root's rows.
  double LinearCost(const Eigen::VectorXd& x, const Eigen::VectorXd& offset) const {
    const int* outer = root.outerIndexPtr();
    const int* inner = root.innerIndexPtr();
    const double* values = root.valuePtr();
    double sum = 0.0;
    for (int i = 0; i < root.rows(); ++i) {
      double residual = offset[i];
      for (int k = outer[i]; k < outer[i + 1]; ++k) residual += values[k] * x[inner[k]];
      sum += residual * residual;
    }
    return 0.5 * sum;
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

  // The nonlinear terms at x: Rot (its specialised 9x9 path, the numbers of
  // before the generic terms) plus DeformationEnergy::terms' nonlinear ones,
  // whose J^T J entries go to term_values.
  double NonlinearCost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                       std::vector<Matrix9d>* blocks) const {
    const double rot = RotCost(x, gradient, blocks);
    if (!terms.has_nonlinear()) return rot;
    return rot + terms.Cost(x, gradient, gradient != nullptr ? &term_values : nullptr);
  }
};

GaussNewtonSolver::GaussNewtonSolver(const GaussNewtonOptions& options,
                                     const StoppingRule& stopping)
    : options_(options), stopping_(stopping) {}
GaussNewtonSolver::~GaussNewtonSolver() = default;

bool GaussNewtonSolver::Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
                              std::string* error) {
  if (!options_.Check(error) || !stopping_.Check(error)) return false;
  CHECK_EQ(static_cast<int>(energy.node_class.size()), transforms.num_nodes());
  impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  impl.options = options_;
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
  if (!impl.terms.Setup(energy.terms, impl.offset, impl.totally_free, transforms, error))
    return false;
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
  // Position terms (one per handle vertex, and per held fixed vertex: a
  // hundred thousand on a 1.7M-vertex mesh) are not rows of A: their three
  // rows share one pattern, u_i = s w_i [o_i; 1] per node i (rotation column
  // c * 3 + a and translation a for coordinate a), so their products are
  // accumulated as 4x4 moments per node pair and expanded once below (I_3
  // Kronecker each moment). p = s [rest; 1] is the handle row's pattern.
  const int num_position_nodes = num_nodes;
  std::unordered_map<int64_t, Eigen::Matrix4d> pair_moment;        // sum u_j u_k^T
  std::vector<Eigen::Matrix4d> handle_moment;                      // sum u_j p^T
  std::vector<Eigen::Matrix<double, 4, 3>> constant_moment;        // sum u_j c^T
  // The terms' rows for the compressed residuals (Impl::root), grouped by
  // their variable nodes (sorted) and whether they follow the handle. A row
  // [u_1 .. u_k, p, c] (4 k + 7 numbers; u_i with 0 for a translation that
  // is not a variable) gives coordinate a's residual as
  //   row . [X_1a .. X_ka, -theta_a, e_a],
  // X_ia = (R_i(a, 0..2), t_i(a)), theta_a = (handle(a, 0..2), its translation(a)).
  struct PositionGroup {
    std::vector<int> nodes;
    std::vector<double> rows;  // row-major, 4 k + 7 wide
  };
  std::vector<PositionGroup> groups;
  std::map<std::vector<int>, int> group_of_key;
  std::vector<int> key, order;
  if (!energy.positions.empty()) {
    handle_moment.assign(num_position_nodes, Eigen::Matrix4d::Zero());
    constant_moment.assign(num_position_nodes, Eigen::Matrix<double, 4, 3>::Zero());
  }
  std::vector<int> variable_nodes;
  std::vector<Eigen::Vector4d> patterns;
  for (const DeformationEnergy::Position& term : energy.positions) {
    const double s = term.sqrt_weight;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    variable_nodes.clear();
    patterns.clear();
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const SkinningTerm& skin = term.terms[i];
      const int j = term.nodes[i];
      const double sw = s * skin.weight;
      if (rotation_variable(j) < 0) c += sw * (transforms.rotation(j) * skin.offset);
      if (translation_variable(j) < 0) c += sw * transforms.translations.col(j);
      c += sw * skin.position;
      if (rotation_variable(j) >= 0) {
        variable_nodes.push_back(j);
        patterns.push_back(sw * Eigen::Vector4d(skin.offset[0], skin.offset[1], skin.offset[2], 1.0));
      }
    }
    Eigen::Vector4d p = Eigen::Vector4d::Zero();
    if (term.follows_handle) {
      p << s * term.rest, s;
    } else {
      c -= s * term.rest;
    }
    order.resize(variable_nodes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return variable_nodes[a] < variable_nodes[b]; });
    key.assign(1, term.follows_handle ? 1 : 0);
    for (int i : order) key.push_back(variable_nodes[i]);
    auto [group, inserted] = group_of_key.try_emplace(key, static_cast<int>(groups.size()));
    if (inserted) groups.push_back({std::vector<int>(key.begin() + 1, key.end()), {}});
    std::vector<double>& rows = groups[group->second].rows;
    for (int i : order) {
      for (int e = 0; e < 4; ++e) {
        const bool variable = e < 3 || translation_variable(variable_nodes[i]) >= 0;
        rows.push_back(variable ? patterns[i][e] : 0.0);
      }
    }
    for (int e = 0; e < 4; ++e) rows.push_back(p[e]);
    for (int a = 0; a < 3; ++a) rows.push_back(c[a]);
    for (size_t i = 0; i < variable_nodes.size(); ++i) {
      const int j = variable_nodes[i];
      if (term.follows_handle) handle_moment[j].noalias() += patterns[i] * p.transpose();
      constant_moment[j].noalias() += patterns[i] * c.transpose();
      for (size_t k = 0; k < variable_nodes.size(); ++k) {
        const int64_t key = static_cast<int64_t>(j) * num_position_nodes + variable_nodes[k];
        auto [it, inserted] = pair_moment.try_emplace(key, Eigen::Matrix4d::Zero());
        it->second.noalias() += patterns[i] * patterns[k].transpose();
      }
    }
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
  impl.terms.AppendLinearRows(&a_entries, &constant, &row);
  SparseMatrix a_matrix(row, n), p_matrix(row, 13);
  a_matrix.setFromTriplets(a_entries.begin(), a_entries.end());
  for (int r = 0; r < row; ++r) {
    if (constant[r] != 0.0) p_entries.emplace_back(r, 12, -constant[r]);
  }
  // p_matrix = [P, -c]: the residual is A x - p_matrix [tau; 1].
  p_matrix.setFromTriplets(p_entries.begin(), p_entries.end());
  const SparseMatrix a_transposed = a_matrix.transpose();
  // The position terms' moments as variables: the column of node j's
  // pattern entry c (0..2 rotation, 3 translation) for coordinate a, -1 when
  // that part of j is not a variable; the handle's parameter column likewise.
  auto variable_of = [&](int j, int c, int a) {
    return c < 3 ? rotation_variable(j) + c * 3 + a : translation_variable(j) < 0 ? -1 : translation_variable(j) + a;
  };
  auto handle_column = [](int d, int a) { return d < 3 ? d * 3 + a : 9 + a; };
  std::vector<Eigen::Triplet<double, int>> position_hessian, position_atp;
  position_hessian.reserve(48 * pair_moment.size());
  for (const auto& [key, moment] : pair_moment) {
    const int j = static_cast<int>(key / num_position_nodes);
    const int k = static_cast<int>(key % num_position_nodes);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        const int row_variable = variable_of(j, c, a);
        if (row_variable < 0) continue;
        for (int d = 0; d < 4; ++d) {
          const int column_variable = variable_of(k, d, a);
          if (column_variable >= 0 && moment(c, d) != 0.0) {
            position_hessian.emplace_back(row_variable, column_variable, moment(c, d));
          }
        }
      }
    }
  }
  for (int j = 0; j < static_cast<int>(handle_moment.size()); ++j) {
    if (rotation_variable(j) < 0) continue;
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        const int row_variable = variable_of(j, c, a);
        if (row_variable < 0) continue;
        for (int d = 0; d < 4; ++d) {
          if (handle_moment[j](c, d) != 0.0) {
            position_atp.emplace_back(row_variable, handle_column(d, a), handle_moment[j](c, d));
          }
        }
        // Column 12 is -c (p_matrix's last column).
        if (constant_moment[j](c, a) != 0.0) {
          position_atp.emplace_back(row_variable, 12, -constant_moment[j](c, a));
        }
      }
    }
  }
  SparseMatrix hessian_positions(n, n), atp_positions(n, 13);
  hessian_positions.setFromTriplets(position_hessian.begin(), position_hessian.end());
  atp_positions.setFromTriplets(position_atp.begin(), position_atp.end());
  impl.hessian = (SparseMatrix(a_transposed * a_matrix) + hessian_positions).pruned();
  const SparseMatrix atp = a_transposed * p_matrix + atp_positions;  // n by 13
  impl.handle_gradient = atp.leftCols(12);
  impl.linear_gradient = -Eigen::VectorXd(atp.col(12));

  // The compressed residuals: A's rows (Coherence, gauge), then per position
  // group R of a QR of its rows (R^T R = M^T M, so the same sum of squares for
  // every x and tau; Householder QR is backward stable, so the rounding is
  // about 1e-16 |M| |z| |M z|, not 1e-16 |M z|^2's expanded terms), or the
  // rows themselves when there are no more of them than columns.
  std::vector<Eigen::Triplet<double, int>> root_entries = a_entries, root_handle_entries;
  for (const Eigen::Triplet<double, int>& entry : p_entries)
    root_handle_entries.emplace_back(entry.row(), entry.col(), -entry.value());
  int root_rows = row;
  for (const PositionGroup& group : groups) {
    const int k = static_cast<int>(group.nodes.size());
    const int width = 4 * k + 7;
    const int count = static_cast<int>(group.rows.size()) / width;
    Eigen::MatrixXd factor = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                                            Eigen::RowMajor>>(
        group.rows.data(), count, width);
    if (count > width) {
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(factor);
      factor = qr.matrixQR().topRows(width).triangularView<Eigen::Upper>();
    }
    for (int i = 0; i < factor.rows(); ++i) {
      for (int a = 0; a < 3; ++a) {
        for (int node = 0; node < k; ++node) {
          for (int e = 0; e < 4; ++e) {
            const double value = factor(i, 4 * node + e);
            const int variable = variable_of(group.nodes[node], e, a);
            if (value != 0.0 && variable >= 0) root_entries.emplace_back(root_rows, variable, value);
          }
        }
        for (int d = 0; d < 4; ++d) {
          const double value = factor(i, 4 * k + d);
          if (value != 0.0) root_handle_entries.emplace_back(root_rows, handle_column(d, a), -value);
        }
        const double value = factor(i, 4 * k + 4 + a);
        if (value != 0.0) root_handle_entries.emplace_back(root_rows, 12, value);
        ++root_rows;
      }
    }
  }
  impl.root.resize(root_rows, n);
  impl.root.setFromTriplets(root_entries.begin(), root_entries.end());
  impl.root.makeCompressed();
  impl.root_handle.resize(root_rows, 13);
  impl.root_handle.setFromTriplets(root_handle_entries.begin(), root_handle_entries.end());

  // The pattern of J^T J: H plus the 9x9 rotation blocks plus the diagonal.
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(impl.hessian.nonZeros() + 81 * impl.rot_nodes.size() + n);
  for (int col = 0; col < n; ++col)
    for (SparseMatrix::InnerIterator it(impl.hessian, col); it; ++it)
      entries.emplace_back(it.row(), col, it.value());
  for (int j : impl.rot_nodes)
    for (int c = 0; c < 9; ++c)
      for (int r = 0; r < 9; ++r) entries.emplace_back(impl.offset[j] + r, impl.offset[j] + c, 0.0);
  impl.terms.AppendPattern(&entries);
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
  impl.terms.IndexValues(impl.system);
  impl.diagonal_index.resize(n);
  for (int i = 0; i < n; ++i) impl.diagonal_index[i] = ValueIndex(impl.system, i, i);
  impl.linear_solver = MakeGaussNewtonLinearSolver(options_);
  if (n > 0) impl.linear_solver->Analyze(impl.system);
  return true;
}

double GaussNewtonSolver::Cost(const Eigen::Affine3d& handle, const NodeTransforms& transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  const Impl& impl = *impl_;
  CHECK_EQ(static_cast<int>(impl.offset.size()), transforms.num_nodes());
  const Eigen::VectorXd x = impl.Gather(transforms);
  return impl.LinearCost(x, impl.RootOffset(handle)) +
         impl.NonlinearCost(x, nullptr, nullptr);
}

SolveSummary GaussNewtonSolver::Solve(const Eigen::Affine3d& handle,
                                      NodeTransforms* transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  const auto start = std::chrono::steady_clock::now();
  auto elapsed_ms = [&start] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
  };
  Impl& impl = *impl_;
  SolveSummary summary;
  const int n = num_variables_;
  const int num_nodes = transforms->num_nodes();
  CHECK_EQ(static_cast<int>(impl.offset.size()), num_nodes);

  Eigen::VectorXd x = impl.Gather(*transforms);
  const Eigen::VectorXd g0 = impl.HandleGradient(handle);
  const Eigen::VectorXd root_offset = impl.RootOffset(handle);

  Eigen::VectorXd hx = impl.hessian * x;
  // The linear terms' cost from their residuals at the start and after every
  // accepted step; a trial step's cost adds to it the change of the
  // quadratic, delta^T (H x + g0) + 1/2 delta^T H delta (small terms only:
  // kept from step to step, its rounding reached 2.4e-9 of the energy on the
  // 416K claw in one step).
  double linear_cost = impl.LinearCost(x, root_offset);
  std::vector<Matrix9d> blocks(impl.rot_nodes.size());
  Eigen::VectorXd gradient = hx + g0;
  double cost = linear_cost + impl.NonlinearCost(x, &gradient, &blocks);
  summary.initial_cost = cost;
  summary.trace.push_back({0.0, cost});

  const bool levenberg_marquardt = options_.damping == Damping::kLevenbergMarquardt;
  double mu = levenberg_marquardt ? options_.initial_damping : options_.min_damping;
  double nu = 2.0;  // Levenberg-Marquardt's growth after a rejected step
  Eigen::VectorXd delta, x_new, h_delta, damped_delta;
  bool done = n == 0;
  double gradient_norm = gradient.lpNorm<Eigen::Infinity>();
  impl.forcing_reference = gradient_norm;
  if (!done && gradient_norm <= stopping_.gradient_tolerance) {
    summary.converged = true;
    summary.message = "gradient tolerance";
    done = true;
  }
  // PCG multiplies by the current J^T J, so it reassembles every iteration
  // and only its preconditioner follows the factorisation rule.
  const bool cholesky = impl.linear_solver->direct();
  bool need_factor = !impl.factor_valid || impl.refactor_next ||
                     options_.factorization != Factorization::kLagged ||
                     levenberg_marquardt;
  bool fresh = false;  // the factorisation is of J^T J at the current x and mu
  // A frame fails when it ends on a system that could not be factorised
  // before any step was taken (the start would come back as a result), or
  // when even the largest damping does not make it factorisable.
  bool factor_failed = false;  // the last factorisation (or its solve) failed
  bool unfactorisable = false;
  int accepted_steps = 0;
  bool assembled = false;  // `system` holds J^T J + mu D at the current x and mu
  while (!done && summary.iterations < stopping_.max_iterations) {
    if (need_factor || !cholesky) {
      impl.Assemble(blocks, mu);
      assembled = true;
    }
    if (need_factor) {
      ++summary.factorizations;
      need_factor = false;
      impl.factor_valid = impl.linear_solver->Factorize(impl.system);
      fresh = true;
      factor_failed = !impl.factor_valid;
      if (!impl.factor_valid) {
        ++summary.iterations;
        summary.trace.push_back({elapsed_ms(), cost});
        mu *= 10.0;
        need_factor = true;
        if (mu > 1e32) {
          unfactorisable = true;
          break;
        }
        continue;
      }
    }
    ++summary.iterations;
    const double eta = std::min(
        options_.forcing_term,
        std::sqrt(gradient_norm / std::max(impl.forcing_reference, 1e-300)));
    if (!impl.linear_solver->Solve(impl.system, -gradient, eta, &delta)) {
      summary.trace.push_back({elapsed_ms(), cost});
      factor_failed = true;
      impl.factor_valid = false;
      need_factor = true;
      if (fresh) mu *= 10.0;
      continue;
    }
    factor_failed = false;
    if (delta.norm() <=
        stopping_.parameter_tolerance * (x.norm() + stopping_.parameter_tolerance)) {
      summary.trace.push_back({elapsed_ms(), cost});
      summary.converged = true;
      summary.message = "parameter tolerance";
      break;
    }
    x_new = x + delta;
    h_delta = impl.hessian * delta;
    const double new_linear_cost = linear_cost + delta.dot(hx + g0) + 0.5 * delta.dot(h_delta);
    const double new_cost = new_linear_cost + impl.NonlinearCost(x_new, nullptr, nullptr);
    double rho = 1.0;  // gain ratio, Levenberg-Marquardt only
    if (levenberg_marquardt && assembled) {
      // Predicted decrease of the model: 1/2 delta^T (mu D delta - g).
      double damped = 0.0;
      const double* values = impl.system.valuePtr();
      for (int i = 0; i < n; ++i) {
        const double d = values[impl.diagonal_index[i]];
        damped += delta[i] * delta[i] * (d - d / (1.0 + mu));  // mu D_ii, D from J^T J
      }
      const double predicted = 0.5 * (damped - delta.dot(gradient));
      rho = predicted > 0.0 ? (cost - new_cost) / predicted : -1.0;
    }
    if (new_cost < cost) {
      ++accepted_steps;
      const double decrease = cost - new_cost;
      x.swap(x_new);
      hx += h_delta;
      linear_cost = impl.LinearCost(x, root_offset);
      gradient = hx + g0;
      cost = linear_cost + impl.NonlinearCost(x, &gradient, &blocks);
      summary.trace.push_back({elapsed_ms(), cost});
      if (levenberg_marquardt) {
        mu = std::max(mu * std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)),
                      options_.min_damping);
        nu = 2.0;
      } else {
        mu = std::max(mu / 10.0, options_.min_damping);
      }
      const double new_gradient_norm = gradient.lpNorm<Eigen::Infinity>();
      if (decrease <= stopping_.function_tolerance * (cost + decrease)) {
        summary.converged = true;
        summary.message = "function tolerance";
        break;
      }
      if (new_gradient_norm <= stopping_.gradient_tolerance) {
        summary.converged = true;
        summary.message = "gradient tolerance";
        break;
      }
      fresh = false;
      // Pure Gauss-Newton and Levenberg-Marquardt refactorise every
      // iteration; the lagged variants keep the factorisation while the
      // gradient shrinks by refactor_ratio a step.
      need_factor = levenberg_marquardt ||
                    options_.factorization == Factorization::kEveryIteration ||
                    new_gradient_norm > options_.refactor_ratio * gradient_norm;
      gradient_norm = new_gradient_norm;
    } else {
      summary.trace.push_back({elapsed_ms(), cost});
      if (levenberg_marquardt) {
        mu *= nu;
        nu *= 2.0;
      } else if (fresh) {
        // A stale factorisation is refreshed first; a fresh one is damped more.
        mu *= 10.0;
      }
      need_factor = true;
    }
    assembled = false;
  }
  if (!done && summary.message.empty()) summary.message = "iteration cap";
  impl.refactor_next = need_factor && !summary.converged;
  summary.final_cost = cost;
  if (unfactorisable || (factor_failed && accepted_steps == 0)) {
    summary.failed = true;
    summary.message = "the damped normal equations could not be factorised (" +
                      std::to_string(summary.factorizations) + " tries); " +
                      (accepted_steps == 0 ? std::string("the nodes were not moved")
                                           : "stopped after " + std::to_string(accepted_steps) +
                                                 " accepted steps");
  }
  if (!std::isfinite(cost)) {
    summary.failed = true;
    summary.message = "the cost is not finite";
  }

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
