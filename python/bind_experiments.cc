// The experiments' scenarios, runner and metrics (experiments/) on NumPy
// arrays. Runs come back as dicts keyed by the experiment tables' column
// names (experiments/runner.cc; experiments/results/README.md explains them).

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/methods/cgal_arap.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "experiments/experiment_scenario.h"
#include "msdeform/core/metrics.h"
#include "experiments/runner.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/scenario.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

// One run as the tables name its numbers: every column of RunResultColumns()
// (experiments/runner.h), in its order. NaN where a number does not apply
// (the tables print an empty cell).
py::dict RunResultToDict(const RunResult& r) {
  py::dict d;
  for (const ResultColumn& column : RunResultColumns()) {
    switch (column.kind) {
      case ResultColumnKind::kText:
        d[column.name.c_str()] = r.*(column.text);
        break;
      case ResultColumnKind::kInt:
        d[column.name.c_str()] = r.*(column.integer);
        break;
      case ResultColumnKind::kNumber:
        d[column.name.c_str()] = r.*(column.number);
        break;
    }
  }
  return d;
}

ExperimentScenario LoadScenario(const py::object& path_object, int frames,
                                const py::object& mesh_path_object) {
  const std::string path = PathFromObject(path_object, "path");
  const std::string mesh_path =
      mesh_path_object.is_none() ? std::string() : PathFromObject(mesh_path_object, "mesh_path");
  if (frames < 0 || frames > kMaxScenarioFrames) {
    ThrowValueError("frames: expected 0.." + std::to_string(kMaxScenarioFrames) +
                    " (0: the scenario's), got " + std::to_string(frames));
  }
  ExperimentScenario scenario;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = LoadExperimentScenario(path, frames, &scenario, &error, mesh_path);
  }
  if (!ok) ThrowOSError(error);
  return scenario;
}

py::dict RunDeformerOn(const ExperimentScenario& scenario, const py::object& options,
                       const py::object& label, const py::object& arap_result,
                       const py::kwargs& kwargs) {
  const DeformerOptions resolved = DeformerOptionsFrom(options, kwargs);
  std::string error;
  if (!resolved.Check(&error)) ThrowValueError(error);
  const std::string name =
      label.is_none() ? std::string(MethodName(resolved.method)) : label.cast<std::string>();
  Eigen::Matrix3Xd reference;
  if (!arap_result.is_none()) {
    reference = PositionsFromArray(arap_result, "arap_result");
    if (reference.cols() != scenario.mesh.num_vertices()) {
      ThrowValueError("arap_result: " + std::to_string(reference.cols()) +
                      " vertices, the scenario's mesh has " +
                      std::to_string(scenario.mesh.num_vertices()));
    }
  }
  RunResult result;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = RunDeformer(scenario, resolved, name, arap_result.is_none() ? nullptr : &reference,
                     &result, &error);
  }
  if (!ok) ThrowRuntimeError(error);
  // Not timed here (the runner times the other backend itself).
  result.other_backend_frame_ms = std::numeric_limits<double>::quiet_NaN();
  return RunResultToDict(result);
}

py::tuple RunCgalArapOn(const ExperimentScenario& scenario, int iterations, double tolerance) {
  CgalArapOptions options;
  options.iterations = iterations;
  options.tolerance = tolerance;
  std::string error;
  if (!options.Check(&error)) ThrowValueError(error);
  RunResult result;
  Eigen::Matrix3Xd deformed;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = RunCgalArap(scenario, options, &result, &deformed, &error);
  }
  if (!ok) ThrowRuntimeError(error);
  return py::make_tuple(RunResultToDict(result), PositionsToArray(deformed));
}

py::tuple RunMethodOn(const ExperimentScenario& scenario, const std::string& method,
                      const py::object& options, const py::object& label,
                      const py::object& reference, const py::kwargs& kwargs) {
  const MethodOptions method_options = MethodOptionsFrom(options, kwargs);
  std::string error;
  if (!IsMethodName(method)) ThrowValueError("method: " + (CreateMethod(method, &error), error));
  if (!method_options.deformer.Check(&error) || !method_options.cgal.Check(&error) ||
      !method_options.fastlsm.Check(&error)) {
    ThrowValueError(error);
  }
  const std::string name = label.is_none() ? method : label.cast<std::string>();
  Eigen::Matrix3Xd reference_positions;
  if (!reference.is_none()) {
    reference_positions = PositionsFromArray(reference, "reference");
    if (reference_positions.cols() != scenario.mesh.num_vertices()) {
      ThrowValueError("reference: " + std::to_string(reference_positions.cols()) +
                      " vertices, the scenario's mesh has " +
                      std::to_string(scenario.mesh.num_vertices()));
    }
  }
  RunResult result;
  Eigen::Matrix3Xd deformed;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = RunMethod(scenario, method, method_options, name,
                   reference.is_none() ? nullptr : &reference_positions, &result, &deformed,
                   &error);
  }
  if (!ok) ThrowRuntimeError(error);
  return py::make_tuple(RunResultToDict(result), PositionsToArray(deformed));
}

// The rest positions V (#V, 3) and the deformed ones V2 of the same count.
struct Positions {
  Mesh rest;
  Eigen::Matrix3Xd deformed;
};

Positions PositionsFrom(const py::object& vertices, const py::object& faces,
                        const py::object& deformed) {
  Positions p;
  if (faces.is_none()) {
    p.rest.vertices = PositionsFromArray(vertices, "V");
  } else {
    p.rest = MeshFromArrays(vertices, faces);
    ValidateOrThrow(p.rest);
  }
  p.deformed = PositionsFromArray(deformed, "V2");
  if (p.deformed.cols() != p.rest.vertices.cols()) {
    ThrowValueError("V2: " + std::to_string(p.deformed.cols()) + " vertices, V has " +
                    std::to_string(p.rest.vertices.cols()));
  }
  return p;
}

ArapTerms ArapTermsFrom(const py::object& energy, const py::object& normaliser) {
  ArapTerms terms;
  terms.energy = ValuesFromArray(energy, "energy");
  terms.normaliser = ValuesFromArray(normaliser, "normaliser");
  if (terms.energy.size() != terms.normaliser.size()) {
    ThrowValueError("normaliser: " + std::to_string(terms.normaliser.size()) +
                    " values, energy has " + std::to_string(terms.energy.size()));
  }
  return terms;
}

// A scenario from arrays: the mesh, a status array (0 fixed, 1 free, 2
// handle) and the drag path, one (4, 4) transform or (frames, 4, 4).
std::unique_ptr<ExperimentScenario> ScenarioFromArrays(const py::object& vertices,
                                                       const py::object& faces,
                                                       const py::object& status,
                                                       const py::object& path,
                                                       const py::object& watch,
                                                       const std::string& name) {
  auto scenario = std::make_unique<ExperimentScenario>();
  scenario->name = name;
  scenario->mesh = MeshFromArrays(vertices, faces);
  ValidateOrThrow(scenario->mesh);
  const int num_vertices = scenario->mesh.num_vertices();
  scenario->layout = LayoutFromStatus(status, num_vertices, "status");
  std::string error;
  if (!ValidateHandles(scenario->layout, num_vertices, &error)) {
    ThrowValueError("status: " + error);
  }
  const int num_groups = scenario->layout.num_groups();
  if (!PathFromArray(path, "path", num_groups, &scenario->path)) {
    scenario->path.push_back(FrameFromArray(path, "path", num_groups));
  }
  if (scenario->path.empty()) ThrowValueError("path: no transform");
  if (static_cast<int>(scenario->path.size()) > kMaxScenarioFrames) {
    ThrowValueError("path: more than " + std::to_string(kMaxScenarioFrames) + " frames");
  }
  if (!watch.is_none()) {
    scenario->watch = IdsFromArray(watch, num_vertices, "watch");
    std::sort(scenario->watch.begin(), scenario->watch.end());
    scenario->watch.erase(std::unique(scenario->watch.begin(), scenario->watch.end()),
                          scenario->watch.end());
    scenario->has_watch = true;
  }
  return scenario;
}

void BindScenario(py::module_& m) {
  py::class_<ExperimentScenario> c(
      m, "Scenario",
      "An experiment's edit loaded from a scenario file (docs/formats.md): the mesh, the "
      "handle layout, the optional watch region and the drag path. Made by load_scenario, or "
      "from arrays with Scenario(V, F, status, path, watch=None, name='arrays').");
  c.def(py::init(&ScenarioFromArrays), py::arg("V"), py::arg("F"), py::arg("status"),
        py::arg("path"), py::arg("watch") = py::none(), py::arg("name") = "arrays",
        "A scenario from arrays, for run_deformer and run_cgal_arap: V (#V, 3), F (#F, 3), "
        "status per vertex (0 fixed, 1 free, 2 + g handle group g), path the handle's "
        "transforms, one (4, 4) or (frames, 4, 4) (msdeform.drag_path makes one; with several "
        "handle groups (groups, 4, 4) or (frames, groups, 4, 4)), watch optional vertex ids "
        "whose displacement is the leakage. Raises ValueError (the C++ message) for bad "
        "arrays or a layout without a handle vertex.");
  c.def_readonly("name", &ExperimentScenario::name, "The scenario's name.");
  c.def_readonly("file", &ExperimentScenario::file, "The scenario file.");
  c.def_readonly("mesh_path", &ExperimentScenario::mesh_path, "The mesh file, resolved.");
  c.def_property_readonly(
      "V",
      [](const py::object& self) {
        return ReadOnlyView(self.cast<const ExperimentScenario&>().mesh.vertices, self);
      },
      "The rest vertices, a read-only float64 (#V, 3) view.");
  c.def_property_readonly(
      "F",
      [](const py::object& self) {
        return ReadOnlyView(self.cast<const ExperimentScenario&>().mesh.faces, self);
      },
      "The faces, a read-only int32 (#F, 3) view.");
  c.def_property_readonly(
      "status",
      [](const ExperimentScenario& s) {
        return StatusFromLayout(s.layout, s.mesh.num_vertices());
      },
      "The handle layout as a per-vertex status array (0 fixed, 1 free, 2 + g handle group "
      "g), for Method.set_handles.");
  c.def_property_readonly(
      "fixed", [](const ExperimentScenario& s) { return IdsToArray(s.layout.fixed); },
      "The fixed vertex ids, sorted.");
  c.def_property_readonly(
      "handle", [](const ExperimentScenario& s) { return IdsToArray(s.layout.moveable); },
      "The moveable handle's vertex ids, sorted.");
  c.def_property_readonly(
      "watch",
      [](const ExperimentScenario& s) -> py::object {
        if (!s.has_watch) return py::none();
        return IdsToArray(s.watch);
      },
      "The watch region's vertex ids (leakage), or None when the scenario has none.");
  c.def_property_readonly(
      "path",
      [](const ExperimentScenario& s) { return HandlePathToArray(s.path, s.layout.num_groups()); },
      "The drag path, one 4x4 transform per frame, a (frames, 4, 4) array; for a scenario with "
      "several handles one a handle group, (frames, groups, 4, 4). The last frame is the "
      "target. Method.drag_along(scenario.path) drags it as the runner does.");
  c.def_property_readonly(
      "frames", [](const ExperimentScenario& s) { return static_cast<int>(s.path.size()); },
      "Frames of the drag path.");
  c.def(
      "__repr__",
      [](const ExperimentScenario& s) {
        return "<msdeform.Scenario " + s.name + ": " + std::to_string(s.mesh.num_vertices()) +
               " vertices, " + std::to_string(s.layout.fixed.size()) + " fixed, " +
               std::to_string(s.layout.moveable.size()) + " handle, " +
               std::to_string(s.path.size()) + " frames>";
      },
      "A one-line summary.");

  // The most frames a scenario, load_scenario or a sweep may ask for.
  m.attr("MAX_SCENARIO_FRAMES") = kMaxScenarioFrames;
  m.def("load_scenario", &LoadScenario, py::arg("path"), py::arg("frames") = 0,
        py::arg("mesh_path") = py::none(),
        "Loads a scenario file and its mesh (experiments/experiment_scenario.h). frames > 0 "
        "overrides the file's frame count; mesh_path replaces its mesh (the same edit on a "
        "mesh whose first vertices are the original's). Raises OSError with the C++ message "
        "(naming the file and the field) on any error.");
}

void BindRunner(py::module_& m) {
  m.def("run_method", &RunMethodOn, py::arg("scenario"), py::arg("method"),
        py::arg("options") = py::none(), py::arg("label") = py::none(),
        py::arg("reference") = py::none(),
        "run_method(scenario, method, options=None, label=None, reference=None, **kwargs)\n\n"
        "Runs any registered method (msdeform.METHODS) over the scenario's drag path through "
        "the method interface, as the experiment runner does (experiments/runner.h, "
        "RunMethod). options and keyword arguments as for Method (the Deformer's, and the "
        "methods' own: cgal_iterations, fastlsm_steps, ...). reference, the reference "
        "method's final vertices on the same drag (the runner's: full_arap's), gives "
        "arap_energy_ratio, ref_distance_rel and ref_distance_max_rel (NaN without). "
        "Returns (row, V2): run_deformer's dict and the final vertices (#V, 3). Raises "
        "ValueError for an unknown method or bad options, RuntimeError when a frame fails.");
  m.def("run_deformer", &RunDeformerOn, py::arg("scenario"), py::arg("options") = py::none(),
        py::arg("label") = py::none(), py::arg("arap_result") = py::none(),
        "run_deformer(scenario, options=None, label=None, arap_result=None, **kwargs)\n\n"
        "Runs the deformer over the scenario's drag path and measures it as the experiment "
        "runner does (experiments/runner.h, RunDeformer). options and keyword arguments as for "
        "Method (the runner uses num_threads=1); label names the row (default: the method). "
        "arap_result, the reference's final vertices on the same drag (the runner's: "
        "run_method(scenario, 'full_arap')), gives arap_energy_ratio, ref_distance_rel and "
        "ref_distance_max_rel (NaN without). Returns a dict keyed by the tables' column names: "
        "scenario, method, energy (what it minimised: ed or arap for the graph methods, "
        "DeformerOptions.energy; arap, sr_arap or shape_matching for the others), vertices, "
        "faces, diagonal, cell_width, particles, d1, scales_n, "
        "shared_cells, selected_scale, scale_nodes, totally_free, half_free, nodes_optimized, "
        "variables, precompute_ms, rigidity_ms, setup_ms, frame_ms, solve_ms, skin_ms "
        "(medians over frames), solve_total_ms, iterations (median), iterations_total, "
        "final_cost, unconverged_frames, handle_rms_rel, fixed_max_rel, leakage_rel, "
        "leakage_max_rel (NaN without a watch region), arap_energy, arap_energy_joint, strain, "
        "orthogonality, arap_energy_ratio, ref_distance_rel, ref_distance_max_rel, "
        "other_backend_frame_ms (NaN: not run here), "
        "wall_ms. Raises ValueError for bad options and RuntimeError when a frame fails.");
  m.def("run_cgal_arap", &RunCgalArapOn, py::arg("scenario"),
        py::arg("iterations") = CgalArapOptions().iterations,
        py::arg("tolerance") = CgalArapOptions().tolerance,
        "Runs CGAL's ARAP (ROI: every non-fixed vertex) over the scenario's drag path with "
        "`iterations` local/global iterations per frame, measured against its own result "
        "(arap_energy_ratio 1, distances 0). Returns (row, V2): the dict of run_deformer "
        "(method 'cgal_arap') and the final vertices, a new (#V, 3) array (usable as "
        "run_deformer's arap_result).");
}

void BindMetrics(py::module_& m) {
  m.def(
      "handle_rms_error",
      [](const py::object& vertices, const py::object& deformed, const py::object& handle,
         const py::object& matrix) {
        const Positions p = PositionsFrom(vertices, py::none(), deformed);
        const std::vector<int> ids =
            IdsFromArray(handle, p.rest.num_vertices(), "handle");
        return HandleRmsError(p.rest, p.deformed, ids, TransformFromArray(matrix, "M"));
      },
      py::arg("V"), py::arg("V2"), py::arg("handle"), py::arg("M"),
      "Root mean square of |V2[v] - M V[v]| over the handle's vertex ids, in mesh units "
      "(core/metrics.h, HandleRmsError; divide by bounding_box_diagonal(V) for the "
      "tables' handle_rms_rel). 0 for an empty list.");
  m.def(
      "vertex_displacement",
      [](const py::object& vertices, const py::object& deformed, const py::object& ids) {
        const Positions p = PositionsFrom(vertices, py::none(), deformed);
        const Displacement d =
            VertexDisplacement(p.rest, p.deformed, IdsFromArray(ids, p.rest.num_vertices(),
                                                                "vertices"));
        return py::make_tuple(d.mean, d.max);
      },
      py::arg("V"), py::arg("V2"), py::arg("vertices"),
      "(mean, max) of |V2[v] - V[v]| over the vertex ids, in mesh units (VertexDisplacement); "
      "zeros for an empty list.");
  m.def(
      "leakage",
      [](const py::object& vertices, const py::object& deformed, const py::object& watch) {
        const Positions p = PositionsFrom(vertices, py::none(), deformed);
        const Displacement d =
            VertexDisplacement(p.rest, p.deformed, IdsFromArray(watch, p.rest.num_vertices(),
                                                                "watch"));
        const double diagonal = BoundingBoxDiagonal(p.rest);
        py::dict result;
        result["leakage_rel"] = d.mean / diagonal;
        result["leakage_max_rel"] = d.max / diagonal;
        return result;
      },
      py::arg("V"), py::arg("V2"), py::arg("watch"),
      "Leakage into a watch region, as the runner and the msdeform report measure it: "
      "{'leakage_rel': mean, 'leakage_max_rel': max} displacement of the watch vertices over "
      "the bounding-box diagonal of V.");
  m.def(
      "arap_energy_per_vertex",
      [](const py::object& vertices, const py::object& faces, const py::object& deformed) {
        const Positions p = PositionsFrom(vertices, faces, deformed);
        const ArapTerms terms = ArapEnergyPerVertex(p.rest, p.deformed);
        return py::make_tuple(VectorToArray(terms.energy), VectorToArray(terms.normaliser));
      },
      py::arg("V"), py::arg("F"), py::arg("V2"),
      "Cotangent-weighted ARAP energy per vertex (Sorkine & Alexa 2007; ArapEnergyPerVertex): "
      "(energy, normaliser), two float64 (#V,) arrays E_i and N_i = sum_j w_ij |p_i - p_j|^2.");
  m.def(
      "normalised_arap_energy",
      [](const py::object& energy, const py::object& normaliser, const py::object& ids) {
        const ArapTerms terms = ArapTermsFrom(energy, normaliser);
        const std::vector<int> vertices =
            ids.is_none() ? std::vector<int>()
                          : IdsFromArray(ids, static_cast<int>(terms.energy.size()), "vertices");
        return NormalisedArapEnergy(terms, vertices);
      },
      py::arg("energy"), py::arg("normaliser"), py::arg("vertices") = py::none(),
      "sum E_i / sum N_i over the vertex ids (all when None or empty) of "
      "arap_energy_per_vertex's terms: the tables' arap_energy (all vertices) and "
      "arap_energy_joint (the vertices_near the fixed region).");
  m.def(
      "mean_edge_strain",
      [](const py::object& vertices, const py::object& faces, const py::object& deformed) {
        const Positions p = PositionsFrom(vertices, faces, deformed);
        return MeanEdgeStrain(p.rest, p.deformed);
      },
      py::arg("V"), py::arg("F"), py::arg("V2"),
      "Mean over the undirected edges of | |e'| / |e| - 1 | (MeanEdgeStrain): the tables' "
      "strain.");
  m.def(
      "orthogonality_error",
      [](const py::object& rotations, const py::object& ids) {
        const py::array array = py::array::ensure(rotations);
        if (!array || array.ndim() != 3 || array.shape(1) != 3 || array.shape(2) != 3) {
          ThrowValueError("R: expected an array of shape (k, 3, 3)");
        }
        // Row-major 3x3 blocks -> the column-major columns of NodeTransforms.
        const Eigen::Matrix3Xd rows = PositionsFromArray(array.attr("reshape")(-1, 3), "R");
        const int k = static_cast<int>(array.shape(0));
        NodeTransforms transforms = NodeTransforms::Identity(k);
        for (int j = 0; j < k; ++j) {
          transforms.rotation(j) = rows.middleCols(3 * j, 3).transpose();
        }
        return OrthogonalityError(transforms, IdsFromArray(ids, k, "nodes"));
      },
      py::arg("R"), py::arg("nodes"),
      "Mean over the node ids of ||R_j^T R_j - I||_F for rotations R (k, 3, 3) "
      "(OrthogonalityError): the tables' orthogonality over the optimised nodes "
      "(Method.node_rotations, nodes whose class is not fixed).");
  m.def(
      "vertices_near",
      [](const py::object& vertices, const py::object& faces, const py::object& sources,
         double radius) {
        Mesh mesh = MeshFromArrays(vertices, faces);
        ValidateOrThrow(mesh);
        const std::vector<int> ids = IdsFromArray(sources, mesh.num_vertices(), "sources");
        if (!(radius >= 0.0)) ThrowValueError("radius: expected a number >= 0");
        return IdsToArray(VerticesNear(mesh, ids, radius));
      },
      py::arg("V"), py::arg("F"), py::arg("sources"), py::arg("radius"),
      "Vertex ids, not in sources, within `radius` of a source along mesh edges (Dijkstra; "
      "VerticesNear): the runner's joint band is vertices_near(V, F, fixed, 0.05 * diagonal).");
}

}  // namespace

void BindExperiments(py::module_& m) {
  // RunResult's columns (experiments/runner.h): (name, timing) pairs in the
  // order of run_deformer's dicts; the sweeps derive their columns from it.
  py::list columns;
  for (const ResultColumn& column : RunResultColumns()) {
    columns.append(py::make_tuple(column.name, column.timing));
  }
  m.attr("RESULT_COLUMNS") = py::tuple(columns);
  BindScenario(m);
  BindRunner(m);
  BindMetrics(m);
}

}  // namespace python
}  // namespace msdeform
