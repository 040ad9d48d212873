// What the overlays show, as numbers and colours (the drawing is the
// renderer's): the handle labels, the rigidity e' of the current layout as a
// colour map, and the node classes of the selected scale.
//
// Colours are 8-bit sRGB. The label colours are what the screenshot tests
// look for: fixed blue, handle red, free a light neutral grey, all on a
// near-white background.

#ifndef MSDEFORM_APPS_EDITOR_OVERLAYS_H_
#define MSDEFORM_APPS_EDITOR_OVERLAYS_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "apps/editor/selection.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {
namespace editor {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kBackgroundColor = {236, 238, 242};
constexpr Rgb kFreeColor = {196, 196, 190};
constexpr Rgb kFixedColor = {40, 90, 230};
constexpr Rgb kHandleColor = {225, 35, 30};
constexpr Rgb kTotallyFreeColor = {250, 150, 20};
constexpr Rgb kHalfFreeColor = {200, 70, 210};
constexpr Rgb kFixedNodeColor = {90, 90, 96};
constexpr Rgb kEdgeColor = {30, 30, 36};

Rgb LabelColor(VertexLabel label);
// The colour of handle group g: kHandleColor for group 0.
Rgb HandleGroupColor(int group);
Rgb NodeClassColor(NodeClass node_class);

// The colour map of e': perceptually uniform (viridis), e' = 0 (rigid, stays
// still) dark blue-violet to e' = 1 (moves with the handle) yellow; values
// outside [0, 1] are clamped.
Rgb RigidityColor(double e_prime);

// e' per mesh vertex, interpolated from the DG1 nodes (the lattice's surface
// particles) with DG1's skinning weights, as the deformation itself blends
// the nodes. Empty when the graph method has no rigidity estimate (the static
// baselines, or no layout yet). #V.
Eigen::VectorXd VertexRigidity(const GraphMethod& graph_method);

// Per-vertex colours (3 by #V bytes): by label; with `rigidity` (#V), the
// free vertices by e' and the fixed and handle vertices still blue and red, so
// the e' map shows where the handles are.
std::vector<Rgb> VertexColors(const std::vector<VertexLabel>& labels,
                              const Eigen::VectorXd& rigidity);

// Node centres of the active graph in the current pose, g_j + t_j (3 by
// #nodes), and their class colours.
Eigen::Matrix3Xd DeformedNodePositions(const GraphMethod& graph_method);
std::vector<Rgb> NodeColors(const GraphMethod& graph_method);

// Counts per class of the active graph: {Totally Free, Half Free, Fixed}.
std::array<int, 3> CountNodeClasses(const GraphMethod& graph_method);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_OVERLAYS_H_
