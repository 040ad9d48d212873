// msdeform_figure_data: writes the data the paper figures need
// (paper_figures/README.md), as JSON next to OFF meshes. Three modes:
//
//   --mode=graphs --mesh=M --out=F.json
//       The lattice (surface and interior cell centres, cell width) and the
//       deformation graphs DG1, a middle scale and DG_N (node positions and
//       edges). --scales=1,5,N picks other scales ("N" is the coarsest).
//   --mode=edit --scenario=S --out=F.json [--method=...] [ablations]
//       One edit (ablations, as msdeform's: --keep_left_out_terms,
//       --fix_fixed_handle_nodes, --rigidity, --half_free, --border,
//       --hold_fixed_vertices, --pin_fixed_region, --split_cells, and
//       --energy with its --arap_* options; all recorded in F.json): handle and watch
//       vertices, e' and class of every DG1 node, the size of group 1, the
//       selected scale's nodes/edges/classes, per-vertex displacement; the
//       deformed mesh is written to F with extension .off.
//   --mode=nodes_vs_p --scenario=S --out=F.json --p_values=25,50,100,...
//       For each P (nodes per scale step): the selected scale, its node
//       count, the optimised (Totally/Half Free) nodes and variables, and the
//       median frame time of a short drag.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <nlohmann/json.hpp>

#include "apps/flags/deformer_flags.h"
#include "apps/flags/program.h"
#include "msdeform/core/atomic_file.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"
#include "msdeform/core/timing.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/solvers/subspace_arap.h"

DEFINE_string(mode, "edit", "[input] graphs, edit or nodes_vs_p.");
DEFINE_string(mesh, "", "[input] Mesh (graphs mode; overrides the scenario's mesh otherwise).");
DEFINE_string(scenario, "", "[input] JSON scenario (edit and nodes_vs_p modes).");
DEFINE_string(out, "", "[output] Output JSON (edit mode also writes the deformed mesh as .off).");
DEFINE_string(scales, "1,mid,N", "[input] graphs mode: scales to export (1-based, 'mid' or 'N').");
DEFINE_string(p_values, "25,50,100,200,400", "[input] nodes_vs_p mode: the P values.");
DEFINE_int32(frames, 0, "[input] Drag frames (0: the scenario's; nodes_vs_p uses min(this or 5)).");

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

// Rounds to 6 significant digits to keep the files small.
double R6(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", x);
  return std::atof(buffer);
}

Json Points(const Eigen::Matrix3Xd& points) {
  Json out = Json::array();
  for (int i = 0; i < points.cols(); ++i) {
    out.push_back({R6(points(0, i)), R6(points(1, i)), R6(points(2, i))});
  }
  return out;
}

Json GraphJson(const DeformationGraph& graph, int scale) {
  Json edges = Json::array();
  for (const auto& [a, b] : graph.edges) edges.push_back({a, b});
  return {{"scale", scale}, {"num_nodes", graph.num_nodes()},
          {"positions", Points(graph.positions)}, {"edges", edges}};
}

bool WriteJson(const std::string& path, const Json& json, std::string* error) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) fs::create_directories(parent, ignored);
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << json.dump() << "\n";
        return static_cast<bool>(out);
      },
      error);
}

bool FillOptions(DeformerOptions* options, std::string* error) {
  return DeformerOptionsFromFlags(options, error);
}

// Loads a scenario: mesh, layout and drag path.
bool LoadScenario(Scenario* scenario, Mesh* mesh, HandleLayout* layout,
                  std::vector<HandleTransforms>* path, std::vector<int>* watch,
                  std::string* error) {
  if (FLAGS_scenario.empty()) {
    *error = "--scenario is required in this mode";
    return false;
  }
  if (!ReadScenario(FLAGS_scenario, scenario, error)) return false;
  if (FLAGS_frames > 0) scenario->frames = FLAGS_frames;
  const std::string mesh_path = FLAGS_mesh.empty() ? scenario->mesh_path : FLAGS_mesh;
  if (!ReadMesh(mesh_path, mesh, error)) return false;
  HandleTransforms deformed_from_rest;
  if (!ResolveScenario(*scenario, *mesh, layout, watch, &deformed_from_rest, error)) return false;
  *path = DragPath(*scenario, *mesh, *layout);
  return true;
}

bool RunGraphs(std::string* error) {
  if (FLAGS_mesh.empty()) {
    *error = "--mesh is required in graphs mode";
    return false;
  }
  Mesh mesh;
  if (!ReadMesh(FLAGS_mesh, &mesh, error)) return false;
  DeformerOptions options;
  if (!FillOptions(&options, error)) return false;
  options.method = Method::kMultiScale;
  GraphMethod deformer(options.method);
  if (!deformer.Precompute(mesh, options, error)) return false;
  const Lattice& lattice = *deformer.lattice();
  const int num_scales = static_cast<int>(deformer.graphs().size());
  Json out;
  out["mesh"] = FLAGS_mesh;
  out["vertices"] = mesh.num_vertices();
  out["diag"] = deformer.diagonal();
  const Eigen::Matrix3Xd& particles = lattice.rest_positions();
  const int ns = lattice.num_surface_particles();
  out["lattice"] = {{"cell_width", lattice.cell_width()},
                    {"surface", Points(particles.leftCols(ns))},
                    {"interior", Points(particles.rightCols(particles.cols() - ns))}};
  out["num_scales"] = num_scales;
  out["graphs"] = Json::array();
  std::stringstream list(FLAGS_scales);
  std::string token;
  while (std::getline(list, token, ',')) {
    int scale = 0;
    if (token == "N") {
      scale = num_scales;
    } else if (token == "mid") {
      scale = std::max(1, (num_scales + 1) / 2);
    } else {
      scale = std::atoi(token.c_str());
    }
    if (scale < 1 || scale > num_scales) {
      *error = "--scales: '" + token + "' is not a scale in 1.." + std::to_string(num_scales);
      return false;
    }
    out["graphs"].push_back(GraphJson(deformer.ConnectedGraph(scale - 1), scale));
  }
  return WriteJson(FLAGS_out, out, error);
}

// Init, SetHandles and the whole drag; frame_ms gets each Drag's wall time.
bool InitAndDrag(const Mesh& mesh, const DeformerOptions& options, const HandleLayout& layout,
                 const std::vector<HandleTransforms>& path, GraphMethod* deformer,
                 std::vector<double>* frame_ms, std::string* error) {
  if (!deformer->Precompute(mesh, options, error)) return false;
  if (!deformer->SetHandles(layout, error)) return false;
  DragLog log;
  if (!DragAlong(deformer, path, DragAlongOptions(), &log, error)) return false;
  for (const DragStats& stats : log.frames) frame_ms->push_back(stats.frame_ms);
  return true;
}

bool RunEdit(std::string* error) {
  Scenario scenario;
  Mesh mesh;
  HandleLayout layout;
  std::vector<HandleTransforms> path;
  std::vector<int> watch;
  if (!LoadScenario(&scenario, &mesh, &layout, &path, &watch, error)) return false;
  DeformerOptions options;
  if (!FillOptions(&options, error)) return false;
  GraphMethod deformer(options.method);
  std::vector<double> frame_ms;
  if (!InitAndDrag(mesh, options, layout, path, &deformer, &frame_ms, error)) return false;
  const fs::path mesh_out = fs::path(FLAGS_out).replace_extension(".off");
  Mesh deformed = mesh;
  deformed.vertices = deformer.deformed_vertices();
  std::error_code ignored;
  if (mesh_out.has_parent_path()) fs::create_directories(mesh_out.parent_path(), ignored);
  if (!WriteMesh(mesh_out.string(), deformed, error)) return false;

  Json out;
  out["name"] = scenario.name;
  out["mesh"] = scenario.mesh_path;
  out["method"] = MethodName(options.method);
  out["keep_left_out_terms"] = options.keep_left_out_terms;
  out["fix_fixed_handle_nodes"] = options.fix_fixed_handle_nodes;
  out["rigidity"] = RigidityModelName(options.rigidity.model);
  out["half_free"] = HalfFreeRuleName(options.selection.half_free);
  out["border"] = BorderRuleName(options.selection.border);
  out["hold_fixed_vertices"] = options.hold_fixed_vertices;
  out["pin_fixed_region"] = options.selection.pin_fixed_region;
  out["split_cells"] = options.lattice.split_cells;
  out["energy"] = EnergyName(options.energy);
  if (options.energy == Energy::kArap) {
    out["arap_clusters"] = RotationClustersNames().Name(options.arap.clusters);
    out["arap_num_clusters"] = options.arap.num_clusters;
    out["arap_constraints"] = ArapConstraintsNames().Name(options.arap.constraints);
  }
  out["deformed_mesh"] = mesh_out.filename().string();
  out["vertices"] = mesh.num_vertices();
  out["diag"] = deformer.diagonal();
  out["cell_width"] = deformer.lattice()->cell_width();
  out["fixed"] = layout.fixed;
  out["moveable"] = layout.moveable;
  out["watch"] = watch;  // vertices that should not move (may be empty)
  out["num_scales"] = deformer.options().method == Method::kMultiScale
                          ? static_cast<int>(deformer.graphs().size())
                          : 1;
  out["selected_scale"] = deformer.active_graph() + 1;
  out["threshold"] = deformer.selection().threshold;
  out["group1"] = deformer.selection().group1_size;
  out["variables"] = deformer.variables();
  out["frame_ms_median"] = Median(frame_ms);

  // DG1 nodes: position, e' (multi-scale only) and class of the node they merged into.
  const DeformationGraph& dg1 = deformer.graphs()[0];
  const DeformationGraph& active = deformer.active();
  const bool has_rigidity = deformer.rigidity().relative_extent.size() > 0;
  Json e_prime = Json::array(), dg1_class = Json::array();
  for (int i = 0; i < dg1.num_nodes(); ++i) {
    e_prime.push_back(has_rigidity ? R6(deformer.rigidity().relative_extent[i]) : 0.0);
    dg1_class.push_back(static_cast<int>(deformer.node_classes()[active.node_of_dg1[i]]));
  }
  out["dg1"] = {{"positions", Points(dg1.positions)}, {"e_prime", e_prime}, {"class", dg1_class}};
  Json active_json = GraphJson(active, deformer.active_graph() + 1);
  Json classes = Json::array();
  for (NodeClass c : deformer.node_classes()) classes.push_back(static_cast<int>(c));
  active_json["class"] = classes;  // 0 fixed, 1 half free, 2 totally free
  out["active"] = active_json;
  Json displacement = Json::array();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    displacement.push_back(
        R6((deformer.deformed_vertices().col(v) - mesh.vertices.col(v)).norm()));
  }
  out["displacement"] = displacement;
  return WriteJson(FLAGS_out, out, error);
}

bool RunNodesVsP(std::string* error) {
  Scenario scenario;
  Mesh mesh;
  HandleLayout layout;
  std::vector<HandleTransforms> path;
  const int frames = FLAGS_frames > 0 ? FLAGS_frames : 5;
  std::vector<int> watch;
  if (!LoadScenario(&scenario, &mesh, &layout, &path, &watch, error)) return false;
  scenario.frames = frames;
  path = DragPath(scenario, mesh, layout);
  Json rows = Json::array();
  std::stringstream list(FLAGS_p_values);
  std::string token;
  while (std::getline(list, token, ',')) {
    DeformerOptions options;
    if (!FillOptions(&options, error)) return false;
    options.method = Method::kMultiScale;
    options.graph.nodes_per_scale = std::atoi(token.c_str());
    GraphMethod deformer(options.method);
    std::vector<double> frame_ms;
    if (!InitAndDrag(mesh, options, layout, path, &deformer, &frame_ms, error)) return false;
    const ScaleSelection& s = deformer.selection();
    rows.push_back({{"P", options.graph.nodes_per_scale},
                    {"num_scales", static_cast<int>(deformer.graphs().size())},
                    {"dg1_nodes", deformer.graphs()[0].num_nodes()},
                    {"group1", s.group1_size},
                    {"selected_scale", deformer.active_graph() + 1},
                    {"scale_nodes", deformer.active().num_nodes()},
                    {"totally_free", s.num_totally_free},
                    {"half_free", s.num_half_free},
                    {"optimised_nodes", s.num_totally_free + s.num_half_free},
                    {"variables", deformer.variables()},
                    {"frame_ms_median", Median(frame_ms)}});
    std::cerr << "P=" << options.graph.nodes_per_scale << " " << rows.back().dump() << "\n";
  }
  DeformerOptions options;
  if (!FillOptions(&options, error)) return false;
  Json out;
  out["name"] = scenario.name;
  out["vertices"] = mesh.num_vertices();
  out["frames"] = frames;
  out["rigidity"] = RigidityModelName(options.rigidity.model);
  out["half_free"] = HalfFreeRuleName(options.selection.half_free);
  out["border"] = BorderRuleName(options.selection.border);
  out["hold_fixed_vertices"] = options.hold_fixed_vertices;
  out["pin_fixed_region"] = options.selection.pin_fixed_region;
  out["split_cells"] = options.lattice.split_cells;
  out["rows"] = rows;
  return WriteJson(FLAGS_out, out, error);
}

int Run() {
  std::string error;
  if (FLAGS_out.empty()) {
    std::cerr << "msdeform_figure_data: --out is required\n";
    return 1;
  }
  bool ok = false;
  if (FLAGS_mode == "graphs") {
    ok = RunGraphs(&error);
  } else if (FLAGS_mode == "edit") {
    ok = RunEdit(&error);
  } else if (FLAGS_mode == "nodes_vs_p") {
    ok = RunNodesVsP(&error);
  } else {
    error = "--mode=" + FLAGS_mode + ": expected graphs, edit or nodes_vs_p";
  }
  if (!ok) {
    std::cerr << "msdeform_figure_data: " << error << "\n";
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace msdeform

// The program after the shared prologue (apps/flags/program.h).
static int Body(const std::vector<std::string>&) {
  if (FLAGS_frames < 0 || FLAGS_frames > msdeform::kMaxScenarioFrames) {
    std::cerr << "msdeform_figure_data: --frames=" << FLAGS_frames << ": expected 0.."
              << msdeform::kMaxScenarioFrames << "\n";
    return 1;
  }
  return msdeform::Run();
}

int main(int argc, char** argv) {
  msdeform::ProgramInfo info;
  info.name = "msdeform_figure_data";
  info.usage =
      "msdeform_figure_data --mode=graphs|edit|nodes_vs_p --out=F.json "
      "[--mesh=M] [--scenario=S] [--method=...] (paper_figures/README.md)";
  return msdeform::RunProgram(info, Body, argc, argv);
}
