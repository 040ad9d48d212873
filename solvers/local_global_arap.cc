#include "msdeform/solvers/local_global_arap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <glog/logging.h>
#ifdef MSDEFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "msdeform/core/cotangent_weights.h"
#include "msdeform/core/parallel.h"
#include "msdeform/core/timing.h"
#include "msdeform/solvers/anderson_acceleration.h"

namespace msdeform {
namespace {

// Vertices per task of the local step and of the right-hand side.
constexpr int64_t kChunk = 4096;

// The rotation maximising tr(R^T S): the orthogonal factor of the polar
// decomposition S = R P by Newton's iteration with Frobenius-norm scaling
// (Higham 1986), X <- (g X + X^-T / g) / 2, g = (|X^-1| / |X|)^(1/2), which
// converges quadratically from X = S in about 5 steps; for S with det S <= 0
// or nearly singular (a flat one-ring: rank 2) the SVD, U diag(1, 1, det U V^T) V^T.
// Exact to rounding either way (the local step must be exact for the
// iteration never to raise the energy), and about 3x faster than the SVD on
// the one-rings of a curved surface.
Eigen::Matrix3d FitRotation(const Eigen::Matrix3d& covariance) {
  const double norm = covariance.norm();
  if (!(covariance.determinant() > 1e-6 * norm * norm * norm)) {
    if (norm == 0.0) return Eigen::Matrix3d::Identity();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) *= -1.0;
    return u * svd.matrixV().transpose();
  }
  Eigen::Matrix3d x = covariance;
  for (int k = 0; k < 30; ++k) {
    const Eigen::Matrix3d inverse = x.inverse();
    const double g = std::sqrt(std::sqrt(inverse.squaredNorm() / x.squaredNorm()));
    const Eigen::Matrix3d next = 0.5 * (g * x + inverse.transpose() / g);
    const double change = (next - x).squaredNorm();
    x = next;
    // Quadratic convergence: a step of size d leaves x about d^2 / 2 from
    // the rotation, so d^2 <= 1e-16 means rounding already dominates.
    if (change <= 1e-16) break;
  }
  return x;
}

}  // namespace

const EnumNames<LocalGlobalArapOptions::Factorization>& LocalGlobalArapFactorizationNames() {
  using F = LocalGlobalArapOptions::Factorization;
  static const EnumNames<F> names{
      {F::kAuto, "auto"}, {F::kSimplicial, "simplicial"}, {F::kCholmod, "cholmod"}};
  return names;
}

bool LocalGlobalArapOptions::Check(std::string* error) const {
  if (!(relative_tolerance >= 0.0) || !std::isfinite(relative_tolerance)) {
    *error = "relative_tolerance must be finite and >= 0";
    return false;
  }
  if (max_iterations < 0) {
    *error = "max_iterations must be >= 0";
    return false;
  }
  if (anderson_window < 0) {
    *error = "anderson_window must be >= 0";
    return false;
  }
  if (num_threads < 0) {
    *error = "num_threads must be >= 0";
    return false;
  }
#ifndef MSDEFORM_HAVE_CHOLMOD
  if (factorization == Factorization::kCholmod) {
    *error = "factorization=cholmod: msdeform was built without CHOLMOD (libsuitesparse-dev)";
    return false;
  }
#endif
  return true;
}

struct LocalGlobalArap::Impl {
  LocalGlobalArapOptions options;
  Eigen::Matrix3Xd rest;
  CotangentWeights cotangent;
  double normaliser = 0.0;  // sum over spokes of w |r_i - r_k|^2
  // -1 for a constant vertex (constrained, or reached by no constraint),
  // else its row in the Laplacian.
  std::vector<int> free_index;
  std::vector<int> free_vertices;
  std::vector<int> constrained;
  // Vertices whose spokes can change during a solve (free, or a neighbour
  // of a free vertex), and the others, whose spokes join constants: their
  // energy is summed once per Solve.
  std::vector<int> active, inactive;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
#ifdef MSDEFORM_HAVE_CHOLMOD
  // Factorization::kCholmod's factor (llt is then empty).
  std::unique_ptr<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>> cholmod;
#endif
  // Per vertex: the last local step's rotation.
  std::vector<Eigen::Matrix3d> rotation;
  double setup_ms = 0.0;

  // The local step at `x` over `vertices`: fits their rotations into
  // *rotations and returns the sum of their
  // spokes' energy, not normalised.
  double Local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices,
               std::vector<Eigen::Matrix3d>* rotations) const;
  // The global step: the free vertices' positions minimising the energy for
  // the rotations, the constant ones read from `x`; n_free by 3.
  Eigen::MatrixXd Global(const Eigen::Matrix3Xd& x,
                         const std::vector<Eigen::Matrix3d>& rotations) const;
};

double LocalGlobalArap::Impl::Local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices,
                                    std::vector<Eigen::Matrix3d>* rotations) const {
  const int n = static_cast<int>(vertices.size());
  const VertexAdjacency& adjacency = cotangent.adjacency;
  std::vector<double> chunk_energy(NumChunks(n, kChunk), 0.0);
  ForEachChunk(n, kChunk, ThreadsFor(options.num_threads, n),
               [&](int64_t begin, int64_t end, int64_t chunk) {
                 double energy = 0.0;
                 for (int64_t index = begin; index < end; ++index) {
                   const int i = vertices[index];
                   Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
                   const int first = adjacency.offsets[i], last = adjacency.offsets[i + 1];
                   for (int s = first; s < last; ++s) {
                     const int k = adjacency.neighbors[s];
                     covariance.noalias() += cotangent.weight[s] * (x.col(i) - x.col(k)) *
                                             (rest.col(i) - rest.col(k)).transpose();
                   }
                   Eigen::Matrix3d& r = (*rotations)[i];
                   if (first < last) r = FitRotation(covariance);
                   for (int s = first; s < last; ++s) {
                     const int k = adjacency.neighbors[s];
                     energy += cotangent.weight[s] *
                               ((x.col(i) - x.col(k)) - r * (rest.col(i) - rest.col(k)))
                                   .squaredNorm();
                   }
                 }
                 chunk_energy[chunk] = energy;
               });
  double energy = 0.0;
  for (double e : chunk_energy) energy += e;
  return energy;
}

Eigen::MatrixXd LocalGlobalArap::Impl::Global(
    const Eigen::Matrix3Xd& x, const std::vector<Eigen::Matrix3d>& rotations) const {
  const int num_free = static_cast<int>(free_vertices.size());
  const VertexAdjacency& adjacency = cotangent.adjacency;
  Eigen::MatrixXd rhs(num_free, 3);
  ForEachChunk(num_free, kChunk, ThreadsFor(options.num_threads, num_free),
               [&](int64_t begin, int64_t end, int64_t) {
                 for (int64_t row = begin; row < end; ++row) {
                   const int i = free_vertices[row];
                   Eigen::Vector3d b = Eigen::Vector3d::Zero();
                   for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
                     const int k = adjacency.neighbors[s];
                     const double w = cotangent.weight[s];
                     b += 0.5 * w *
                          ((rotations[i] + rotations[k]) * (rest.col(i) - rest.col(k)));
                     if (free_index[k] < 0) b += w * x.col(k);
                   }
                   rhs.row(row) = b.transpose();
                 }
               });
#ifdef MSDEFORM_HAVE_CHOLMOD
  if (cholmod != nullptr) return cholmod->solve(rhs);  // the three columns in one pass
#endif
  Eigen::MatrixXd solution(num_free, 3);
  // The three coordinates are independent solves with the one factor.
#pragma omp parallel for num_threads(std::min(3, ThreadsFor(options.num_threads, num_free)))
  for (int d = 0; d < 3; ++d) solution.col(d) = llt.solve(rhs.col(d));
  return solution;
}

LocalGlobalArap::LocalGlobalArap() = default;
LocalGlobalArap::~LocalGlobalArap() = default;

bool LocalGlobalArap::Setup(const Mesh& rest, const std::vector<int>& constrained,
                            const LocalGlobalArapOptions& options, std::string* error) {
  impl_.reset();
  if (!options.Check(error)) return false;
  const auto start = std::chrono::steady_clock::now();
  const int n = rest.num_vertices();
  for (size_t j = 0; j < constrained.size(); ++j) {
    if (constrained[j] < 0 || constrained[j] >= n) {
      *error = "constrained vertex " + std::to_string(constrained[j]) + " is not a vertex (" +
               std::to_string(n) + " vertices)";
      return false;
    }
    if (j > 0 && constrained[j] <= constrained[j - 1]) {
      *error = "constrained vertices must be sorted and unique";
      return false;
    }
  }
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->rest = rest.vertices;
  impl->cotangent = ComputeCotangentWeights(rest);
  impl->constrained = constrained;
  const VertexAdjacency& adjacency = impl->cotangent.adjacency;
  for (int i = 0; i < n; ++i) {
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
      impl->normaliser += impl->cotangent.weight[s] *
                          (rest.vertices.col(i) - rest.vertices.col(adjacency.neighbors[s]))
                              .squaredNorm();
    }
  }

  // Free: every vertex a constraint reaches through edges of positive weight
  // (breadth first from the constrained vertices, numbered in vertex order).
  std::vector<char> is_constrained(n, 0), reached(n, 0);
  std::deque<int> queue;
  for (int v : constrained) {
    is_constrained[v] = 1;
    reached[v] = 1;
    queue.push_back(v);
  }
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
      const int k = adjacency.neighbors[s];
      if (!reached[k] && impl->cotangent.weight[s] > 0.0) {
        reached[k] = 1;
        queue.push_back(k);
      }
    }
  }
  impl->free_index.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    if (reached[i] && !is_constrained[i]) {
      impl->free_index[i] = static_cast<int>(impl->free_vertices.size());
      impl->free_vertices.push_back(i);
    }
  }
  for (int i = 0; i < n; ++i) {
    bool active = impl->free_index[i] >= 0;
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1] && !active; ++s) {
      active = impl->free_index[adjacency.neighbors[s]] >= 0;
    }
    (active ? impl->active : impl->inactive).push_back(i);
  }

  // The Laplacian of the free vertices (lower triangle): L_ii = sum_k w_ik,
  // L_ik = -w_ik.
  const int num_free = static_cast<int>(impl->free_vertices.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(adjacency.neighbors.size() / 2 + num_free);
  for (int row = 0; row < num_free; ++row) {
    const int i = impl->free_vertices[row];
    double diagonal = 0.0;
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
      const double w = impl->cotangent.weight[s];
      diagonal += w;
      const int column = impl->free_index[adjacency.neighbors[s]];
      if (column >= 0 && column < row && w != 0.0) triplets.emplace_back(row, column, -w);
    }
    triplets.emplace_back(row, row, diagonal);
  }
  Eigen::SparseMatrix<double> laplacian(num_free, num_free);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  bool use_cholmod = false;
#ifdef MSDEFORM_HAVE_CHOLMOD
  using Factorization = LocalGlobalArapOptions::Factorization;
  use_cholmod = options.factorization == Factorization::kCholmod ||
                (options.factorization == Factorization::kAuto &&
                 num_free >= LocalGlobalArapOptions::kCholmodFromFreeVertices);
#endif
  bool factorised = false;
  if (!use_cholmod) {
    impl->llt.compute(laplacian);
    factorised = impl->llt.info() == Eigen::Success;
  }
#ifdef MSDEFORM_HAVE_CHOLMOD
  if (use_cholmod && num_free > 0) {
    impl->cholmod = std::make_unique<
        Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>>();
    impl->cholmod->compute(laplacian);
    factorised = impl->cholmod->info() == Eigen::Success;
  }
#endif
  if (num_free > 0 && !factorised) {
    *error = "the ARAP system of " + std::to_string(num_free) +
             " free vertices could not be factorised (not positive definite)";
    return false;
  }
  impl->rotation.assign(n, Eigen::Matrix3d::Identity());
  impl->setup_ms = MillisecondsSince(start);
  impl_ = std::move(impl);
  return true;
}

LocalGlobalArapSummary LocalGlobalArap::Solve(
    const Eigen::Matrix3Xd& targets, Eigen::Matrix3Xd* deformed,
    const std::function<bool(int iterations, double ms)>& stop) {
  CHECK(impl_ != nullptr) << "Solve before a successful Setup";
  Impl& impl = *impl_;
  CHECK_EQ(targets.cols(), static_cast<int64_t>(impl.constrained.size()));
  CHECK_EQ(deformed->cols(), impl.rest.cols());
  const auto start = std::chrono::steady_clock::now();
  Eigen::Matrix3Xd& x = *deformed;
  for (size_t j = 0; j < impl.constrained.size(); ++j) x.col(impl.constrained[j]) = targets.col(j);

  const int num_free = static_cast<int>(impl.free_vertices.size());
  // The free positions as one vector, coordinate-major (x's of every free
  // vertex, then y's, then z's): the accelerated variable.
  auto gather = [&](const Eigen::Matrix3Xd& positions, Eigen::VectorXd* v) {
    v->resize(3 * num_free);
    for (int row = 0; row < num_free; ++row) {
      for (int d = 0; d < 3; ++d) (*v)[d * num_free + row] = positions(d, impl.free_vertices[row]);
    }
  };
  auto scatter = [&](const Eigen::VectorXd& v, Eigen::Matrix3Xd* positions) {
    for (int row = 0; row < num_free; ++row) {
      for (int d = 0; d < 3; ++d) (*positions)(d, impl.free_vertices[row]) = v[d * num_free + row];
    }
  };

  LocalGlobalArapSummary summary;
  const double scale = impl.normaliser > 0.0 ? 1.0 / impl.normaliser : 0.0;
  const double constant_energy = impl.Local(x, impl.inactive, &impl.rotation);
  auto local = [&](const Eigen::Matrix3Xd& positions, std::vector<Eigen::Matrix3d>* r) {
    return (constant_energy + impl.Local(positions, impl.active, r)) * scale;
  };
  double energy = local(x, &impl.rotation);
  summary.initial_energy = energy;
  if (!std::isfinite(energy)) {  // non-finite targets or warm start: nothing to iterate
    summary.final_energy = energy;
    return summary;
  }
  summary.energy_trace.push_back(energy);
  summary.ms_trace.push_back(0.0);
  if (num_free == 0 || energy == 0.0) {
    summary.final_energy = energy;
    summary.converged = true;
    return summary;
  }
  AndersonAcceleration anderson(3 * num_free, impl.options.anderson_window);
  Eigen::VectorXd current, plain, next;
  gather(x, &current);
  // The trial's rotations: the local step writes every active entry, and only
  // active entries are read (the global step reads free vertices and their
  // neighbours), so the buffer is never copied from the accepted one.
  std::vector<Eigen::Matrix3d> trial_rotation = impl.rotation;
  Eigen::Matrix3Xd trial = x;
  while (summary.iterations < impl.options.max_iterations) {
    if (stop && stop(summary.iterations, MillisecondsSince(start))) {
      summary.stopped = true;
      break;
    }
    const Eigen::MatrixXd solution = impl.Global(x, impl.rotation);
    plain = Eigen::Map<const Eigen::VectorXd>(solution.data(), solution.size());
    anderson.Compute(current, plain, &next);
    bool accelerated = anderson.history() > 0;  // next combines past iterates
    scatter(next, &trial);
    double trial_energy = local(trial, &trial_rotation);
    // The safeguard: an accelerated step that does not lower the energy is
    // replaced by the plain local/global step.
    if (accelerated && !(trial_energy < energy)) {
      ++summary.rejected;
      anderson.Reset();
      accelerated = false;
      next = plain;
      scatter(next, &trial);
      trial_energy = local(trial, &trial_rotation);
    }
    ++summary.iterations;
    // A plain step never raises the energy but by rounding: at the minimum
    // it may, and then the previous iterate is the result.
    if (!accelerated && trial_energy > energy) {
      summary.converged = true;
      break;
    }
    const double decrease = energy - trial_energy;
    std::swap(x, trial);
    std::swap(impl.rotation, trial_rotation);
    std::swap(current, next);
    energy = trial_energy;
    summary.energy_trace.push_back(energy);
    summary.ms_trace.push_back(MillisecondsSince(start));
    if (decrease <= impl.options.relative_tolerance * (energy + decrease)) {
      // Only a plain step's small decrease says the iteration has converged:
      // an extrapolation can land close to the last iterate while the plain
      // step would still go far. Let the next step be a plain one.
      if (!accelerated) {
        summary.converged = true;
        break;
      }
      anderson.Reset();
    }
  }
  summary.final_energy = energy;
  return summary;
}

double LocalGlobalArap::Energy(const Eigen::Matrix3Xd& deformed) const {
  CHECK(impl_ != nullptr);
  CHECK_EQ(deformed.cols(), impl_->rest.cols());
  std::vector<Eigen::Matrix3d> rotations = impl_->rotation;
  const double energy = impl_->Local(deformed, impl_->active, &rotations) +
                        impl_->Local(deformed, impl_->inactive, &rotations);
  return impl_->normaliser > 0.0 ? energy / impl_->normaliser : 0.0;
}

int LocalGlobalArap::num_free() const {
  return impl_ ? static_cast<int>(impl_->free_vertices.size()) : 0;
}
int LocalGlobalArap::num_vertices() const {
  return impl_ ? static_cast<int>(impl_->rest.cols()) : 0;
}
const LocalGlobalArapOptions& LocalGlobalArap::options() const {
  CHECK(impl_ != nullptr);
  return impl_->options;
}
double LocalGlobalArap::setup_ms() const { return impl_ ? impl_->setup_ms : 0.0; }

}  // namespace msdeform
