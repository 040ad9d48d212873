// Rigidity estimation by lattice shape matching (paper §4.1-4.2, Eq. 2-5;
// docs/method.md §2).
//
// The lattice particles (unit mass) are simulated for S steps with FastLSM
// shape matching (Rivers & James 2007). Region R_i is particle i with its
// r-ring in the particle adjacency (r = 1: i and its adjacent particles).
// Each step, each region fits the rigid transform T_r = [R_r t_r] of its rest
// positions onto its current ones (centroids c0, c; A = sum (x_j - c)(x0_j - c0)^T;
// R_r the rotation of A, no reflection, warm-started from the previous step);
// particle i gets the goal (Eq. 2)
//   g_i = average over the regions holding i of T_r x0_i,
// and moves by (Eq. 3, 4)
//   v_i += (g_i - x_i) / h + h f_ext / m,  f_ext = -k_ext (x_i - x0_i),
//   v_i *= 1 - damping,  x_i += h v_i.
// Fixed-handle particles stay at x0; moveable-handle particles start with
// velocity v0 in one random direction (seeded). The deforming extent (Eq. 5) is
//   e_i = max_{n=1..S} |g_i(t0 + n h) - x0_i|,
// normalised by the extent of the moveable handle e_h = max over its particles:
// e'_i = e_i / e_h. Small e' means rigid (stays still).
//
// The work per step is linear in the number of particles (region sums, see
// RegionSummation). Runs only when the handle layout changes.
//
// That is RigidityModel::kShapeMatching, the paper's procedure. Its e' falls
// off about like 1 / distance from the handle (a kick that has not crossed a
// limb in S steps), so on a limb edit the deforming region stops short of the
// joint. The default, RigidityModel::kHarmonic, replaces the S steps by the
// state they tend to when the handle is driven and nothing oscillates: with
// translation-only matching, a particle's goal is the mean displacement of
// its neighbours, and the rest state under a displaced handle is the harmonic
// field on the particle adjacency,
//   (L u)_i = sum_{j adjacent to i} (u_i - u_j) = 0 for every free particle,
//   u = 1 on moveable-handle particles, u = 0 on fixed-handle particles,
// one sparse Cholesky solve. e'_i = u_i (e_i = u_i w for a handle displaced by
// one cell width w). Along a limb between the handle and a fixed region u
// falls off about linearly; a thin part (ear, toe, finger) takes the whole
// drop, so a small edit stays local. Particles whose piece of the lattice has
// no handle particle get 0; a piece with a moveable and no fixed particle
// moves as a whole (u = 1). No seed, no time step. docs/decisions/rigidity.md,
// "Rigidity: the harmonic estimate".

#ifndef MSDEFORM_SCALES_RIGIDITY_H_
#define MSDEFORM_SCALES_RIGIDITY_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/option_table.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"

namespace msdeform {

// How region sums are formed (both give the same numbers up to rounding).
enum class RegionSummation {
  // Each region adds up precomputed per-particle quantities over its list.
  kPerRegion,
  // FastLSM box summation: separable x, y, z sums for the particles whose
  // region is exactly the particles of their (2r+1)^3 lattice box (the
  // regular interior); per-region sums for the others.
  kBox,
};

// "box", "per_region".
const EnumNames<RegionSummation>& RegionSummationNames();

// How e' is estimated (see the top of this file).
enum class RigidityModel {
  kShapeMatching,  // the paper: S steps of lattice shape matching after a kick
  kHarmonic,       // the driven lattice's rest state: a harmonic field
};
// "harmonic", "paper".
const EnumNames<RigidityModel>& RigidityModelNames();
const char* RigidityModelName(RigidityModel model);
bool ParseRigidityModel(const std::string& name, RigidityModel* model);

// The largest region half-width r. A region holds up to (2r + 1)^3 particles
// and every particle's region is stored and summed at each step, so memory
// and time grow as r^3 per particle: 125 at r = 2, 4913 at r = 8 (10 GB of
// region lists on a 500K-particle lattice). 2^31 - 1 overflowed the ring
// loop and hung; r = 100 ran 2 minutes on the 620-vertex cactus.
constexpr int kMaxRegionHalfWidth = 8;

struct RigidityOptions {
  // Which estimate (docs/decisions/rigidity.md).
  // The fields below up to `seed` and the rotation settings apply to
  // kShapeMatching only.
  RigidityModel model = RigidityModel::kHarmonic;
  // S: number of shape-matching steps (docs/method.md: 20).
  int num_steps = 20;
  // h: time step, in lattice-time units. With positions in mesh units the
  // trajectory depends only on k_ext h^2 and |v0| h, so h just fixes the
  // unit of time.
  double time_step = 1.0;
  // k_ext: stiffness per unit mass of the spring pulling each particle to its
  // rest position, in 1 / time^2. The force is linear in the displacement, so
  // k_ext carries no length unit: scaling the mesh scales every displacement
  // and e by the same factor and leaves e' unchanged. Check() asks for
  // k_ext h^2 <= 1 (a conservative stability bound).
  double external_stiffness = 0.01;  // docs/decisions/rigidity-shape-matching.md
  // |v0| of the moveable-handle particles, in cell widths w per time step h
  // (docs/method.md: 0.5 w / h). Set before the first step, so damping applies.
  double initial_speed = 0.5;
  // Fraction of each particle's velocity removed per step, in [0, 1).
  double damping = 0.0;
  // r: a region is a particle and its r-ring in the particle adjacency, r in
  // 1..kMaxRegionHalfWidth.
  int region_half_width = 2;  // the paper suggests 1; see docs/decisions/rigidity-shape-matching.md
  // Seed of the direction of v0 (std::mt19937_64).
  std::uint64_t seed = 1;
  // How region sums are formed (kBox measured slightly faster; see
  // docs/decisions/rigidity-shape-matching.md).
  RegionSummation region_summation = RegionSummation::kBox;
  // Polar decomposition: at most this many warm-started updates per region and
  // step, stopping when an update rotates by less than rotation_tolerance
  // (radians).
  int max_rotation_iterations = 20;
  double rotation_tolerance = 1e-6;

  // The ranges of RigidityOptionTable()'s rows, then k_ext h^2 <= 1.
  bool Check(std::string* error) const;
};

// RigidityOptions' rows (core/option_table.h), declared in its header beside the fields: a new
// field is the field above and its row here. RigidityOptionTable() (rigidity.cc) builds the table
// from them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareRigidityOptionRows(Table& t) {
  using R = RigidityOptions;
  t.Enum("model", &R::model, RigidityModelNames(),
         "Estimate: harmonic (the driven lattice's rest state) or paper (S steps of lattice "
         "shape matching after a kick).");
  t.Int("num_steps", &R::num_steps, "S: shape-matching steps of the paper's rigidity.")
      .Range(1, kOptionIntMax, "an integer >= 1");
  t.Double("time_step", &R::time_step, "h: time step, lattice-time units.")
      .Above(0, "a finite number > 0");
  t.Double("external_stiffness", &R::external_stiffness,
           "k_ext h^2 of the rigidity estimation (docs/method.md §2).")
      .AtLeast(0, "a finite number >= 0");
  t.Double("initial_speed", &R::initial_speed,
           "|v0| of the moveable-handle particles, cell widths per time step.")
      .Above(0, "a finite number > 0");
  t.Double("damping", &R::damping, "Velocity damping per shape-matching step, in [0, 1).")
      .Range(0, 1, "a number in [0, 1)", /*high_open=*/true);
  t.Int("region_half_width", &R::region_half_width,
        "Region half-width r of the shape matching (the paper: 1).")
      .Range(1, kMaxRegionHalfWidth, "an integer in 1..8 (cost grows as r^3 per particle)");
  t.Int("seed", &R::seed, "Seed of the direction of v0.");
  t.Enum("region_summation", &R::region_summation, RegionSummationNames(),
         "box (FastLSM box sums) or per_region; the same numbers up to rounding.");
  t.Int("max_rotation_iterations", &R::max_rotation_iterations,
        "Polar-decomposition updates per region and step, at most.")
      .Range(1, kOptionIntMax, "an integer >= 1");
  t.Double("rotation_tolerance", &R::rotation_tolerance,
           "Stop the updates below this rotation (radians).")
      .Above(0, "a finite number > 0");
}
const OptionTable<RigidityOptions>& RigidityOptionTable();

struct RigidityEstimate {
  Eigen::VectorXd extent;           // e_i in mesh units. #particles.
  Eigen::VectorXd relative_extent;  // e'_i = e_i / e_h. #particles.
  double handle_extent = 0.0;       // e_h in mesh units (> 0).
  Eigen::Vector3d initial_direction = Eigen::Vector3d::Zero();  // of v0 (unit).
  long long rotation_iterations = 0;  // Polar updates over all regions and steps.
};

// The unique particles (sorted) of the surface cells holding `vertices`.
// Returns false and names the first bad vertex id in *error when an id is not
// a vertex of the mesh the lattice was built from.
bool ParticlesOfVertices(const Lattice& lattice, const std::vector<int>& vertices,
                         std::vector<int>* particles, std::string* error);

// The cells a lattice method holds or drives: per particle, -1 for a free
// cell, -2 for a cell that holds a fixed vertex (it stays at rest, whatever
// else it holds), else the handle group (core/handles.h) of the moveable
// vertices it holds, which it follows. False with a message on a bad vertex
// id, on a cell (not fixed) that holds vertices of two groups (it cannot
// follow both; naming them), or when every cell of a group also holds a
// fixed vertex (that handle could not move).
constexpr int kFixedParticle = -2;
bool HandleGroupOfParticles(const Lattice& lattice, const HandleLayout& layout,
                            std::vector<int>* group_of_particle, std::string* error);

// Precomputes the regions and rest data of one lattice, then estimates
// rigidity for any number of handle layouts. Not thread-safe (scratch buffers).
class RigidityEstimator {
 public:
  // Returns false with a message when the options are invalid. The lattice is
  // copied from; it need not outlive the estimator. Init and the shape-matching
  // steps run their per-particle loops on `num_threads` threads (0: OpenMP's
  // default); the results do not depend on it.
  bool Init(const Lattice& lattice, const RigidityOptions& options, std::string* error,
            int num_threads = 1);

  // Estimates e' for the given fixed and moveable handle particles (particle
  // ids, duplicates allowed; a particle in both stays fixed): the S steps with
  // the given seed for the direction of v0, or the harmonic field (no seed).
  // Returns false with a message when an id is out of range, the moveable
  // handle is empty, or it does not move (every moveable particle is also
  // fixed).
  bool Estimate(const std::vector<int>& fixed_particles,
                const std::vector<int>& moveable_particles, std::uint64_t seed,
                RigidityEstimate* estimate, std::string* error);
  // The same with options().seed.
  bool Estimate(const std::vector<int>& fixed_particles,
                const std::vector<int>& moveable_particles, RigidityEstimate* estimate,
                std::string* error);

  // Goals (Eq. 2) for the given current positions, 3 by #particles in mesh
  // units, with rotations cold-started from the identity, or with
  // `warm_start` from the previous call's (a simulation that calls it every
  // step, like methods/fastlsm.h). Exposes one shape matching step; shape
  // matching is exact for a rigid motion.
  void ComputeGoals(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* goals,
                    bool warm_start = false);

  const RigidityOptions& options() const { return options_; }
  int num_particles() const { return static_cast<int>(rest_.cols()); }
  // R_i: particle i and its r-ring, sorted.
  const CompressedLists& regions() const { return regions_; }
  // Particles whose region sums come from box sums (kBox only).
  int num_box_particles() const { return static_cast<int>(box_particles_.size()); }

 private:
  using Vector12d = Eigen::Matrix<double, 12, 1>;
  using Matrix12Xd = Eigen::Matrix<double, 12, Eigen::Dynamic>;

  // Sums columns of `values` over each region into `sums` (12 by #particles).
  void SumOverRegions(const Matrix12Xd& values, Matrix12Xd* sums);
  // The two models' e (lattice units, squared for shape matching) per particle.
  void SimulateShapeMatching(const std::vector<char>& fixed,
                             const std::vector<int>& moveable_particles, std::uint64_t seed,
                             RigidityEstimate* estimate);
  void SolveHarmonic(const std::vector<char>& fixed, const std::vector<int>& moveable_particles,
                     RigidityEstimate* estimate);
  // Goals in lattice units from positions in lattice units; updates the
  // warm-started rotations and adds the polar updates to *iterations.
  void ComputeGoalsInLatticeUnits(const Eigen::Matrix3Xd& positions,
                                  Eigen::Matrix3Xd* goals, long long* iterations);

  RigidityOptions options_;
  int num_threads_ = 1;
  // Lattice units: positions are (x - centre_) / cell_width_.
  double cell_width_ = 1.0;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3Xd rest_;              // x0, lattice units. 3 by #particles.
  CompressedLists regions_;
  CompressedLists adjacency_;  // the lattice's particle adjacency
  Eigen::VectorXd inverse_region_size_;  // 1 / |R_i|. #particles.
  Eigen::Matrix3Xd rest_centroids_;      // c0 of each region. 3 by #particles.

  // Box summation (kBox), FastLSM's separable sums on the cells they need:
  // bar sums along x (particles at x offsets -r..r of a bar cell), plate sums
  // along y of bars, box sums along z of plates. Bar and plate cells may be
  // empty cells; neighbouring box particles share their bars and plates.
  std::vector<int> box_particles_;     // sums from plates
  std::vector<int> listed_particles_;  // sums from their region lists
  CompressedLists bar_members_;        // per bar: particles
  CompressedLists plate_members_;      // per plate: bars
  CompressedLists box_members_;        // per box particle: plates
  Matrix12Xd bar_sums_, plate_sums_;

  // Scratch.
  std::vector<Eigen::Quaterniond> rotations_;  // warm starts, one per region
  Matrix12Xd particle_values_, region_sums_, region_transforms_, goal_sums_;
};

// One-off estimation: builds a RigidityEstimator and runs it with options.seed.
bool EstimateRigidity(const Lattice& lattice, const std::vector<int>& fixed_particles,
                      const std::vector<int>& moveable_particles,
                      const RigidityOptions& options, RigidityEstimate* estimate,
                      std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_RIGIDITY_H_
