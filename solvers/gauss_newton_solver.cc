#include "msdeform/solvers/gauss_newton_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glog/logging.h>

#include "msdeform/energies/rot_cost.h"
#include "msdeform/solvers/damped_gauss_newton.h"
#include "msdeform/solvers/gauss_newton_linear_solver.h"
#include "msdeform/solvers/gauss_newton_linear_terms.h"
#include "msdeform/solvers/gauss_newton_terms.h"

namespace msdeform {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
// tau, 12 numbers a handle group (group g's at 12 g): its transform's matrix
// column-major, then its translation; and a trailing 1 when with_one.
Eigen::VectorXd HandleParameters(const HandleTransforms& handles, int num_groups, bool with_one) {
  Eigen::VectorXd tau(12 * num_groups + (with_one ? 1 : 0));
  for (int g = 0; g < num_groups; ++g) {
    Eigen::Map<Eigen::Matrix3d>(tau.data() + 12 * g) = handles[g].linear();
    tau.segment<3>(12 * g + 9) = handles[g].translation();
  }
  if (with_one) tau[12 * num_groups] = 1.0;
  return tau;
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
  GaussNewtonThreads threads;
  mutable std::vector<double> chunk_sums;  // RotCost's, per chunk
  std::vector<int> offset;  // first variable of node j, or -1
  std::vector<char> totally_free;  // node j has t among the variables
  std::vector<int> rot_nodes;
  double sqrt_rot = 1.0;
  SparseMatrix hessian;        // H = A^T A (linear terms only)
  RowSparseMatrix hessian_rows;  // the same, by rows (HessianTimes)
  // H = I_3 (x) H4 when each linear term treats the three coordinates alike
  // (Coherence and Position do; a gauge term or an extra linear term may
  // not): H4 over the compact variables p, one per node and R column or t,
  // whose coordinate a is variable compact_base[p] + a. Empty otherwise.
  RowSparseMatrix hessian_compact;
  std::vector<int> compact_base;

  // Fills hessian_compact when H has that form, entry for entry (the same
  // values bit for bit in the three coordinates).
  void CompactHessian() {
    const int n = static_cast<int>(hessian_rows.rows());
    std::vector<int> compact(n, -1), coordinate(n, -1);
    compact_base.clear();
    for (size_t j = 0; j < offset.size(); ++j) {
      if (offset[j] < 0) continue;
      for (int e = 0; e < (totally_free[j] ? 4 : 3); ++e) {
        const int base = offset[j] + (e < 3 ? 3 * e : 9);
        for (int a = 0; a < 3; ++a) {
          compact[base + a] = static_cast<int>(compact_base.size());
          coordinate[base + a] = a;
        }
        compact_base.push_back(base);
      }
    }
    hessian_compact.resize(0, 0);
    const int* outer = hessian_rows.outerIndexPtr();
    const int* inner = hessian_rows.innerIndexPtr();
    const double* values = hessian_rows.valuePtr();
    std::vector<Eigen::Triplet<double, int>> entries;
    for (size_t p = 0; p < compact_base.size(); ++p) {
      const int row = compact_base[p];
      const int length = outer[row + 1] - outer[row];
      for (int a = 1; a < 3; ++a) {
        if (outer[row + a + 1] - outer[row + a] != length) return;
      }
      for (int k = 0; k < length; ++k) {
        const int column = inner[outer[row] + k];
        if (coordinate[column] != 0) return;
        for (int a = 1; a < 3; ++a) {
          if (inner[outer[row + a] + k] != column + a ||
              values[outer[row + a] + k] != values[outer[row] + k])
            return;
        }
        entries.emplace_back(static_cast<int>(p), compact[column], values[outer[row] + k]);
      }
    }
    const int m = static_cast<int>(compact_base.size());
    hessian_compact.resize(m, m);
    hessian_compact.setFromTriplets(entries.begin(), entries.end());
    hessian_compact.makeCompressed();
  }
  Eigen::VectorXd linear_gradient;  // A^T c
  int num_handle_groups = 1;        // G
  SparseMatrix handle_gradient;     // A^T P, #variables by 12 G
  // The linear residuals in a compressed form that keeps their sum of
  // squares: |root x + root_handle [tau; 1]|^2 = |A x + c - P tau|^2. The
  // Coherence and gauge rows of A as they are; per group of position terms
  // with the same variable nodes, the triangular factor of a QR of their rows.
  // The cost is evaluated from these residuals, not from H, g0 and a Gram
  // matrix of the constant: that expanded form loses about 1e-16 of
  // |c - P tau|^2, which grows with the handle's size and its distance from
  // the origin (4e-7 of the energy on the 416K claw).
  RowSparseMatrix root;         // m by #variables
  RowSparseMatrix root_handle;  // m by 12 G + 1
  SparseMatrix system;              // pattern of J^T J, full (both triangles)
  std::vector<double> base_values;  // H on that pattern
  std::vector<int> rot_value_index;  // 81 per rot node, column-major 9x9
  std::vector<int> diagonal_index;   // per variable
  // DeformationEnergy::terms: linear ones are rows of A; nonlinear ones write
  // term_values (their J^T J entries at the last evaluation with a gradient).
  GaussNewtonTerms terms;
  mutable std::vector<double> term_values;
  // The factorisation that carries over between frames (damped_gauss_newton.h).
  DampedGaussNewtonState state;
  std::unique_ptr<GaussNewtonLinearSolver> linear_solver;  // gauss_newton_linear_solver.h

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

  // *product = H v, row by row, four rows at a time: each row's sum in
  // the order of the column-major product's (so the same bits), four
  // independent chains of additions instead of one (1.3x on the claw).
  void HessianTimes(const Eigen::VectorXd& v, Eigen::VectorXd* product) const {
    if (hessian_compact.rows() > 0) {
      // The three coordinates' sums at once, each in the order of H's row
      // (ascending compact column is ascending variable): the same bits, a
      // third of the entries to read.
      product->resize(hessian_rows.rows());
      const int* outer = hessian_compact.outerIndexPtr();
      const int* inner = hessian_compact.innerIndexPtr();
      const double* values = hessian_compact.valuePtr();
      const int* base = compact_base.data();
      for (int p = 0; p < hessian_compact.rows(); ++p) {
        double sum0 = 0.0, sum1 = 0.0, sum2 = 0.0;
        for (int k = outer[p]; k < outer[p + 1]; ++k) {
          const double* w = v.data() + base[inner[k]];
          sum0 += values[k] * w[0];
          sum1 += values[k] * w[1];
          sum2 += values[k] * w[2];
        }
        double* out = product->data() + base[p];
        out[0] = sum0;
        out[1] = sum1;
        out[2] = sum2;
      }
      return;
    }
    const int rows = static_cast<int>(hessian_rows.rows());
    const int* outer = hessian_rows.outerIndexPtr();
    const int* inner = hessian_rows.innerIndexPtr();
    const double* values = hessian_rows.valuePtr();
    product->resize(rows);
    int i = 0;
    for (; i + 4 <= rows; i += 4) {
      double sum[4] = {0.0, 0.0, 0.0, 0.0};
      int length = outer[i + 1] - outer[i];
      for (int q = 1; q < 4; ++q) length = std::min(length, outer[i + q + 1] - outer[i + q]);
      const int b0 = outer[i], b1 = outer[i + 1], b2 = outer[i + 2], b3 = outer[i + 3];
      for (int k = 0; k < length; ++k) {
        sum[0] += values[b0 + k] * v[inner[b0 + k]];
        sum[1] += values[b1 + k] * v[inner[b1 + k]];
        sum[2] += values[b2 + k] * v[inner[b2 + k]];
        sum[3] += values[b3 + k] * v[inner[b3 + k]];
      }
      for (int q = 0; q < 4; ++q) {
        for (int k = outer[i + q] + length; k < outer[i + q + 1]; ++k)
          sum[q] += values[k] * v[inner[k]];
        (*product)[i + q] = sum[q];
      }
    }
    for (; i < rows; ++i) {
      double sum = 0.0;
      for (int k = outer[i]; k < outer[i + 1]; ++k) sum += values[k] * v[inner[k]];
      (*product)[i] = sum;
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

  // Writes the variables x into *transforms.
  void Scatter(const Eigen::VectorXd& x, NodeTransforms* transforms) const {
    for (int j = 0; j < static_cast<int>(offset.size()); ++j) {
      const int o = offset[j];
      if (o < 0) continue;
      transforms->rotations.col(j) = x.segment<9>(o);
      if (totally_free[j]) transforms->translations.col(j) = x.segment<3>(o + 9);
    }
  }

  // g0 = A^T c - A^T P tau: the gradient of the linear terms at x = 0.
  Eigen::VectorXd HandleGradient(const HandleTransforms& handles) const {
    return linear_gradient -
           handle_gradient * HandleParameters(handles, num_handle_groups, /*with_one=*/false);
  }

  // root_handle [tau; 1]: the frame's part of the compressed residuals.
  // By hand, in the order of Eigen's row-major product (the same bits):
  // Eigen's runs an OpenMP region above 20,000 entries, whose wake-up on a
  // busy machine can cost more than this whole pass.
  Eigen::VectorXd RootOffset(const HandleTransforms& handles) const {
    const Eigen::VectorXd tau1 = HandleParameters(handles, num_handle_groups, /*with_one=*/true);
    const int* outer = root_handle.outerIndexPtr();
    const int* inner = root_handle.innerIndexPtr();
    const double* values = root_handle.valuePtr();
    Eigen::VectorXd offset(root_handle.rows());
    for (int i = 0; i < root_handle.rows(); ++i) {
      double sum = 0.0;
      for (int k = outer[i]; k < outer[i + 1]; ++k) sum += values[k] * tau1[inner[k]];
      offset[i] = sum;
    }
    return offset;
  }

  // 1/2 |A x + c - P tau|^2 from the compressed residuals (`offset`:
  // RootOffset of the frame): one pass over root's rows, the squares summed
  // in four interleaved partial sums (row i into sum i mod 4; one chain of
  // 4,818 additions was most of this pass on the 104K claw).
  double LinearCost(const Eigen::VectorXd& x, const Eigen::VectorXd& offset) const {
    const int* outer = root.outerIndexPtr();
    const int* inner = root.innerIndexPtr();
    const double* values = root.valuePtr();
    const int rows = static_cast<int>(root.rows());
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < rows; ++i) {
      double residual = offset[i];
      for (int k = outer[i]; k < outer[i + 1]; ++k) residual += values[k] * x[inner[k]];
      sum[i & 3] += residual * residual;
    }
    return 0.5 * ((sum[0] + sum[1]) + (sum[2] + sum[3]));
  }

  // Rot cost at x; with gradient != nullptr also J_rot^T r (added to
  // *gradient), with blocks != nullptr J_rot^T J_rot per rot node (9x9 each). Each rot node
  // writes only its own gradient entries and block; the cost is summed per
  // chunk of GaussNewtonThreads::chunk_size nodes, then the chunks in order
  // (one chunk: the plain sum).
  double RotCost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                 std::vector<Matrix9d>* blocks) const {
    const int count = static_cast<int>(rot_nodes.size());
    const int chunk = threads.chunk_size;
    const int num_chunks = (count + chunk - 1) / chunk;
    chunk_sums.assign(num_chunks, 0.0);
    const bool parallel = threads.num_threads > 1 && num_chunks > 1 &&
                          count >= threads.min_parallel_terms;
#pragma omp parallel for schedule(static) num_threads(threads.num_threads) if (parallel)
    for (int c = 0; c < num_chunks; ++c) {
      Eigen::Matrix<double, 6, 9> jacobian;
      Eigen::Matrix<double, 6, 1> r;
      double sum = 0.0;
      for (int i = c * chunk; i < std::min(count, (c + 1) * chunk); ++i) {
        const int o = offset[rot_nodes[i]];
        const bool derivatives = gradient != nullptr || blocks != nullptr;
        RotResiduals(x.data() + o, sqrt_rot, r.data(), derivatives ? &jacobian : nullptr);
        sum += r.squaredNorm();
        if (gradient != nullptr) gradient->segment<9>(o) += jacobian.transpose() * r;
        if (blocks != nullptr) (*blocks)[i].noalias() = jacobian.transpose() * jacobian;
      }
      chunk_sums[c] = sum;
    }
    double sum = 0.0;
    for (double chunk_sum : chunk_sums) sum += chunk_sum;
    return 0.5 * sum;
  }

  // The nonlinear terms at x: Rot (its specialised 9x9 path, the numbers of
  // before the generic terms) plus DeformationEnergy::terms' nonlinear ones,
  // whose J^T J entries go to term_values.
  double NonlinearCost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
    const double rot = RotCost(x, gradient, nullptr);
    if (!terms.has_nonlinear()) return rot;
    return rot + terms.Cost(x, gradient, gradient != nullptr ? &term_values : nullptr);
  }
};

GaussNewtonSolver::GaussNewtonSolver(const GaussNewtonOptions& options,
                                     const StoppingRule& stopping,
                                     const GaussNewtonThreads& threads)
    : options_(options), stopping_(stopping), threads_(threads) {}
GaussNewtonSolver::~GaussNewtonSolver() = default;

bool GaussNewtonSolver::Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
                              std::string* error) {
  if (!options_.Check(error) || !stopping_.Check(error)) return false;
  CHECK_EQ(static_cast<int>(energy.node_class.size()), transforms.num_nodes());
  if (!energy.families.empty()) {
    *error = energy.families.front()->name() +
             " needs its own frame solver (MakeFrameSolver, solvers/frame_solver_factory.h)";
    return false;
  }
  impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  impl.options = options_;
  impl.threads = threads_;
  impl.threads.num_threads = std::max(1, threads_.num_threads);
  impl.threads.chunk_size = std::max(1, threads_.chunk_size);
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
  std::vector<char> has_rot(num_nodes, 0);
  for (int j : energy.rot_nodes) {
    CHECK_GE(impl.offset[j], 0) << "Rot term on a Fixed node";
    CHECK(!has_rot[j]) << "two Rot terms on node " << j;  // RotCost's chunks write per node
    has_rot[j] = 1;
    impl.rot_nodes.push_back(j);
  }
  if (!impl.terms.Setup(energy.terms, impl.offset, impl.totally_free, transforms, error))
    return false;
  LinearTerms linear;
  AssembleLinearTerms(energy, transforms, impl.offset, impl.terms, n, &linear,
                      impl.threads.num_threads, impl.threads.min_parallel_rows);
  impl.hessian = std::move(linear.hessian);
  impl.hessian_rows = impl.hessian;
  impl.CompactHessian();
  impl.linear_gradient = std::move(linear.linear_gradient);
  impl.num_handle_groups = linear.num_handle_groups;
  impl.handle_gradient = std::move(linear.handle_gradient);
  impl.root = std::move(linear.root);
  impl.root_handle = std::move(linear.root_handle);
  impl.root.makeCompressed();  // read by hand (LinearCost, RootOffset)
  impl.root_handle.makeCompressed();

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

double GaussNewtonSolver::Cost(const HandleTransforms& handles, const NodeTransforms& transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  const Impl& impl = *impl_;
  CHECK_EQ(static_cast<int>(impl.offset.size()), transforms.num_nodes());
  const Eigen::VectorXd x = impl.Gather(transforms);
  return impl.LinearCost(x, impl.RootOffset(handles)) +
         impl.NonlinearCost(x, nullptr);
}

// One frame of Eq. 17 for the damped Gauss-Newton loop: x, and what its
// cost is kept from. The linear terms' cost is taken from their residuals
// at the start and after every accepted step; a trial step's cost adds to it
// the change of the quadratic, delta^T (H x + g0) + 1/2 delta^T H delta
// (small terms only: kept from step to step, its rounding reached 2.4e-9 of
// the energy on the 416K claw in one step).
class GaussNewtonSolver::Frame : public DampedGaussNewtonProblem {
 public:
  Frame(Impl* impl, const HandleTransforms& handles, const NodeTransforms& transforms)
      : impl_(*impl),
        x_(impl->Gather(transforms)),
        g0_(impl->HandleGradient(handles)),
        root_offset_(impl->RootOffset(handles)),
        blocks_(impl->rot_nodes.size()) {
    impl_.HessianTimes(x_, &hx_);
    linear_cost_ = impl_.LinearCost(x_, root_offset_);
    gradient_ = hx_ + g0_;
    // The 9x9 blocks only when J^T J is assembled (a chord step does not
    // read them; they were 15% of a chord step on the 104K claw).
    cost_ = linear_cost_ + impl_.NonlinearCost(x_, &gradient_);
  }

  const Eigen::VectorXd& x() const { return x_; }
  int num_variables() const override { return static_cast<int>(x_.size()); }
  double cost() const override { return cost_; }
  const Eigen::VectorXd& gradient() const override { return gradient_; }
  double x_norm() const override { return x_.norm(); }
  void Assemble(double mu) override {
    impl_.RotCost(x_, nullptr, &blocks_);
    impl_.Assemble(blocks_, mu);
  }
  SparseMatrix& system() override { return impl_.system; }
  void StepRhs(Eigen::VectorXd* rhs) const override { *rhs = -gradient_; }
  // 1/2 delta^T (mu D delta - g), D from J^T J.
  double PredictedDecrease(const Eigen::VectorXd& delta, double mu) const override {
    double damped = 0.0;
    const double* values = impl_.system.valuePtr();
    for (int i = 0; i < num_variables(); ++i) {
      const double d = values[impl_.diagonal_index[i]];
      damped += delta[i] * delta[i] * (d - d / (1.0 + mu));  // mu D_ii
    }
    return 0.5 * (damped - delta.dot(gradient_));
  }
  double TrialCost(const Eigen::VectorXd& delta) override {
    x_new_ = x_ + delta;
    impl_.HessianTimes(delta, &h_delta_);
    const double new_linear_cost =
        linear_cost_ + delta.dot(hx_ + g0_) + 0.5 * delta.dot(h_delta_);
    return new_linear_cost + impl_.NonlinearCost(x_new_, nullptr);
  }
  void Accept() override {
    x_.swap(x_new_);
    hx_ += h_delta_;
    linear_cost_ = impl_.LinearCost(x_, root_offset_);
    gradient_ = hx_ + g0_;
    cost_ = linear_cost_ + impl_.NonlinearCost(x_, &gradient_);
  }

 private:
  Impl& impl_;
  Eigen::VectorXd x_;
  const Eigen::VectorXd g0_;
  const Eigen::VectorXd root_offset_;
  std::vector<Matrix9d> blocks_;
  Eigen::VectorXd hx_;  // H x
  double linear_cost_ = 0.0;
  Eigen::VectorXd gradient_;
  double cost_ = 0.0;
  Eigen::VectorXd x_new_, h_delta_;  // the last trial
};

SolveSummary GaussNewtonSolver::Solve(const HandleTransforms& handles,
                                      NodeTransforms* transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  const auto start = std::chrono::steady_clock::now();
  Impl& impl = *impl_;
  CHECK_EQ(static_cast<int>(impl.offset.size()), transforms->num_nodes());
  Frame frame(&impl, handles, *transforms);
  SolveSummary summary;
  summary.initial_cost = frame.cost();
  summary.trace.push_back({0.0, frame.cost()});
  RunDampedGaussNewton(options_, stopping_, start, impl.linear_solver.get(), &frame, &impl.state,
                       &summary);
  impl.Scatter(frame.x(), transforms);
  return summary;
}

}  // namespace msdeform
