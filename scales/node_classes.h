// Node classes (paper §4.2; docs/method.md §4): the one place that decides
// which nodes of a graph are Totally Free, Half Free or Fixed, for the
// multi-scale method (at a given scale, as SelectScale tries them) and for the
// static baselines, from the handle layout and the mesh's components.
//
// A mesh component that holds no moveable-handle vertex is "still": nothing
// moves it, its vertices stay at rest and a node whose DG1 members are all
// still is Fixed whatever else holds. The multi-scale rules are those stated
// in scale_selection.h (Eq. 7's threshold T is an input here); the static
// baselines make every other node Totally Free.

#ifndef MSDEFORM_SCALES_NODE_CLASSES_H_
#define MSDEFORM_SCALES_NODE_CLASSES_H_

#include <vector>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/scales/scale_selection.h"

namespace msdeform {

// Per vertex: whether its mesh component holds no moveable-handle vertex (an
// isolated vertex is a component of its own). Empty when the mesh has one
// component.
std::vector<char> StillVertices(const Components& components, const HandleLayout& layout);

// The DG1 nodes (surface particles) holding handle vertices, the still ones
// (holding only still vertices; empty when `still_vertices` is) and the handle
// vertices pin_fixed_region looks at (still fixed vertices left out).
HandleNodes HandleNodesOf(const Lattice& lattice, const HandleLayout& layout,
                          const std::vector<char>& still_vertices);

// Per node of `graph`: whether all its DG1 members are still (`still_dg1` as
// HandleNodes::still; empty gives all false). Such a node is Fixed whatever
// its extent: it gets no variables.
std::vector<char> StillNodes(const DeformationGraph& graph, const std::vector<char>& still_dg1);

// Whether vertex v has a non-Fixed node of non-zero weight among its nearest:
// only such a vertex can move (a Fixed node is the identity).
bool SkinnedByAFreeNode(const SkinningWeights& weights, const std::vector<NodeClass>& node_class,
                        int v);

// The first of `vertices` that only Fixed nodes skin (SkinnedByAFreeNode is
// false: it stays at rest whatever the solve does), or -1 when there is none.
int FirstVertexSkinnedOnlyByFixedNodes(const SkinningWeights& weights,
                                       const std::vector<NodeClass>& node_class,
                                       const std::vector<int>& vertices);

// The multi-scale classes of DG_scale (`graph`, connected) for threshold T.
struct ScaleClasses {
  std::vector<double> node_extent;    // e' per node (max or mean of its members')
  std::vector<NodeClass> node_class;  // per node
  int num_pinned = 0;                 // nodes pin_fixed_region made Fixed
};

// Returns false when DG_scale cannot serve the layout, so that the selection
// moves finer: a node holds both fixed and moveable handle vertices, or (scale
// > 1, pin_fixed_region) a node that skins a fixed vertex holds or skins a
// moveable one. On DG1 such a pinned node is left unpinned instead.
bool ClassifyNodesAtScale(const DeformationGraph& graph, int scale,
                          const std::vector<double>& dg1_extent, const HandleNodes& handles,
                          double threshold, const ScaleSelectionOptions& options,
                          ScaleClasses* classes);

// The static baselines' classes on their graph: Fixed where all DG1 members
// are still, Totally Free elsewhere.
std::vector<NodeClass> StaticGraphNodeClasses(const DeformationGraph& graph,
                                              const std::vector<char>& still_dg1);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_NODE_CLASSES_H_
