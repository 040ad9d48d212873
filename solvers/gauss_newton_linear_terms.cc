#include "msdeform/solvers/gauss_newton_linear_terms.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <unordered_map>

#include <Eigen/Householder>
#include <Eigen/QR>
#include <glog/logging.h>

#include "msdeform/energies/gauge_cost.h"

namespace msdeform {
namespace {

using SparseMatrix = LinearTerms::SparseMatrix;
using Triplet = Eigen::Triplet<double, int>;

// Node j's columns among the variables: offset[j] for R_j (-1 for a Fixed
// node), then t_j for a Totally Free node (-1 otherwise).
struct VariableColumns {
  const DeformationEnergy& energy;
  const std::vector<int>& offset;

  int rotation(int j) const { return offset[j]; }
  int translation(int j) const {
    return energy.node_class[j] == NodeClass::kTotallyFree ? offset[j] + 9 : -1;
  }
  // The column of node j's pattern entry c (0..2 rotation, 3 translation)
  // for coordinate a, -1 when that part of j is not a variable.
  int of(int j, int c, int a) const {
    return c < 3 ? rotation(j) + c * 3 + a : translation(j) < 0 ? -1 : translation(j) + a;
  }
};

// Handle group g's parameter column of pattern entry d for coordinate a
// (tau: 12 numbers a group, GaussNewtonSolver's HandleParameters).
int HandleColumn(int g, int d, int a) { return 12 * g + (d < 3 ? d * 3 + a : 9 + a); }

// Linear residuals r = A x + c - P tau, row by row: A's entries, c, and the
// next row.
struct LinearRows {
  std::vector<Triplet> a_entries;
  std::vector<double> constant;
  int row = 0;
};

// scale * R_j * vector into rows row..row+2: A's where R_j is a variable,
// c's (at R_j's value) where it is not.
void AddRotation(const VariableColumns& columns, const NodeTransforms& transforms, int j,
                 const Eigen::Vector3d& vector, double scale, LinearRows* rows) {
  const int row = rows->row;
  if (columns.rotation(j) >= 0) {
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        rows->a_entries.emplace_back(row + a, columns.rotation(j) + c * 3 + a, scale * vector[c]);
  } else {
    const Eigen::Vector3d value = scale * (transforms.rotation(j) * vector);
    for (int a = 0; a < 3; ++a) rows->constant[row + a] += value[a];
  }
}

// scale * t_j into rows row..row+2, likewise.
void AddTranslation(const VariableColumns& columns, const NodeTransforms& transforms, int j,
                    double scale, LinearRows* rows) {
  const int row = rows->row;
  if (columns.translation(j) >= 0) {
    for (int a = 0; a < 3; ++a)
      rows->a_entries.emplace_back(row + a, columns.translation(j) + a, scale);
  } else {
    for (int a = 0; a < 3; ++a) rows->constant[row + a] += scale * transforms.translations(a, j);
  }
}

// Coherence (Eq. 14): s (R_j e + t_j - t_k - e), three rows a term.
void AppendCoherenceRows(const DeformationEnergy& energy, const NodeTransforms& transforms,
                         const VariableColumns& columns, LinearRows* rows) {
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    rows->constant.resize(rows->row + 3, 0.0);
    AddRotation(columns, transforms, term.j, term.edge, term.sqrt_weight, rows);
    for (int a = 0; a < 3; ++a) rows->constant[rows->row + a] -= term.sqrt_weight * term.edge[a];
    AddTranslation(columns, transforms, term.j, term.sqrt_weight, rows);
    AddTranslation(columns, transforms, term.k, -term.sqrt_weight, rows);
    rows->row += 3;
  }
}

// Gauge terms: linear in R with no constant, one row of A each.
void AppendGaugeRows(const DeformationEnergy& energy, const VariableColumns& columns,
                     LinearRows* rows) {
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    CHECK_GE(columns.rotation(term.node), 0) << "gauge term on a Fixed node";
    rows->constant.resize(rows->row + 1, 0.0);
    const Eigen::Matrix<double, 1, 9> jacobian =
        GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight);
    for (int i = 0; i < 9; ++i) {
      if (jacobian[i] != 0.0)
        rows->a_entries.emplace_back(rows->row, columns.rotation(term.node) + i, jacobian[i]);
    }
    rows->row += 1;
  }
}

// The terms' rows for the compressed residuals (LinearTerms::root), grouped
// by their variable nodes (sorted) and the handle group they follow (-1:
// none). A row [u_1 .. u_k, p, c] (4 k + 7 numbers; u_i with 0 for a
// translation that is not a variable) gives coordinate a's residual as
//   row . [X_1a .. X_ka, -theta_a, e_a],
// X_ia = (R_i(a, 0..2), t_i(a)), theta_a = (handle(a, 0..2), its translation(a))
// of the group's handle.
struct PositionGroup {
  std::vector<int> nodes;
  int handle_group;          // -1: p = 0
  std::vector<double> rows;  // row-major, 4 k + 7 wide
};

// Position terms (Eq. 16; one per handle vertex, and per held fixed vertex:
// a hundred thousand on a 1.7M-vertex mesh) are not rows of A: their three
// rows share one pattern, u_i = s w_i [o_i; 1] per node i (rotation column
// c * 3 + a and translation a for coordinate a), so their products are
// accumulated as 4x4 moments per node pair and expanded once
// (ExpandPositionMoments: I_3 Kronecker each moment). p = s [rest; 1] is
// the handle row's pattern.
struct PositionMoments {
  int num_nodes = 0;
  int num_handle_groups = 1;
  std::unordered_map<int64_t, Eigen::Matrix4d> pair_moment;  // sum u_j u_k^T
  // sum u_j p^T of node j's terms that follow handle group g, at j G + g.
  std::unordered_map<int64_t, Eigen::Matrix4d> handle_moment;
  std::vector<Eigen::Matrix<double, 4, 3>> constant_moment;  // sum u_j c^T
  std::vector<PositionGroup> groups;
};

void AccumulatePositionTerms(const DeformationEnergy& energy, const NodeTransforms& transforms,
                             const VariableColumns& columns, PositionMoments* moments) {
  const int num_position_nodes = moments->num_nodes;
  auto& pair_moment = moments->pair_moment;
  auto& handle_moment = moments->handle_moment;
  auto& constant_moment = moments->constant_moment;
  std::vector<PositionGroup>& groups = moments->groups;
  std::map<std::vector<int>, int> group_of_key;
  std::vector<int> key, order;
  const int num_handle_groups = moments->num_handle_groups;
  if (!energy.positions.empty()) {
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
      if (columns.rotation(j) < 0) c += sw * (transforms.rotation(j) * skin.offset);
      if (columns.translation(j) < 0) c += sw * transforms.translations.col(j);
      c += sw * skin.position;
      if (columns.rotation(j) >= 0) {
        variable_nodes.push_back(j);
        patterns.push_back(sw * Eigen::Vector4d(skin.offset[0], skin.offset[1], skin.offset[2], 1.0));
      }
    }
    Eigen::Vector4d p = Eigen::Vector4d::Zero();
    if (term.follows_handle()) {
      CHECK_LT(term.handle_group, num_handle_groups);
      p << s * term.rest, s;
    } else {
      c -= s * term.rest;
    }
    order.resize(variable_nodes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return variable_nodes[a] < variable_nodes[b]; });
    key.assign(1, term.handle_group);
    for (int i : order) key.push_back(variable_nodes[i]);
    auto [group, inserted] = group_of_key.try_emplace(key, static_cast<int>(groups.size()));
    if (inserted) {
      groups.push_back({std::vector<int>(key.begin() + 1, key.end()), term.handle_group, {}});
    }
    std::vector<double>& rows = groups[group->second].rows;
    for (int i : order) {
      for (int e = 0; e < 4; ++e) {
        const bool variable = e < 3 || columns.translation(variable_nodes[i]) >= 0;
        rows.push_back(variable ? patterns[i][e] : 0.0);
      }
    }
    for (int e = 0; e < 4; ++e) rows.push_back(p[e]);
    for (int a = 0; a < 3; ++a) rows.push_back(c[a]);
    for (size_t i = 0; i < variable_nodes.size(); ++i) {
      const int j = variable_nodes[i];
      if (term.follows_handle()) {
        const int64_t at = static_cast<int64_t>(j) * num_handle_groups + term.handle_group;
        auto [it, inserted] = handle_moment.try_emplace(at, Eigen::Matrix4d::Zero());
        it->second.noalias() += patterns[i] * p.transpose();
      }
      constant_moment[j].noalias() += patterns[i] * c.transpose();
      for (size_t k = 0; k < variable_nodes.size(); ++k) {
        const int64_t key = static_cast<int64_t>(j) * num_position_nodes + variable_nodes[k];
        auto [it, inserted] = pair_moment.try_emplace(key, Eigen::Matrix4d::Zero());
        it->second.noalias() += patterns[i] * patterns[k].transpose();
      }
    }
  }
}

// The position terms' moments as entries of H (n by n) and of A^T P (n by
// 12 G + 1; column 12 G is -c, p_matrix's last column).
void ExpandPositionMoments(const PositionMoments& moments, const VariableColumns& columns,
                           SparseMatrix* hessian_positions, SparseMatrix* atp_positions) {
  const int num_position_nodes = moments.num_nodes;
  const auto& handle_moment = moments.handle_moment;
  const auto& constant_moment = moments.constant_moment;
  std::vector<Triplet> position_hessian, position_atp;
  position_hessian.reserve(48 * moments.pair_moment.size());
  for (const auto& [key, moment] : moments.pair_moment) {
    const int j = static_cast<int>(key / num_position_nodes);
    const int k = static_cast<int>(key % num_position_nodes);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        const int row_variable = columns.of(j, c, a);
        if (row_variable < 0) continue;
        for (int d = 0; d < 4; ++d) {
          const int column_variable = columns.of(k, d, a);
          if (column_variable >= 0 && moment(c, d) != 0.0) {
            position_hessian.emplace_back(row_variable, column_variable, moment(c, d));
          }
        }
      }
    }
  }
  const int num_handle_groups = moments.num_handle_groups;
  const int constant_column = 12 * num_handle_groups;
  for (const auto& [at, moment] : handle_moment) {
    const int j = static_cast<int>(at / num_handle_groups);
    const int g = static_cast<int>(at % num_handle_groups);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        const int row_variable = columns.of(j, c, a);
        if (row_variable < 0) continue;
        for (int d = 0; d < 4; ++d) {
          if (moment(c, d) != 0.0) {
            position_atp.emplace_back(row_variable, HandleColumn(g, d, a), moment(c, d));
          }
        }
      }
    }
  }
  for (int j = 0; j < static_cast<int>(constant_moment.size()); ++j) {
    if (columns.rotation(j) < 0) continue;
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 4; ++c) {
        const int row_variable = columns.of(j, c, a);
        // The constant column is -c (p_matrix's last column).
        if (row_variable >= 0 && constant_moment[j](c, a) != 0.0) {
          position_atp.emplace_back(row_variable, constant_column, -constant_moment[j](c, a));
        }
      }
    }
  }
  hessian_positions->setFromTriplets(position_hessian.begin(), position_hessian.end());
  atp_positions->setFromTriplets(position_atp.begin(), position_atp.end());
}

// Each position group's rows, or the R of a Householder QR of them when
// there are more rows than columns; on num_threads threads, one group per
// thread at a time, once the groups have min_parallel_rows rows in all.
std::vector<Eigen::MatrixXd> GroupFactors(const std::vector<PositionGroup>& groups,
                                          int num_threads, int min_parallel_rows) {
  const int num_groups = static_cast<int>(groups.size());
  std::vector<Eigen::MatrixXd> factors(num_groups);
  int64_t total_rows = 0;
  for (const PositionGroup& group : groups)
    total_rows += static_cast<int64_t>(group.rows.size()) / (4 * group.nodes.size() + 7);
  const bool parallel = num_threads > 1 && num_groups > 1 && total_rows >= min_parallel_rows;
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, num_threads)) if (parallel)
  for (int g = 0; g < num_groups; ++g) {
    const PositionGroup& group = groups[g];
    const int width = 4 * static_cast<int>(group.nodes.size()) + 7;
    const int count = static_cast<int>(group.rows.size()) / width;
    Eigen::MatrixXd& factor = factors[g];
    factor = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                            Eigen::RowMajor>>(group.rows.data(), count, width);
    if (count > width) {
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(factor);
      factor = qr.matrixQR().topRows(width).triangularView<Eigen::Upper>();
    }
  }
  return factors;
}

// The compressed residuals: A's rows (Coherence, gauge), then per position
// group R of a QR of its rows (R^T R = M^T M, so the same sum of squares for
// every x and tau; Householder QR is backward stable, so the rounding is
// about 1e-16 |M| |z| |M z|, not 1e-16 |M z|^2's expanded terms), or the
// rows themselves when there are no more of them than columns.
void CompressResiduals(const LinearRows& rows, const std::vector<Triplet>& p_entries,
                       const std::vector<PositionGroup>& groups, const VariableColumns& columns,
                       int n, int num_handle_groups, int num_threads, int min_parallel_rows,
                       LinearTerms* out) {
  const int constant_column = 12 * num_handle_groups;
  std::vector<Triplet> root_entries = rows.a_entries, root_handle_entries;
  for (const Triplet& entry : p_entries)
    root_handle_entries.emplace_back(entry.row(), entry.col(), -entry.value());
  int root_rows = rows.row;
  const int num_groups = static_cast<int>(groups.size());
  const std::vector<Eigen::MatrixXd> factors =
      GroupFactors(groups, num_threads, min_parallel_rows);
  for (int g = 0; g < num_groups; ++g) {
    const PositionGroup& group = groups[g];
    const int k = static_cast<int>(group.nodes.size());
    const Eigen::MatrixXd& factor = factors[g];
    for (int i = 0; i < factor.rows(); ++i) {
      for (int a = 0; a < 3; ++a) {
        for (int node = 0; node < k; ++node) {
          for (int e = 0; e < 4; ++e) {
            const double value = factor(i, 4 * node + e);
            const int variable = columns.of(group.nodes[node], e, a);
            if (value != 0.0 && variable >= 0) root_entries.emplace_back(root_rows, variable, value);
          }
        }
        for (int d = 0; d < 4 && group.handle_group >= 0; ++d) {
          const double value = factor(i, 4 * k + d);
          if (value != 0.0) {
            root_handle_entries.emplace_back(root_rows, HandleColumn(group.handle_group, d, a),
                                             -value);
          }
        }
        const double value = factor(i, 4 * k + 4 + a);
        if (value != 0.0) root_handle_entries.emplace_back(root_rows, constant_column, value);
        ++root_rows;
      }
    }
  }
  out->root.resize(root_rows, n);
  out->root.setFromTriplets(root_entries.begin(), root_entries.end());
  out->root.makeCompressed();
  out->root_handle.resize(root_rows, constant_column + 1);
  out->root_handle.setFromTriplets(root_handle_entries.begin(), root_handle_entries.end());
}

}  // namespace

void AssembleLinearTerms(const DeformationEnergy& energy, const NodeTransforms& transforms,
                         const std::vector<int>& offset, const GaussNewtonTerms& terms, int n,
                         LinearTerms* out, int num_threads, int min_parallel_rows) {
  const VariableColumns columns{energy, offset};
  LinearRows rows;
  AppendCoherenceRows(energy, transforms, columns, &rows);
  const int num_handle_groups = energy.num_handle_groups;
  const int constant_column = 12 * num_handle_groups;
  out->num_handle_groups = num_handle_groups;
  PositionMoments moments;
  moments.num_nodes = transforms.num_nodes();
  moments.num_handle_groups = num_handle_groups;
  AccumulatePositionTerms(energy, transforms, columns, &moments);
  AppendGaugeRows(energy, columns, &rows);
  terms.AppendLinearRows(&rows.a_entries, &rows.constant, &rows.row);

  const int row = rows.row;
  SparseMatrix a_matrix(row, n), p_matrix(row, constant_column + 1);
  a_matrix.setFromTriplets(rows.a_entries.begin(), rows.a_entries.end());
  std::vector<Triplet> p_entries;
  for (int r = 0; r < row; ++r) {
    if (rows.constant[r] != 0.0) p_entries.emplace_back(r, constant_column, -rows.constant[r]);
  }
  // p_matrix = [P, -c]: the residual is A x - p_matrix [tau; 1].
  p_matrix.setFromTriplets(p_entries.begin(), p_entries.end());
  const SparseMatrix a_transposed = a_matrix.transpose();
  SparseMatrix hessian_positions(n, n), atp_positions(n, constant_column + 1);
  ExpandPositionMoments(moments, columns, &hessian_positions, &atp_positions);
  out->hessian = (SparseMatrix(a_transposed * a_matrix) + hessian_positions).pruned();
  const SparseMatrix atp = a_transposed * p_matrix + atp_positions;  // n by 12 G + 1
  out->handle_gradient = atp.leftCols(constant_column);
  out->linear_gradient = -Eigen::VectorXd(atp.col(constant_column));

  CompressResiduals(rows, p_entries, moments.groups, columns, n, num_handle_groups, num_threads,
                    min_parallel_rows, out);
}

}  // namespace msdeform
