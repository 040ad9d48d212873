// Editing scenarios: a JSON file naming a mesh, the regions held fixed, the
// moveable handle and its motion (or several handles, each with its own
// motion), and an optional "watch" region of vertices that should not move
// (to measure leakage).
//
// Example (comments are allowed in the file):
//
//   {
//     "name": "armadillo_arm_raise",                  // optional; default: file stem
//     "description": "free text",                     // optional, ignored
//     "mesh": "../../data/meshes/armadillo.off",      // relative to this file's folder
//     "fixed": [                                      // optional; union; may be empty
//       {"slab": {"axis": "y", "from": 0.0, "to": 0.1}}
//     ],
//     "handle": {"sphere": {"center_vertex": 1234, "radius_rel": 0.05}},
//     "watch": {"vertices": [10, 11, 12]},            // optional
//     "transform": {                                  // optional; default identity
//       "translation_rel": [0, 0.2, 0],               // or "translation": [x, y, z]
//       "rotation": {"axis": [0, 0, 1], "angle_deg": 30,
//                    "center": "centroid"}            // or [x, y, z]; default centroid
//     },
//     "frames": 30                                    // optional, default 1
//   }
//
// Instead of "handle" and "transform", a scenario may give several handles
// that move independently (handle groups, core/handles.h), each a region and
// its own optional transform, about its own centroid:
//     "handles": [
//       {"region": {"sphere": {"center_vertex": 12, "radius_rel": 0.05}},
//        "transform": {"translation_rel": [0, 0.1, 0]}},
//       {"region": {"slab": {"axis": "x", "from": 0.9, "to": 1.0}}}   // stays put
//     ],
// Two handles' regions may not share a vertex.
//
// Instead of "fixed", "handle" and "transform", a scenario may name a
// Botsch-Sorkine pair, relative to its folder (docs/formats.md):
//     "sel": "cactus.sel",   // per vertex 0 fixed, 1 free, 2 handle
//     "def": "cactus.def",   // the handle's final 4x4 transform, world coordinates
// Its drag path interpolates the .def transform (core/drag_path.h) about the
// handle's centroid; "watch" may be given with either form.
//
// A REGION is exactly one of:
//   {"vertices": [ids...]}
//   {"sphere": {"center": [x,y,z] | "center_vertex": id,
//               "radius": r | "radius_rel": r_over_bbox_diagonal}}
//   {"slab": {"axis": "x"|"y"|"z", "from": f0, "to": f1}}
//       f0, f1 are fractions of the bounding box extent along the axis:
//       the lowest 10% along y is {"axis": "y", "from": 0, "to": 0.1}.
//   {"any": [REGION, ...]}   union
//   {"all": [REGION, ...]}   intersection
//   {"not": REGION}          complement: every mesh vertex REGION does not
//                            select ("everything but this leg" is
//                            {"not": LEG}; "A but not B" is {"all": [A, {"not": B}]})
// Spheres and slabs are closed (boundary included). Every region, nested ones
// too, must select at least one vertex: an empty selection is almost always a
// typo, so it is an error naming the region (a "not" of a region that selects
// the whole mesh is one too).
//
// The handle transform is: rotate about the centre (the handle's rest
// centroid unless given), then translate; "translation_rel" is in units of
// the bounding box diagonal. Frame k of n (k = 1..n) of the drag path applies
// the fraction k/n of the angle and of the translation, about the same centre.

#ifndef MSDEFORM_CORE_SCENARIO_H_
#define MSDEFORM_CORE_SCENARIO_H_

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"

namespace msdeform {

// One node of a region expression; see the format above.
struct VertexRegion {
  enum class Kind { kVertices, kSphere, kSlab, kAny, kAll, kNot };
  Kind kind = Kind::kVertices;
  // Where the region sits in the file, e.g. "fixed[1].any[0]", for messages.
  std::string field;

  std::vector<int> vertices;  // kVertices, as listed.

  // kSphere: centre is a point or the rest position of a vertex.
  bool center_is_vertex = false;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  int center_vertex = -1;
  double radius = 0.0;
  bool radius_is_relative = false;  // radius times the bbox diagonal.

  // kSlab: coordinate `axis` (0, 1, 2) between these fractions of the extent.
  int axis = 0;
  double from = 0.0;
  double to = 0.0;

  std::vector<VertexRegion> children;  // kAny, kAll; kNot: the one complemented.
};

// The handle's motion as written in the file, before a mesh gives it scale
// and a centroid.
struct HandleMotion {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  bool translation_is_relative = false;                      // times the bbox diagonal.
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitZ();  // unit length.
  double rotation_angle_deg = 0.0;
  bool rotate_about_centroid = true;  // else about rotation_center.
  Eigen::Vector3d rotation_center = Eigen::Vector3d::Zero();
};

// Upper bound of "frames" (and of msdeform --frames): every frame is a solve,
// and the drag path is held in memory.
constexpr int kMaxScenarioFrames = 100000;

// Upper bound of how deep "any", "all" and "not" nest: the parser and the
// selection recurse once per level, so a deeper file is refused rather than
// allowed to overflow the stack (20000 levels did). Real regions nest 2 or 3.
constexpr int kMaxRegionDepth = 64;

// One handle of a scenario: its region and its motion.
struct ScenarioHandle {
  VertexRegion region;
  HandleMotion motion;
};

struct Scenario {
  std::string path;       // the scenario file itself, for messages.
  std::string name;       // "name", or the file stem.
  std::string mesh_path;  // "mesh" resolved against the scenario's folder.
  std::vector<VertexRegion> fixed;
  // "handle" and "transform" (one entry), or "handles": handle group g is
  // handles[g]. Empty with "sel" and "def".
  std::vector<ScenarioHandle> handles;
  bool has_watch = false;
  VertexRegion watch;
  int frames = 1;  // 1 .. kMaxScenarioFrames.
  // "sel" and "def" (resolved), instead of "fixed", "handle" and "transform":
  // the handles from a .sel file (read against the mesh by ResolveScenario)
  // and the final transform from a .def file (read by ReadScenario).
  std::string sel_path, def_path;
  Eigen::Affine3d def_transform = Eigen::Affine3d::Identity();

  bool uses_sel_def() const { return !sel_path.empty(); }
};

// Parses a scenario file. Missing, mistyped, unknown or out-of-range fields
// give false and one line naming the file and the field path, e.g.
// "s.json: fixed[1].sphere.radius: expected a number, found a string".
bool ReadScenario(const std::string& path, Scenario* scenario, std::string* error);

// Applies a scenario to its mesh: selects the fixed, handle and watch
// vertices (sorted, unique; from the .sel file when the scenario names one;
// the layout's handle groups from "handles") and computes the final handle
// transforms (one, or one a group). Fails, naming the region, when a region
// selects nothing or names a vertex outside the mesh, when two handles share
// a vertex, or when the layout does not validate (e.g. a vertex both fixed
// and moveable). The passes over all vertices (bounding box, regions) use up
// to `num_threads` threads, with the same result for any count.
bool ResolveScenario(const Scenario& scenario, const Mesh& mesh, HandleLayout* layout,
                     std::vector<int>* watch, HandleTransforms* deformed_from_rest,
                     std::string* error, int num_threads = 1);

// The drag path: scenario.frames frames, frame k (1-based) carrying the
// fraction k / frames of each handle's motion (core/drag_path.h: k / frames
// of the angle about the rotation centre, which moves by k / frames of the
// translation; a .def's rotation part slerped, its rest blended linearly);
// the last equals ResolveScenario's transforms. `layout` is the resolved
// layout (each group's rest centroid is its rotation centre unless given).
// The bounding box takes up to `num_threads` threads.
std::vector<HandleTransforms> DragPath(const Scenario& scenario, const Mesh& mesh,
                                       const HandleLayout& layout, int num_threads = 1);

// The vertices of handle group g of a layout (sorted).
std::vector<int> HandleGroupVertices(const HandleLayout& layout, int g);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_SCENARIO_H_
