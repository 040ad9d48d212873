#include "msdeform/methods/fastlsm.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <utility>

#include "msdeform/core/timing.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "msdeform/scales/polar_decomposition.h"

namespace msdeform {
namespace {

using Clock = std::chrono::steady_clock;
// Polar decomposition of the skinning fits: warm-started updates per frame.
constexpr int kMaxRotationIterations = 20;
constexpr double kRotationTolerance = 1e-9;

}  // namespace

bool FastLsmOptions::Check(std::string* error) const {
  // The table's ranges, named as MethodOptionTable() names the row.
  if (FastLsmOptionTable().CheckRanges(*this, error)) return true;
  *error = "fastlsm." + *error;
  return false;
}

bool FastLsm::DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) {
  const auto start = Clock::now();
  if (!options.fastlsm.Check(error)) return false;
  options_ = options.fastlsm;
  if (!ValidateMesh(mesh, error)) return false;
  if (!Lattice::Build(mesh, options.deformer.lattice, &lattice_, error)) return false;
  RigidityOptions matching;
  matching.model = RigidityModel::kShapeMatching;
  matching.region_half_width = options_.region_half_width;
  if (!shape_matching_.Init(lattice_, matching, error)) return false;
  mesh_ = mesh;
  deformed_vertices_ = mesh.vertices;
  positions_ = lattice_.rest_positions();
  kind_.assign(lattice_.num_particles(), Kind::kFree);
  num_free_ = lattice_.num_particles();
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool FastLsm::DoSetHandles(const HandleLayout& layout, std::string* error) {
  const auto start = Clock::now();
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  const int n = lattice_.num_particles();
  // Each handle group drives the particles of its vertices' cells; a cell
  // holding a fixed vertex stays fixed.
  if (!HandleGroupOfParticles(lattice_, layout, &driven_group_, error)) return false;
  kind_.assign(n, Kind::kFree);
  num_free_ = 0;
  for (int p = 0; p < n; ++p) {
    kind_[p] = driven_group_[p] == kFixedParticle ? Kind::kFixed
               : driven_group_[p] >= 0            ? Kind::kDriven
                                                  : Kind::kFree;
    num_free_ += kind_[p] == Kind::kFree;
  }
  positions_ = lattice_.rest_positions();
  velocities_ = Eigen::Matrix3Xd::Zero(3, n);
  rotations_.assign(n, Eigen::Quaterniond::Identity());
  first_step_ = true;
  deformed_vertices_ = mesh_.vertices;
  setup_ms_ = MillisecondsSince(start);
  return true;
}

bool FastLsm::DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                     std::string* error) {
  const auto frame_start = Clock::now();
  *stats = MethodStats();
  const Eigen::Matrix3Xd& rest = lattice_.rest_positions();
  const int n = lattice_.num_particles();
  for (int i = 0; i < n; ++i) {
    if (kind_[i] == Kind::kDriven) {
      positions_.col(i) = deformed_from_rest[driven_group_[i]] * rest.col(i);
      velocities_.col(i).setZero();
    }
  }
  const double keep = 1.0 - options_.damping;
  for (int step = 0; step < options_.steps_per_frame; ++step) {
    // Each region's rotation warm-started from the step before (from the
    // identity on a layout's first step).
    shape_matching_.ComputeGoals(positions_, &goals_, /*warm_start=*/!first_step_);
    first_step_ = false;
    for (int i = 0; i < n; ++i) {
      if (kind_[i] != Kind::kFree) continue;
      velocities_.col(i) = keep * (velocities_.col(i) + goals_.col(i) - positions_.col(i));
      positions_.col(i) += velocities_.col(i);
    }
  }
  stats->solve_ms = MillisecondsSince(frame_start);
  const auto skin_start = Clock::now();
  Skin(deformed_from_rest);
  stats->skin_ms = MillisecondsSince(skin_start);
  if (!deformed_vertices_.allFinite()) {
    *error = "fastlsm produced non-finite positions (lower the steps or raise the damping)";
    return false;
  }
  stats->iterations = options_.steps_per_frame;
  stats->initial_cost = stats->final_cost = std::numeric_limits<double>::quiet_NaN();
  stats->converged = true;
  stats->frame_ms = MillisecondsSince(frame_start);
  return true;
}

void FastLsm::Skin(const HandleTransforms& deformed_from_rest) {
  const Eigen::Matrix3Xd& rest = lattice_.rest_positions();
  const CompressedLists& regions = shape_matching_.regions();
  const CompressedLists& adjacency = lattice_.particle_adjacency();
  const int n = lattice_.num_particles();
  const double w = lattice_.cell_width();
  // Each particle's frame, fitted once per frame when a vertex needs it.
  std::vector<char> fitted(n, 0);
  std::vector<Eigen::Matrix3d> rotation(n);
  Eigen::Matrix3Xd centroid(3, n), rest_centroid(3, n);
  auto frame_of = [&](int p, const Eigen::Vector3d& x0) -> Eigen::Vector3d {
    if (kind_[p] == Kind::kFixed) return x0;
    if (kind_[p] == Kind::kDriven) return deformed_from_rest[driven_group_[p]] * x0;
    if (!fitted[p]) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), c0 = Eigen::Vector3d::Zero();
      for (const int* j = regions.begin(p); j != regions.end(p); ++j) {
        c += positions_.col(*j);
        c0 += rest.col(*j);
      }
      c /= regions.size(p);
      c0 /= regions.size(p);
      Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
      for (const int* j = regions.begin(p); j != regions.end(p); ++j) {
        a += (positions_.col(*j) - c) * (rest.col(*j) - c0).transpose();
      }
      ExtractRotation(a, kMaxRotationIterations, kRotationTolerance, &rotations_[p]);
      rotation[p] = rotations_[p].toRotationMatrix();
      centroid.col(p) = c;
      rest_centroid.col(p) = c0;
      fitted[p] = 1;
    }
    return rotation[p] * (x0 - rest_centroid.col(p)) + centroid.col(p);
  };
  // Trilinear hat weight of particle j at rest point x0 (cell centres are
  // the particles' rest positions, one cell width apart).
  auto weight = [&](int j, const Eigen::Vector3d& x0) {
    const Eigen::Vector3d d = ((x0 - rest.col(j)).cwiseAbs() / w);
    return std::max(0.0, 1.0 - d.x()) * std::max(0.0, 1.0 - d.y()) *
           std::max(0.0, 1.0 - d.z());
  };
  for (int v = 0; v < mesh_.num_vertices(); ++v) {
    const int p = lattice_.particle_of_vertex(v);
    const Eigen::Vector3d x0 = mesh_.vertices.col(v);
    if (kind_[p] != Kind::kFree) {
      deformed_vertices_.col(v) = frame_of(p, x0);
      continue;
    }
    // The vertex's particle (weight >= 1/8: the vertex is inside its cell)
    // and its lattice neighbours, blended by their trilinear weights.
    double total = weight(p, x0);
    Eigen::Vector3d sum = total * frame_of(p, x0);
    for (const int* j = adjacency.begin(p); j != adjacency.end(p); ++j) {
      const double wj = weight(*j, x0);
      if (wj <= 0.0) continue;
      sum += wj * frame_of(*j, x0);
      total += wj;
    }
    deformed_vertices_.col(v) = sum / total;
  }
}

MSDEFORM_REGISTER_METHODS(fastlsm, registry) {
  MethodDescriptor fastlsm;
  fastlsm.name = "fastlsm";
  fastlsm.energy = "shape_matching";
  fastlsm.options = "fastlsm";
  fastlsm.deformer_rows = {"lattice"};
  fastlsm.add_option_rows = [](OptionTable<MethodOptions>* t) {
    t->Embed("fastlsm", &MethodOptions::fastlsm, FastLsmOptionTable());
  };
  fastlsm.create = [] { return std::make_unique<FastLsm>(); };
  registry->push_back(std::move(fastlsm));
}

}  // namespace msdeform
