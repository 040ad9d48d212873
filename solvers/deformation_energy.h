// The deformation energy over the active nodes of one handle layout, as a
// list of term families: what every frame solver minimises
// (solvers/frame_solver.h; solvers/frame_solver_factory.h picks one).
//
//   E = w_rot E_rot + w_coh E_coh + w_con E_con  (+ the gauge terms)   Eq. 17
//     + the user terms (energies/energy_term.h)
//     + the families with their own structure (solvers/term_family.h:
//       the subspace ARAP energy's rotation clusters)
//
// Eq. 17's families and the user terms are per-block cost functors that
// every backend runs; node classes make blocks constant (Ceres's
// SetParameterBlockConstant).
//
// HandleSetup builds a DeformationEnergy once per handle layout
// (GraphMethod::SetHandles); a backend turns it into its own problem.
// Lengths are already scaled into the sqrt weights (docs/decisions/length-unit.md,
// "Length unit"). Costs are 1/2 sum of squared residuals, as Ceres reports.

#ifndef MSDEFORM_SOLVERS_DEFORMATION_ENERGY_H_
#define MSDEFORM_SOLVERS_DEFORMATION_ENERGY_H_

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/energies/energy_term.h"
#include "msdeform/energies/position_cost.h"
#include "msdeform/solvers/node_class.h"
#include "msdeform/solvers/term_family.h"

namespace msdeform {

// The terms of Eq. 17 for one handle layout, independent of the backend.
struct DeformationEnergy {
  // Per node of the active graph: Totally Free varies R and t, Half Free R
  // only, Fixed nothing (values stay as given).
  std::vector<NodeClass> node_class;
  // Rot (Eq. 12) over these nodes, residual scale sqrt(w_rot).
  std::vector<int> rot_nodes;
  double sqrt_rot = 1.0;
  // Coherence (Eq. 14) of directed edge (j, k):
  //   sqrt_weight * (R_j e + g_j + t_j - g_k - t_k),  e = g_k - g_j.
  struct Coherence {
    int j, k;
    Eigen::Vector3d edge;  // g_k - g_j
    double sqrt_weight;
  };
  std::vector<Coherence> coherence;
  // Position (Eq. 16): sqrt_weight * (sum_i w_i [R_i o_i + g_i + t_i] - q),
  // q = handles[handle_group] * rest for a handle vertex, q = rest when
  // handle_group is -1 (fixed vertices held at rest). Nodes distinct, zero
  // weights dropped.
  struct Position {
    std::vector<int> nodes;
    std::vector<SkinningTerm> terms;
    Eigen::Vector3d rest;
    int handle_group;  // -1: held at rest
    double sqrt_weight;
    bool follows_handle() const { return handle_group >= 0; }
  };
  std::vector<Position> positions;
  // The layout's handle groups (core/handles.h): handle_group < this.
  int num_handle_groups = 1;
  // Gauge fixing (energies/gauge_cost.h, docs/decisions/gauge-freedom.md):
  //   sqrt_weight * axis^T omega(R_node),  omega(R) = 1/2 (R32 - R23, R13 - R31, R21 - R12),
  // one per unit axis along which Eq. 17 leaves R_node free (GaugeTerms).
  // Zero on a member of every such family of minima, so the minimum value
  // does not change; J^T J becomes non-singular.
  struct Gauge {
    int node;
    Eigen::Vector3d axis;  // unit
    double sqrt_weight;
  };
  std::vector<Gauge> gauge;
  // Terms beyond Eq. 17 (energies/energy_term.h): each backend runs them
  // from this description alone (examples/energy_terms/ has one). They do
  // not enter GaugeTerms.
  std::vector<EnergyTerm> terms;
  // Families that bring their own structure (solvers/term_family.h), such
  // as the subspace ARAP energy (--energy=arap, solvers/subspace_arap_terms.h),
  // which stands in place of Eq. 17's terms (then empty). Empty for Eq. 17.
  std::vector<std::shared_ptr<const TermFamily>> families;

  // 12 per Totally Free node, 9 per Half Free node.
  int num_variables() const;
};

// The gauge terms `energy` needs, from its Rot, Coherence and Position terms
// (energy.gauge is ignored). R_j of a node in rot_nodes enters Eq. 17 through
// Rot, which depends on R_j^T R_j only, and through R_j u for the vectors u of
// its terms: the edge of each Coherence term with j as source, the offset of
// each Position term's share of j. Spinning R_j about a unit axis n
// (R_j -> Q R_j, Q a rotation about R_j n; = R_j Q_n for a rotation R_j)
// changes none of these when every u is parallel to n. With S the sum of
// u u^T over those vectors scaled as in J (sqrt weight, times w_i for a
// Position share):
//   S = 0 (no such term): axes x, y and z;
//   S of rank one (second eigenvalue <= 1e-12 times the first, a relative
//   test): its leading eigenvector, the common direction of the edges;
//   otherwise none (the terms pin R_j).
// Weight sqrt_rot (the Rot residuals' scale, so the term is as stiff as the
// Rot terms that pin R_j's other directions); none when sqrt_rot is 0.
std::vector<DeformationEnergy::Gauge> GaugeTerms(const DeformationEnergy& energy);

// 1/2 sum of squared residuals of `energy` at `transforms` with the handle at
// `handles` (deformed_from_rest a handle group), evaluated term by term through the functors
// of energies/ (the reference every backend's reported cost is tested
// against).
double EvaluateEnergy(const DeformationEnergy& energy, const NodeTransforms& transforms,
                      const HandleTransforms& handles);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_DEFORMATION_ENERGY_H_
