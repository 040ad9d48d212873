#include "msdeform/solvers/gauss_newton_terms.h"

#include <algorithm>
#include <limits>

#include <glog/logging.h>

namespace msdeform {

bool GaussNewtonTerms::Setup(const std::vector<EnergyTerm>& terms, const std::vector<int>& offset,
                             const std::vector<char>& totally_free,
                             const NodeTransforms& transforms, std::string* error) {
  offset_ = offset;
  totally_free_ = totally_free;
  constants_ = transforms;
  linear_.clear();
  nonlinear_.clear();
  value_index_.clear();
  for (const EnergyTerm& term : terms) {
    if (!CheckEnergyTerm(term, transforms.num_nodes(), error)) return false;
    (term.linear ? linear_ : nonlinear_).push_back(Prepare(term));
  }
  return true;
}

GaussNewtonTerms::Term GaussNewtonTerms::Prepare(const EnergyTerm& term) const {
  Term prepared;
  prepared.cost.reset(term.NewCostFunction(false));
  for (const TermBlock& block : term.blocks) {
    const int o = offset_[block.node];
    const bool rotation = block.kind == TermBlock::Kind::kRotation;
    int variable = -1;
    if (o >= 0 && rotation) variable = o;
    if (o >= 0 && !rotation && totally_free_[block.node]) variable = o + 9;
    prepared.variable.push_back(variable);
    prepared.constant.push_back(rotation ? constants_.rotations.col(block.node).data()
                                         : constants_.translations.col(block.node).data());
    prepared.size.push_back(block.size());
  }
  return prepared;
}

void GaussNewtonTerms::Evaluate(const Term& term, const Eigen::VectorXd& x, double* residuals,
                                std::vector<std::vector<double>>* jacobians) const {
  const int m = term.cost->num_residuals();
  const size_t num_blocks = term.variable.size();
  std::vector<const double*> parameters(num_blocks);
  std::vector<double*> jacobian_pointers(num_blocks, nullptr);
  if (jacobians != nullptr) jacobians->resize(num_blocks);
  for (size_t b = 0; b < num_blocks; ++b) {
    const bool variable = term.variable[b] >= 0;
    parameters[b] = variable ? x.data() + term.variable[b] : term.constant[b];
    if (jacobians != nullptr && variable) {
      (*jacobians)[b].assign(m * term.size[b], 0.0);
      jacobian_pointers[b] = (*jacobians)[b].data();
    }
  }
  if (!term.cost->Evaluate(parameters.data(), residuals,
                           jacobians != nullptr ? jacobian_pointers.data() : nullptr)) {
    // A term that cannot be evaluated here (a point outside its domain)
    // makes the cost NaN, as Ceres treats it: a trial step there is
    // rejected, and a frame that starts there fails with "the cost is not
    // finite" instead of stopping the program.
    std::fill(residuals, residuals + m, std::numeric_limits<double>::quiet_NaN());
    if (jacobians != nullptr) {
      for (std::vector<double>& block : *jacobians) std::fill(block.begin(), block.end(), 0.0);
    }
  }
}

void GaussNewtonTerms::AppendLinearRows(std::vector<Triplet>* a_entries,
                                        std::vector<double>* constant, int* row) const {
  int n = 0;
  for (size_t j = 0; j < offset_.size(); ++j)
    if (offset_[j] >= 0) n = std::max(n, offset_[j] + (totally_free_[j] ? 12 : 9));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  std::vector<std::vector<double>> jacobians;
  for (const Term& term : linear_) {
    const int m = term.cost->num_residuals();
    std::vector<double> residuals(m);
    Evaluate(term, zero, residuals.data(), &jacobians);
    constant->resize(*row + m, 0.0);
    for (int r = 0; r < m; ++r) {
      (*constant)[*row + r] += residuals[r];
      for (size_t b = 0; b < term.variable.size(); ++b) {
        if (term.variable[b] < 0) continue;
        for (int p = 0; p < term.size[b]; ++p) {
          const double value = jacobians[b][r * term.size[b] + p];
          if (value != 0.0) a_entries->emplace_back(*row + r, term.variable[b] + p, value);
        }
      }
    }
    *row += m;
  }
}

void GaussNewtonTerms::AppendPattern(std::vector<Triplet>* entries) const {
  for (const Term& term : nonlinear_) {
    for (size_t a = 0; a < term.variable.size(); ++a) {
      if (term.variable[a] < 0) continue;
      for (size_t b = 0; b < term.variable.size(); ++b) {
        if (term.variable[b] < 0) continue;
        for (int c = 0; c < term.size[b]; ++c)
          for (int r = 0; r < term.size[a]; ++r)
            entries->emplace_back(term.variable[a] + r, term.variable[b] + c, 0.0);
      }
    }
  }
}

void GaussNewtonTerms::IndexValues(const SparseMatrix& system) {
  value_index_.clear();
  for (const Term& term : nonlinear_) {
    for (size_t a = 0; a < term.variable.size(); ++a) {
      if (term.variable[a] < 0) continue;
      for (size_t b = 0; b < term.variable.size(); ++b) {
        if (term.variable[b] < 0) continue;
        for (int c = 0; c < term.size[b]; ++c) {
          const int col = term.variable[b] + c;
          for (int r = 0; r < term.size[a]; ++r) {
            const int row = term.variable[a] + r;
            const int* begin = system.innerIndexPtr() + system.outerIndexPtr()[col];
            const int* end = system.innerIndexPtr() + system.outerIndexPtr()[col + 1];
            const int* found = std::lower_bound(begin, end, row);
            CHECK(found != end && *found == row) << "term entry not in the pattern";
            value_index_.push_back(static_cast<int>(found - system.innerIndexPtr()));
          }
        }
      }
    }
  }
}

double GaussNewtonTerms::Cost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                              std::vector<double>* values) const {
  double sum = 0.0;
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobians;
  if (values != nullptr) values->clear();
  for (const Term& term : nonlinear_) {
    const int m = term.cost->num_residuals();
    residuals.assign(m, 0.0);
    Evaluate(term, x, residuals.data(), gradient != nullptr ? &jacobians : nullptr);
    for (double r : residuals) sum += r * r;
    if (gradient == nullptr) continue;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), m);
    for (size_t a = 0; a < term.variable.size(); ++a) {
      if (term.variable[a] < 0) continue;
      const Eigen::Map<const RowMajor> J_a(jacobians[a].data(), m, term.size[a]);
      gradient->segment(term.variable[a], term.size[a]) += J_a.transpose() * r;
      for (size_t b = 0; b < term.variable.size(); ++b) {
        if (term.variable[b] < 0) continue;
        const Eigen::Map<const RowMajor> J_b(jacobians[b].data(), m, term.size[b]);
        const Eigen::MatrixXd block = J_a.transpose() * J_b;  // column-major
        values->insert(values->end(), block.data(), block.data() + block.size());
      }
    }
  }
  return 0.5 * sum;
}

void GaussNewtonTerms::AddValues(const std::vector<double>& values,
                                 double* system_values) const {
  for (size_t k = 0; k < values.size(); ++k) system_values[value_index_[k]] += values[k];
}

}  // namespace msdeform
