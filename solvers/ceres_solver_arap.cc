#include "msdeform/solvers/ceres_solver_arap.h"

#include <algorithm>
#include <map>
#include <utility>

#include <glog/logging.h>

#include "msdeform/energies/arap_cluster_cost.h"

namespace msdeform {
namespace {

// The parameter blocks of one residual block, by pointer, in order.
class BlockList {
 public:
  int Index(double* block, int size) {
    for (size_t b = 0; b < blocks_.size(); ++b)
      if (blocks_[b] == block) return static_cast<int>(b);
    blocks_.push_back(block);
    sizes_.push_back(size);
    return static_cast<int>(blocks_.size()) - 1;
  }
  const std::vector<double*>& blocks() const { return blocks_; }
  const std::vector<int>& sizes() const { return sizes_; }

 private:
  std::vector<double*> blocks_;
  std::vector<int> sizes_;
};

}  // namespace

CeresArapProblem::CeresArapProblem(std::shared_ptr<const SubspaceArap> arap,
                                   NodeTransforms* parameters,
                                   const std::function<void(int)>& ensure_blocks,
                                   ceres::Problem* problem)
    : arap_(std::move(arap)) {
  const SubspaceArap& a = *arap_;
  const int n = a.num_nodes();
  const int num_slots = a.num_slots();
  const double scale = 1.0 / (a.length_unit() * a.length_unit());
  const CotangentWeights& cot = a.cotangent();
  const int num_groups = a.num_handle_groups();
  handles_.assign(num_groups, Eigen::Matrix<double, 12, 1>::Zero());
  rotations_.assign(a.num_clusters(), Eigen::Matrix3d::Identity());
  // The constant parts: a translation slot holds t_j plus this (g_j less
  // the slots' origin), the rest pseudo-node's slots hold these; the handle
  // groups' pseudo-nodes are constant blocks set each frame.
  SubspaceArap::Slots rest;
  a.Gather(NodeTransforms::Identity(n), Eigen::Affine3d::Identity(), &rest);
  auto* manifold_owner = new RotationMatrixManifold();  // the problem takes it
  bool manifold_used = false;

  // The column of a slot in a block list.
  auto slot_column = [&](int slot, BlockList* blocks) {
    ArapClusterCost::Column column;
    const int j = slot / 4, m = slot % 4;
    if (j < n) {
      ensure_blocks(j);
      if (m < 3) {
        column.block = blocks->Index(parameters->rotations.col(j).data(), 9);
        column.offset = 3 * m;
      } else {
        column.block = blocks->Index(parameters->translations.col(j).data(), 3);
        column.constant = rest.row(slot).transpose();
      }
    } else if (j < n + num_groups) {
      column.block = blocks->Index(handles_[j - n].data(), 12);
      column.offset = 3 * m;
    } else {
      column.constant = rest.row(slot).transpose();  // the rest pseudo-node
    }
    return column;
  };
  auto add_block = [&](const Eigen::MatrixXd& gram, const std::vector<int>& slots,
                       Eigen::Matrix3d* rotation) {
    const Eigen::MatrixXd factor = PsdFactor(scale * gram);
    if (factor.rows() == 0) return;
    BlockList blocks;
    std::vector<ArapClusterCost::Column> columns;
    for (int slot : slots) columns.push_back(slot_column(slot, &blocks));
    if (rotation != nullptr) {
      const int block = blocks.Index(rotation->data(), 9);
      for (int m = 0; m < 3; ++m) {
        ArapClusterCost::Column column;
        column.block = block;
        column.offset = 3 * m;
        columns.push_back(column);
      }
    }
    for (Eigen::Matrix<double, 12, 1>& handle : handles_) {
      problem->AddParameterBlock(handle.data(), 12);
      problem->SetParameterBlockConstant(handle.data());
    }
    if (rotation != nullptr) {
      problem->AddParameterBlock(rotation->data(), 9, manifold_owner);
      manifold_used = true;
    }
    problem->AddResidualBlock(new ArapClusterCost(factor, std::move(columns), blocks.sizes()),
                              nullptr, blocks.blocks());
  };

  // Per cluster: G_c = [[Q_c, -K_c^T], [-K_c, Cov_c]] over its slots.
  std::vector<Eigen::Triplet<double>> cluster_q;  // sum_c Q_c, for the soft terms
  std::vector<int> column_of_slot(num_slots, -1);
  for (int c = 0; c < a.num_clusters(); ++c) {
    std::vector<int> slots;
    auto column = [&](int slot) {
      if (column_of_slot[slot] < 0) {
        column_of_slot[slot] = static_cast<int>(slots.size());
        slots.push_back(slot);
      }
      return column_of_slot[slot];
    };
    std::vector<std::pair<std::vector<std::pair<int, double>>, double>> spokes;  // (db, w)
    for (int i : a.ClusterVertices(c)) {
      const std::vector<SubspaceArap::BasisEntry> bi = a.Basis(i);
      for (int s = cot.adjacency.offsets[i]; s < cot.adjacency.offsets[i + 1]; ++s) {
        if (cot.weight[s] == 0.0) continue;
        std::vector<std::pair<int, double>> db;
        for (const auto& entry : bi)
          for (int m = 0; m < 4; ++m) db.emplace_back(column(entry.slot + m), entry.coefficient[m]);
        for (const auto& entry : a.Basis(cot.adjacency.neighbors[s]))
          for (int m = 0; m < 4; ++m) db.emplace_back(column(entry.slot + m), -entry.coefficient[m]);
        spokes.emplace_back(std::move(db), cot.weight[s]);
      }
    }
    for (int e = a.k_offsets()[c]; e < a.k_offsets()[c + 1]; ++e) column(a.k_slots()[e]);
    const int m = static_cast<int>(slots.size());
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(m + 3, m + 3);
    Eigen::VectorXd db(m);
    for (const auto& [entries, w] : spokes) {
      db.setZero();
      for (const auto& [col, value] : entries) db[col] += value;
      gram.topLeftCorner(m, m).noalias() += w * db * db.transpose();
    }
    for (int r = 0; r < m; ++r)
      for (int col = 0; col < m; ++col)
        if (gram(r, col) != 0.0) cluster_q.emplace_back(slots[r], slots[col], gram(r, col));
    for (int e = a.k_offsets()[c]; e < a.k_offsets()[c + 1]; ++e) {
      const int col = column_of_slot[a.k_slots()[e]];
      gram.block<1, 3>(col, m) -= a.k_vectors().col(e).transpose();
      gram.block<3, 1>(m, col) -= a.k_vectors().col(e);
    }
    gram.bottomRightCorner<3, 3>() = a.cluster_covariances()[c];
    for (int slot : slots) column_of_slot[slot] = -1;
    add_block(gram, slots, &rotations_[c]);
  }

  // The soft constraint terms: Q - sum_c Q_c (zero with exact constraints,
  // up to rounding).
  Eigen::SparseMatrix<double> clusters(num_slots, num_slots);
  clusters.setFromTriplets(cluster_q.begin(), cluster_q.end());
  Eigen::SparseMatrix<double> soft = a.full_matrix() - clusters;
  const double largest =
      a.full_matrix().nonZeros() ? a.full_matrix().coeffs().cwiseAbs().maxCoeff() : 0.0;
  soft.prune([&](int, int, double value) { return std::abs(value) > 1e-12 * largest; });
  if (soft.nonZeros() > 0) {
    std::vector<int> slots;
    for (int col = 0; col < soft.outerSize(); ++col)
      if (soft.col(col).nonZeros() > 0) slots.push_back(col);
    for (size_t i = 0; i < slots.size(); ++i) column_of_slot[slots[i]] = static_cast<int>(i);
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(slots.size(), slots.size());
    for (int col = 0; col < soft.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(soft, col); it; ++it)
        gram(column_of_slot[it.row()], column_of_slot[col]) = it.value();
    add_block(gram, slots, nullptr);
  }
  if (!manifold_used) delete manifold_owner;
}

void CeresArapProblem::SetFrame(const HandleTransforms& handles, const NodeTransforms& parameters) {
  SubspaceArap::Slots u;
  arap_->Gather(parameters, handles, &u);
  for (int g = 0; g < static_cast<int>(handles_.size()); ++g) {
    const int h = 4 * (arap_->num_nodes() + g);
    for (int m = 0; m < 4; ++m) handles_[g].segment<3>(3 * m) = u.row(h + m).transpose();
  }
  SubspaceArap::Rotations fitted;
  arap_->FitRotations(u, &fitted);
  for (size_t c = 0; c < rotations_.size(); ++c) rotations_[c] = fitted[c];
}

}  // namespace msdeform
