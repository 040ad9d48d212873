// The deformation-graph methods' members of msdeform.Method
// (python/method_object.h): the lattice's graphs, the rigidity estimate e',
// the scale selection, the node classes and transforms of the selected
// scale, the energy's term counts. For a method that is not a graph each
// raises AttributeError naming the member and the method.

#include <mutex>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/methods/graph_method.h"
#include "msdeform/scales/scale_selection.h"
#include "python/method_object.h"

namespace msdeform {
namespace python {
namespace {

// A read-only graph member named `name`: `function(deformer)` under the lock,
// after the graph check and (when `needs_handles`) RequireHandles.
template <typename Function>
void GraphMember(py::class_<PyMethod>& c, const char* name, Function function,
                 bool needs_handles, const char* doc) {
  c.def_property_readonly(
      name,
      [name, function, needs_handles](PyMethod& self) {
        std::lock_guard<std::mutex> lock(self.mutex);
        const GraphMethod& deformer = self.Graph(name);
        if (needs_handles) self.RequireHandles();
        return function(deformer);
      },
      doc);
}

py::array_t<double> Rotations(const NodeTransforms& transforms) {
  py::array_t<double> rotations(
      {static_cast<py::ssize_t>(transforms.num_nodes()), py::ssize_t{3}, py::ssize_t{3}});
  auto out = rotations.mutable_unchecked<3>();
  for (int j = 0; j < transforms.num_nodes(); ++j) {
    for (int r = 0; r < 3; ++r) {
      for (int col = 0; col < 3; ++col) out(j, r, col) = transforms.rotation(j)(r, col);
    }
  }
  return rotations;
}

py::dict SelectionToDict(const ScaleSelection& selection) {
  py::dict dict;
  dict["threshold"] = selection.threshold;
  dict["group1_size"] = selection.group1_size;
  dict["eq6_scale"] = selection.eq6_scale;
  dict["scale"] = selection.scale;
  dict["local_detail_edit"] = selection.local_detail_edit;
  dict["num_pinned"] = selection.num_pinned;
  return dict;
}

// What Init builds: the graphs.
void BindGraphs(py::class_<PyMethod>& c) {
  GraphMember(c, "num_scales", [](const GraphMethod& d) {
    return d.options().method == Method::kMultiScale ? static_cast<int>(d.graphs().size()) : 1;
  }, false,
      "N, the number of scales (graphs DG1..DGN) of the multi-scale method; 1 for the static "
      "baselines (as the experiment tables' scales_n).");
  GraphMember(c, "num_graphs", [](const GraphMethod& d) { return static_cast<int>(d.graphs().size()); },
              false, "Graphs built: DG1..DGN (multi-scale), or DG1 and the static graph.");
  c.def(
      "graph_node_positions",
      [](PyMethod& self, int graph) {
        std::lock_guard<std::mutex> lock(self.mutex);
        const GraphMethod& deformer = self.Graph("graph_node_positions");
        const int count = static_cast<int>(deformer.graphs().size());
        if (graph < 1 || graph > count) {
          ThrowValueError("graph: expected 1.." + std::to_string(count) + ", got " +
                          std::to_string(graph));
        }
        return PositionsToArray(deformer.graphs()[graph - 1].positions);
      },
      py::arg("graph"),
      "Rest node positions g_j of graph `graph` (1-based: 1 is DG1), a new (#nodes, 3) array.");
}

// What set_handles derives: e', the scale, the node classes.
void BindLayout(py::class_<PyMethod>& c) {
  GraphMember(c, "relative_extent",
              [](const GraphMethod& d) { return VectorToArray(d.rigidity().relative_extent); }, true,
              "One entry per lattice particle, not per node: float64 (#particles,) with "
              "#particles = len(particle_positions) (surface and interior). e' (paper Eq. 5, "
              "normalised), the rigidity estimate; the first num_surface_particles entries are "
              "the DG1 nodes' (node_extent has one per node of the selected scale). Small means "
              "rigid. Empty for the static baselines.");
  GraphMember(c, "extent", [](const GraphMethod& d) { return VectorToArray(d.rigidity().extent); },
              true,
              "e per lattice particle in mesh units (e' = e / handle_extent); empty for the "
              "baselines.");
  GraphMember(c, "handle_extent", [](const GraphMethod& d) { return d.rigidity().handle_extent; },
              true, "e_h, the moveable handle's extent in mesh units (0 for the baselines).");
  GraphMember(c, "node_extent", [](const GraphMethod& d) {
    const std::vector<double>& extent = d.selection().node_extent;
    return py::array_t<double>(static_cast<py::ssize_t>(extent.size()), extent.data());
  }, true,
      "e' per node of the selected scale (the max over its DG1 members by default); empty for "
      "the baselines.");
  GraphMember(c, "selection", [](const GraphMethod& d) { return SelectionToDict(d.selection()); },
              true,
              "The multi-scale scale selection as a dict: threshold (T, Eq. 7), group1_size "
              "(P1), eq6_scale (s of Eq. 6), scale (after conflicts), local_detail_edit, "
              "num_pinned (nodes kept Fixed because they skin a fixed vertex). Zeros for the "
              "baselines.");
  GraphMember(c, "fixed_region_exact", [](const GraphMethod& d) { return d.fixed_region_exact(); },
              true,
              "Whether every fixed-handle vertex is skinned only by Fixed nodes, so that it stays "
              "exactly at rest (the multi-scale default; not the static baselines).");
  GraphMember(c, "selected_scale", [](const GraphMethod& d) { return d.active_graph() + 1; }, true,
              "The 1-based index of the graph solved on (the selected scale s for multi-scale; "
              "graph_node_positions(selected_scale) == node_positions).");
  GraphMember(c, "node_positions",
              [](const GraphMethod& d) { return PositionsToArray(d.active().positions); }, true,
              "Rest node positions g_j of the selected scale's graph, a new (#nodes, 3) array.");
  GraphMember(c, "node_classes", [](const GraphMethod& d) {
    std::vector<int> classes;
    for (NodeClass node_class : d.node_classes()) classes.push_back(static_cast<int>(node_class));
    return IdsToArray(classes);
  }, true,
      "One entry per node of the selected scale (as node_positions), not per lattice "
      "particle or DG1 node: int32 (#nodes,), 0 fixed, 1 half_free, 2 totally_free "
      "(msdeform.NODE_CLASSES[c] names class c).");
}

// The solve: transforms and the energy's terms.
void BindSolve(py::class_<PyMethod>& c) {
  GraphMember(c, "node_rotations", [](const GraphMethod& d) { return Rotations(d.transforms()); },
              true,
              "R_j of the selected scale's nodes after the last drag, a new (#nodes, 3, 3) "
              "array.");
  GraphMember(c, "node_translations",
              [](const GraphMethod& d) { return PositionsToArray(d.transforms().translations); },
              true,
              "t_j of the selected scale's nodes after the last drag, a new (#nodes, 3) array.");
  GraphMember(c, "num_coherence_terms", [](const GraphMethod& d) { return d.num_coherence_terms(); },
              true, "Directed coherence terms E(j, k) in the energy.");
  GraphMember(c, "num_position_terms", [](const GraphMethod& d) { return d.num_position_terms(); },
              true, "Position terms of the moveable handle (one per handle vertex).");
  GraphMember(c, "num_skinned_vertices",
              [](const GraphMethod& d) { return d.num_skinned_vertices(); }, true,
              "Vertices drag() moves (the others stay at rest exactly).");
}

}  // namespace

void BindGraphMembers(py::module_& m, py::class_<PyMethod>& c) {
  BindGraphs(c);
  BindLayout(c);
  BindSolve(c);
  py::list names;
  for (NodeClass node_class : {NodeClass::kFixed, NodeClass::kHalfFree, NodeClass::kTotallyFree}) {
    names.append(NodeClassName(node_class));
  }
  m.attr("NODE_CLASSES") = py::tuple(names);
}

}  // namespace python
}  // namespace msdeform
