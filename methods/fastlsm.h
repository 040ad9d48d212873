// Fast lattice shape matching (FastLSM; Rivers & James 2007, the paper's [4])
// as an editing method, on the lattice msdeform builds (core/lattice.h, with
// options.deformer.lattice).
//
// Each particle i has the region R_i of its r-ring (scales/rigidity.h's
// regions). The particles of cells holding moveable-handle vertices are
// driven: at deformed_from_rest[g] * x0 every frame, g the handle group of
// the cell's vertices (a cell holding two groups' vertices is refused). Those of cells holding
// fixed vertices stay at x0 (a cell holding both is fixed). The other
// particles run `steps_per_frame` FastLSM steps per Drag, from where the last
// frame left them (h = 1):
//   g_i = average over the regions holding i of T_r x0_i   (shape matching)
//   v_i = (1 - damping) (v_i + (g_i - x_i)),   x_i += v_i.
// Each particle has a frame: the handle transform (driven), the identity
// (fixed), or its region's best-fit rigid transform T_p(x) = R_p (x - c0_p) +
// c_p (free; FastLSM's per-particle rotation). A vertex in a driven or fixed
// particle's cell follows that frame exactly (the handle and the fixed
// vertices are exact); a vertex in a free particle's cell is the blend of the
// frames of that particle and its lattice neighbours, x = sum_j w_j T_j(x0) /
// sum_j w_j, with the trilinear weights w_j of the cell centres: continuous
// across the walls between free cells. At the wall of a driven or fixed cell
// it is not (the vertices inside take that one frame, those just outside a
// blend), so a large edit can open a seam there: on a 8 x 1 x 1 bar bent by
// 0.6 rad the longest edge across such a wall stretched 3.6x (between free
// cells 1.8x); docs/decisions/method-interface.md, "FastLSM". A rigid motion of the whole
// lattice is a fixed point of the steps and of the skinning.

#ifndef MSDEFORM_METHODS_FASTLSM_H_
#define MSDEFORM_METHODS_FASTLSM_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/lattice.h"
#include "msdeform/methods/method.h"
#include "msdeform/scales/rigidity.h"

namespace msdeform {

struct FastLsmOptions {
  // Shape-matching steps per frame (Drag). Each step moves a disturbance
  // about r cells, so a lattice L cells long needs about L / r steps to
  // settle; 20 as the paper's rigidity estimate uses.
  int steps_per_frame = 20;
  // r: a region is a particle and its r-ring (Rivers & James's w), 1..8.
  int region_half_width = 2;
  // Fraction of each particle's velocity removed per step, in [0, 1): the
  // simulation is an editing tool here, so it is damped towards rest (quick
  // tables: 0.5 left the cactus bend at arap_energy 0.20, 0.1 at 0.054; 0
  // oscillates, 0.13).
  double damping = 0.1;

  bool Check(std::string* error) const;
};

class FastLsm : public EditingMethod {
 public:
  FastLsm() : EditingMethod("fastlsm") {}

  const Eigen::Matrix3Xd& deformed_vertices() const override { return deformed_vertices_; }
  // Free particles (neither driven nor fixed); 3 unknowns each.
  int nodes_optimized() const override { return num_free_; }
  int variables() const override { return 3 * num_free_; }
  double precompute_ms() const override { return precompute_ms_; }
  double setup_ms() const override { return setup_ms_; }
  const Lattice* lattice() const override { return &lattice_; }
  // Current particle positions, 3 by #particles.
  const Eigen::Matrix3Xd& particle_positions() const { return positions_; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override;
  bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
              std::string* error) override;

 private:
  enum class Kind : char { kFree, kFixed, kDriven };
  void Skin(const HandleTransforms& deformed_from_rest);

  FastLsmOptions options_;
  Mesh mesh_;
  Lattice lattice_;
  RigidityEstimator shape_matching_;  // its goals (Eq. 2) are FastLSM's
  std::vector<Kind> kind_;            // per particle
  std::vector<int> driven_group_;     // per particle: HandleGroupOfParticles (scales/rigidity.h)
  bool first_step_ = true;            // of the layout: shape matching cold-starts
  int num_free_ = 0;
  Eigen::Matrix3Xd positions_, velocities_, goals_;
  std::vector<Eigen::Quaterniond> rotations_;  // warm starts of the skinning fits
  Eigen::Matrix3Xd deformed_vertices_;
  double precompute_ms_ = 0.0;
  double setup_ms_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_FASTLSM_H_
