#include "msdeform/scales/rigidity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <unordered_map>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <glog/logging.h>

#include "msdeform/core/parallel.h"
#include "msdeform/scales/polar_decomposition.h"

namespace msdeform {
namespace {

// A uniformly random unit vector from the raw 64-bit outputs of the engine
// (std::mt19937_64's outputs are fixed by the standard; the std::*_distribution
// algorithms are not), so a seed gives the same direction on every platform.
Eigen::Vector3d RandomDirection(std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  const double u1 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  const double z = 2.0 * u1 - 1.0;
  const double radius = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * M_PI * u2;
  return Eigen::Vector3d(radius * std::cos(phi), radius * std::sin(phi), z);
}

// Particles a task of the per-particle loops takes (a few hundred
// microseconds of work; the lattice has a few thousand particles).
constexpr int64_t kParticleChunk = 256;

// Regions R_i: i and its r-ring in `adjacency`, sorted; each chunk of
// particles on its own, the chunks' lists joined in order.
CompressedLists RingsOf(const CompressedLists& adjacency, int half_width, int num_threads) {
  const int n = adjacency.num_rows();
  std::vector<std::vector<int>> chunk_values(NumChunks(n, kParticleChunk));
  std::vector<int64_t> sizes(n);
  ForEachChunk(n, kParticleChunk, num_threads, [&](int64_t begin, int64_t end, int64_t c) {
    std::vector<int> stamp(n, -1);
    std::vector<int> ring;
    for (int i = static_cast<int>(begin); i < end; ++i) {
      ring.assign(1, i);
      stamp[i] = i;
      std::size_t front = 0;
      for (int depth = 0; depth < half_width; ++depth) {
        const std::size_t back = ring.size();
        for (; front < back; ++front) {
          for (const int* j = adjacency.begin(ring[front]); j != adjacency.end(ring[front]);
               ++j) {
            if (stamp[*j] == i) continue;
            stamp[*j] = i;
            ring.push_back(*j);
          }
        }
      }
      std::sort(ring.begin(), ring.end());
      chunk_values[c].insert(chunk_values[c].end(), ring.begin(), ring.end());
      sizes[i] = static_cast<int64_t>(ring.size());
    }
  });
  CompressedLists rings;
  rings.offsets.resize(n + 1);
  rings.offsets[0] = 0;
  for (int i = 0; i < n; ++i) rings.offsets[i + 1] = rings.offsets[i] + sizes[i];
  rings.values.reserve(rings.offsets[n]);
  for (const std::vector<int>& values : chunk_values) {
    rings.values.insert(rings.values.end(), values.begin(), values.end());
  }
  return rings;
}

bool ValidParticles(const std::vector<int>& particles, int num_particles, const char* what,
                    std::string* error) {
  for (std::size_t k = 0; k < particles.size(); ++k) {
    if (particles[k] < 0 || particles[k] >= num_particles) {
      std::ostringstream message;
      message << what << " particle id " << particles[k] << " (entry " << k
              << ") is out of range [0, " << num_particles << ")";
      *error = message.str();
      return false;
    }
  }
  return true;
}

}  // namespace

const EnumNames<RigidityModel>& RigidityModelNames() {
  static const EnumNames<RigidityModel> names = {{RigidityModel::kHarmonic, "harmonic"},
                                                 {RigidityModel::kShapeMatching, "paper"}};
  return names;
}

const char* RigidityModelName(RigidityModel model) { return RigidityModelNames().Name(model); }

bool ParseRigidityModel(const std::string& name, RigidityModel* model) {
  return RigidityModelNames().Parse(name, model);
}

const EnumNames<RegionSummation>& RegionSummationNames() {
  static const EnumNames<RegionSummation> names = {{RegionSummation::kBox, "box"},
                                                   {RegionSummation::kPerRegion, "per_region"}};
  return names;
}

bool RigidityOptions::Check(std::string* error) const {
  // The ranges are RigidityOptionTable()'s rows (rigidity.h).
  if (!RigidityOptionTable().CheckRanges(*this, error)) return false;
  if (external_stiffness * time_step * time_step > 1.0) {
    *error = "external_stiffness * time_step^2 (k_ext h^2) must be <= 1 for a stable step";
    return false;
  }
  return true;
}

bool ParticlesOfVertices(const Lattice& lattice, const std::vector<int>& vertices,
                         std::vector<int>* particles, std::string* error) {
  CHECK(particles != nullptr);
  const int num_vertices = static_cast<int>(lattice.particle_of_vertex().size());
  particles->clear();
  particles->reserve(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    if (vertices[k] < 0 || vertices[k] >= num_vertices) {
      std::ostringstream message;
      message << "vertex id " << vertices[k] << " (entry " << k << ") is out of range [0, "
              << num_vertices << ")";
      *error = message.str();
      return false;
    }
    particles->push_back(lattice.particle_of_vertex(vertices[k]));
  }
  std::sort(particles->begin(), particles->end());
  particles->erase(std::unique(particles->begin(), particles->end()), particles->end());
  return true;
}

bool HandleGroupOfParticles(const Lattice& lattice, const HandleLayout& layout,
                            std::vector<int>* group_of_particle, std::string* error) {
  std::vector<int> fixed;
  if (!ParticlesOfVertices(lattice, layout.fixed, &fixed, error)) return false;
  std::vector<int>& group = *group_of_particle;
  group.assign(lattice.num_particles(), -1);
  for (int p : fixed) group[p] = kFixedParticle;
  const int num_vertices = static_cast<int>(lattice.particle_of_vertex().size());
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    const int v = layout.moveable[i];
    if (v < 0 || v >= num_vertices) {
      *error = "vertex id " + std::to_string(v) + " is out of range [0, " +
               std::to_string(num_vertices) + ")";
      return false;
    }
    const int g = layout.group_of(i);
    int& cell = group[lattice.particle_of_vertex(v)];
    if (cell == kFixedParticle) continue;  // held at rest
    if (cell >= 0 && cell != g) {
      *error = "a lattice cell holds vertices of handle groups " + std::to_string(cell) + " and " +
               std::to_string(g) + " (vertex " + std::to_string(v) +
               "): a cell follows one handle; separate the handles or refine the lattice";
      return false;
    }
    cell = g;
  }
  const int num_groups = layout.num_groups();
  std::vector<char> moves(num_groups, 0);
  for (int cell : group) {
    if (cell >= 0) moves[cell] = 1;
  }
  for (int g = 0; g < num_groups; ++g) {
    if (moves[g]) continue;
    *error = num_groups == 1 ? std::string("every lattice cell of the moveable handle also holds "
                                           "a fixed vertex: the handle cannot move; separate "
                                           "the handles")
                             : "every lattice cell of handle group " + std::to_string(g) +
                                   " also holds a fixed vertex: that handle cannot move; "
                                   "separate the handles";
    return false;
  }
  return true;
}

bool RigidityEstimator::Init(const Lattice& lattice, const RigidityOptions& options,
                             std::string* error, int num_threads) {
  if (!options.Check(error)) return false;
  if (lattice.num_particles() == 0) {
    *error = "the lattice has no particles";
    return false;
  }
  options_ = options;
  num_threads_ = num_threads;
  const int n = lattice.num_particles();
  const int r = options.region_half_width;
  cell_width_ = lattice.cell_width();
  centre_ = lattice.origin() +
            0.5 * cell_width_ * (lattice.dims() - Eigen::Vector3i::Ones()).cast<double>();
  rest_ = (lattice.rest_positions().colwise() - centre_) / cell_width_;

  regions_ = RingsOf(lattice.particle_adjacency(), r, num_threads_);
  adjacency_ = lattice.particle_adjacency();
  inverse_region_size_.resize(n);
  rest_centroids_.resize(3, n);
  // Box summation: particles whose region is exactly the particles of their
  // (2r+1)^3 box sum plates of bars; the others sum their lists.
  auto is_box_region = [&](int i) {
    bool is_box = options.region_summation == RegionSummation::kBox;
    const Eigen::Vector3i& c = lattice.cell_coords(i);
    for (const int* j = regions_.begin(i); j != regions_.end(i) && is_box; ++j) {
      is_box = (lattice.cell_coords(*j) - c).cwiseAbs().maxCoeff() <= r;
    }
    // A box sums one particle per cell: a cell split into pieces of surface
    // (lattice.h) makes its particle's region a listed one.
    int box_count = 0;
    for (int dz = -r; dz <= r && is_box; ++dz)
      for (int dy = -r; dy <= r && is_box; ++dy)
        for (int dx = -r; dx <= r && is_box; ++dx) {
          const int count = lattice.NumParticlesAt(c + Eigen::Vector3i(dx, dy, dz));
          is_box = count <= 1;
          box_count += count;
        }
    return is_box && box_count == regions_.size(i);
  };
  std::vector<char> is_box_particle(n, 0);
  ForEachChunk(n, kParticleChunk, num_threads_, [&](int64_t begin, int64_t end, int64_t) {
    for (int i = static_cast<int>(begin); i < end; ++i) {
      // Goals average over the regions holding i, which are R_i itself only
      // when membership is symmetric; the lattice adjacency is.
      for (const int* j = regions_.begin(i); j != regions_.end(i); ++j) {
        CHECK(std::binary_search(regions_.begin(*j), regions_.end(*j), i))
            << "particle adjacency is not symmetric at " << i << ", " << *j;
      }
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const int* j = regions_.begin(i); j != regions_.end(i); ++j) sum += rest_.col(*j);
      inverse_region_size_[i] = 1.0 / regions_.size(i);
      rest_centroids_.col(i) = sum * inverse_region_size_[i];
      is_box_particle[i] = is_box_region(i);
    }
  });
  box_particles_.clear();
  listed_particles_.clear();
  bar_members_ = CompressedLists();
  plate_members_ = CompressedLists();
  box_members_ = CompressedLists();
  for (int i = 0; i < n; ++i) {
    if (is_box_particle[i]) {
      box_particles_.push_back(i);
    } else {
      listed_particles_.push_back(i);
    }
  }
  // Cells get ids in order of first use; a hash map keeps Init linear.
  auto key = [](const Eigen::Vector3i& c) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.x())) << 42) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.y())) << 21) ^
           static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.z()));
  };
  auto add_cells = [&](const std::vector<Eigen::Vector3i>& centres, int axis,
                       CompressedLists* members, std::vector<Eigen::Vector3i>* cells) {
    std::unordered_map<std::uint64_t, int> id_of_cell;
    for (const Eigen::Vector3i& centre : centres) {
      for (int d = -r; d <= r; ++d) {
        Eigen::Vector3i cell = centre;
        cell[axis] += d;
        const auto [it, inserted] =
            id_of_cell.emplace(key(cell), static_cast<int>(cells->size()));
        if (inserted) cells->push_back(cell);
        members->values.push_back(it->second);
      }
      members->offsets.push_back(static_cast<int64_t>(members->values.size()));
    }
  };
  std::vector<Eigen::Vector3i> box_cells, plate_cells, bar_cells;
  for (int i : box_particles_) box_cells.push_back(lattice.cell_coords(i));
  add_cells(box_cells, 2, &box_members_, &plate_cells);
  add_cells(plate_cells, 1, &plate_members_, &bar_cells);
  for (const Eigen::Vector3i& cell : bar_cells) {
    for (int d = -r; d <= r; ++d) {
      const int particle = lattice.ParticleAt(cell + Eigen::Vector3i(d, 0, 0));
      if (particle >= 0) bar_members_.values.push_back(particle);
    }
    bar_members_.offsets.push_back(static_cast<int64_t>(bar_members_.values.size()));
  }
  bar_sums_.resize(12, bar_members_.num_rows());
  plate_sums_.resize(12, plate_members_.num_rows());

  rotations_.assign(n, Eigen::Quaterniond::Identity());
  particle_values_.resize(12, n);
  region_sums_.resize(12, n);
  region_transforms_.resize(12, n);
  goal_sums_.resize(12, n);
  return true;
}

void RigidityEstimator::SumOverRegions(const Matrix12Xd& values, Matrix12Xd* sums) {
  // Every column of every pass is a sum of its own, in the same order on any
  // number of threads.
  auto for_each = [this](int64_t count, auto&& body) {
    ForEachChunk(count, kParticleChunk, num_threads_, [&](int64_t begin, int64_t end, int64_t) {
      for (int64_t k = begin; k < end; ++k) body(static_cast<int>(k));
    });
  };
  for_each(static_cast<int64_t>(listed_particles_.size()), [&](int k) {
    const int i = listed_particles_[k];
    Vector12d sum = Vector12d::Zero();
    for (const int* j = regions_.begin(i); j != regions_.end(i); ++j) sum += values.col(*j);
    sums->col(i) = sum;
  });
  if (box_particles_.empty()) return;
  // Separable (2r+1)-wide sums along x (bars), y (plates), z (boxes).
  auto sum_rows = [](const CompressedLists& members, const Matrix12Xd& in, int row) {
    Vector12d sum = Vector12d::Zero();
    for (const int* j = members.begin(row); j != members.end(row); ++j) sum += in.col(*j);
    return sum;
  };
  for_each(bar_members_.num_rows(),
           [&](int k) { bar_sums_.col(k) = sum_rows(bar_members_, values, k); });
  for_each(plate_members_.num_rows(),
           [&](int k) { plate_sums_.col(k) = sum_rows(plate_members_, bar_sums_, k); });
  for_each(box_members_.num_rows(), [&](int k) {
    sums->col(box_particles_[k]) = sum_rows(box_members_, plate_sums_, k);
  });
}

void RigidityEstimator::ComputeGoalsInLatticeUnits(const Eigen::Matrix3Xd& positions,
                                                   Eigen::Matrix3Xd* goals,
                                                   long long* iterations) {
  const int n = num_particles();
  const int64_t num_chunks = NumChunks(n, kParticleChunk);
  // Per particle: x_j and vec(x_j x0_j^T) (column-major).
  ForEachChunk(n, kParticleChunk, num_threads_, [&](int64_t begin, int64_t end, int64_t) {
    for (int64_t j = begin; j < end; ++j) {
      const Eigen::Vector3d x = positions.col(j);
      const Eigen::Vector3d x0 = rest_.col(j);
      particle_values_.col(j).head<3>() = x;
      particle_values_.col(j).segment<3>(3) = x * x0.x();
      particle_values_.col(j).segment<3>(6) = x * x0.y();
      particle_values_.col(j).segment<3>(9) = x * x0.z();
    }
  });
  SumOverRegions(particle_values_, &region_sums_);
  // Per region: A = sum x x0^T - (sum x) c0^T, R = rotation of A,
  // t = c - R c0; stored as [vec(R); t].
  std::vector<long long> chunk_updates(num_chunks, 0);
  ForEachChunk(n, kParticleChunk, num_threads_, [&](int64_t begin, int64_t end, int64_t c) {
    for (int64_t i = begin; i < end; ++i) {
      const Eigen::Vector3d sum_x = region_sums_.col(i).head<3>();
      const Eigen::Vector3d c0 = rest_centroids_.col(i);
      const Eigen::Matrix3d a =
          Eigen::Map<const Eigen::Matrix3d>(region_sums_.col(i).data() + 3) -
          sum_x * c0.transpose();
      chunk_updates[c] += ExtractRotation(a, options_.max_rotation_iterations,
                                          options_.rotation_tolerance, &rotations_[i]);
      const Eigen::Matrix3d rotation = rotations_[i].toRotationMatrix();
      Eigen::Map<Eigen::Matrix3d>(region_transforms_.col(i).data()) = rotation;
      region_transforms_.col(i).tail<3>() = sum_x * inverse_region_size_[i] - rotation * c0;
    }
  });
  for (long long updates : chunk_updates) *iterations += updates;
  // Eq. 2: g_i = (sum_r R_r x0_i + t_r) / |R_i| over the regions holding i.
  SumOverRegions(region_transforms_, &goal_sums_);
  goals->resize(3, n);
  ForEachChunk(n, kParticleChunk, num_threads_, [&](int64_t begin, int64_t end, int64_t) {
    for (int64_t i = begin; i < end; ++i) {
      const Eigen::Map<const Eigen::Matrix3d> rotation_sum(goal_sums_.col(i).data());
      goals->col(i) = (rotation_sum * rest_.col(i) + goal_sums_.col(i).tail<3>()) *
                      inverse_region_size_[i];
    }
  });
}

void RigidityEstimator::ComputeGoals(const Eigen::Matrix3Xd& positions,
                                     Eigen::Matrix3Xd* goals, bool warm_start) {
  CHECK_EQ(positions.cols(), num_particles());
  CHECK(goals != nullptr);
  if (!warm_start) std::fill(rotations_.begin(), rotations_.end(), Eigen::Quaterniond::Identity());
  const Eigen::Matrix3Xd lattice_positions = (positions.colwise() - centre_) / cell_width_;
  long long iterations = 0;
  ComputeGoalsInLatticeUnits(lattice_positions, goals, &iterations);
  *goals = ((*goals) * cell_width_).colwise() + centre_;
}

bool RigidityEstimator::Estimate(const std::vector<int>& fixed_particles,
                                 const std::vector<int>& moveable_particles,
                                 RigidityEstimate* estimate, std::string* error) {
  return Estimate(fixed_particles, moveable_particles, options_.seed, estimate, error);
}

bool RigidityEstimator::Estimate(const std::vector<int>& fixed_particles,
                                 const std::vector<int>& moveable_particles,
                                 std::uint64_t seed, RigidityEstimate* estimate,
                                 std::string* error) {
  CHECK(estimate != nullptr);
  CHECK_GT(num_particles(), 0) << "call Init first";
  const int n = num_particles();
  if (!ValidParticles(fixed_particles, n, "fixed-handle", error)) return false;
  if (!ValidParticles(moveable_particles, n, "moveable-handle", error)) return false;
  if (moveable_particles.empty()) {
    *error = "the moveable handle has no particles";
    return false;
  }
  std::vector<char> fixed(n, 0);
  for (int p : fixed_particles) fixed[p] = 1;
  estimate->initial_direction.setZero();
  estimate->rotation_iterations = 0;
  if (options_.model == RigidityModel::kHarmonic) {
    SolveHarmonic(fixed, moveable_particles, estimate);
  } else {
    SimulateShapeMatching(fixed, moveable_particles, seed, estimate);
  }
  double handle_extent = 0.0;
  for (int p : moveable_particles) handle_extent = std::max(handle_extent, estimate->extent[p]);
  if (!(handle_extent > 0.0)) {
    *error =
        "the moveable handle does not move: every moveable-handle particle is also a "
        "fixed-handle particle; separate the handles";
    return false;
  }
  estimate->handle_extent = handle_extent;
  estimate->relative_extent = estimate->extent / handle_extent;
  return true;
}

void RigidityEstimator::SimulateShapeMatching(const std::vector<char>& fixed,
                                              const std::vector<int>& moveable_particles,
                                              std::uint64_t seed, RigidityEstimate* estimate) {
  const int n = num_particles();
  // Lattice units: lengths in cell widths. Time keeps its unit.
  const double h = options_.time_step;
  const double spring = h * options_.external_stiffness;  // h k_ext / m
  const double keep = 1.0 - options_.damping;
  estimate->initial_direction = RandomDirection(seed);
  const Eigen::Vector3d v0 = estimate->initial_direction * (options_.initial_speed / h);

  Eigen::Matrix3Xd x = rest_;
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, n);
  for (int p : moveable_particles) {
    if (!fixed[p]) v.col(p) = v0;
  }
  Eigen::Matrix3Xd goals = rest_;  // At t0 every region is at rest.
  Eigen::VectorXd squared_extent = Eigen::VectorXd::Zero(n);
  std::fill(rotations_.begin(), rotations_.end(), Eigen::Quaterniond::Identity());

  for (int step = 1; step <= options_.num_steps; ++step) {
    for (int i = 0; i < n; ++i) {
      if (fixed[i]) continue;  // Pinned: x = x0, v = 0.
      const Eigen::Vector3d displacement = x.col(i) - rest_.col(i);
      v.col(i) = keep * (v.col(i) + (goals.col(i) - x.col(i)) / h - spring * displacement);
      x.col(i) += h * v.col(i);
    }
    ComputeGoalsInLatticeUnits(x, &goals, &estimate->rotation_iterations);
    squared_extent = squared_extent.cwiseMax((goals - rest_).colwise().squaredNorm().transpose());
  }

  estimate->extent.resize(n);
  for (int i = 0; i < n; ++i) estimate->extent[i] = std::sqrt(squared_extent[i]) * cell_width_;
}

void RigidityEstimator::SolveHarmonic(const std::vector<char>& fixed,
                                      const std::vector<int>& moveable_particles,
                                      RigidityEstimate* estimate) {
  const int n = num_particles();
  // Dirichlet values: 1 on the moveable handle, 0 on the fixed one (a
  // particle in both stays fixed); -1 marks a free particle.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  std::vector<int> unknown(n, -1);
  std::vector<char> known(n, 0);
  std::vector<int> queue;
  for (int p = 0; p < n; ++p) {
    if (fixed[p]) {
      known[p] = 1;
      queue.push_back(p);
    }
  }
  for (int p : moveable_particles) {
    if (known[p]) continue;
    known[p] = 1;
    u[p] = 1.0;
    queue.push_back(p);
  }
  // Free particles reachable from a handle particle are the unknowns; a piece
  // of the lattice without one keeps u = 0 (nothing moves it).
  int num_unknowns = 0;
  for (std::size_t front = 0; front < queue.size(); ++front) {
    const int p = queue[front];
    for (const int* q = adjacency_.begin(p); q != adjacency_.end(p); ++q) {
      if (known[*q] || unknown[*q] >= 0) continue;
      unknown[*q] = num_unknowns++;
      queue.push_back(*q);
    }
  }
  if (num_unknowns > 0) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(adjacency_.values.size() + num_unknowns);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(num_unknowns);
    for (int p = 0; p < n; ++p) {
      const int row = unknown[p];
      if (row < 0) continue;
      entries.emplace_back(row, row, adjacency_.size(p));
      for (const int* q = adjacency_.begin(p); q != adjacency_.end(p); ++q) {
        if (unknown[*q] >= 0) {
          entries.emplace_back(row, unknown[*q], -1.0);
        } else {
          rhs[row] += u[*q];  // a handle particle (every neighbour is reachable)
        }
      }
    }
    Eigen::SparseMatrix<double> laplacian(num_unknowns, num_unknowns);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> cholesky(laplacian);
    CHECK(cholesky.info() == Eigen::Success) << "harmonic rigidity: factorisation failed";
    const Eigen::VectorXd solution = cholesky.solve(rhs);
    for (int p = 0; p < n; ++p) {
      if (unknown[p] >= 0) u[p] = std::clamp(solution[unknown[p]], 0.0, 1.0);
    }
  }
  estimate->extent = u * cell_width_;
}

bool EstimateRigidity(const Lattice& lattice, const std::vector<int>& fixed_particles,
                      const std::vector<int>& moveable_particles,
                      const RigidityOptions& options, RigidityEstimate* estimate,
                      std::string* error) {
  RigidityEstimator estimator;
  if (!estimator.Init(lattice, options, error)) return false;
  return estimator.Estimate(fixed_particles, moveable_particles, estimate, error);
}

const OptionTable<RigidityOptions>& RigidityOptionTable() {
  static const OptionTable<RigidityOptions>& table =
      MakeOptionTable<RigidityOptions>([](auto& t) { DeclareRigidityOptionRows(t); });
  return table;
}

}  // namespace msdeform
