#include "msdeform/core/scenario.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/json_file.h"
#include "msdeform/core/parallel.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string Join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string Index(const std::string& parent, size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

std::string Describe(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::object:
      return "an object";
    case Json::value_t::number_float:
      return "a number with a fraction";
    default:
      return "a number";
  }
}

// Parses the JSON tree into a Scenario, remembering the first error as
// "<field>: <problem>". Every method returns false once an error is set.
class ScenarioParser {
 public:
  const std::string& error() const { return error_; }

  bool Fail(const std::string& field, const std::string& problem) {
    error_ = (field.empty() ? "" : field + ": ") + problem;
    return false;
  }

  bool ExpectType(const Json& value, const std::string& field, bool ok, const char* expected) {
    if (ok) return true;
    return Fail(field, std::string("expected ") + expected + ", found " + Describe(value));
  }

  // An object whose keys are all in `allowed`.
  bool ExpectObject(const Json& value, const std::string& field,
                    const std::set<std::string>& allowed) {
    if (!ExpectType(value, field, value.is_object(), "an object")) return false;
    for (const auto& item : value.items()) {
      if (allowed.count(item.key())) continue;
      std::string list;
      for (const std::string& key : allowed) list += (list.empty() ? "" : ", ") + key;
      return Fail(Join(field, item.key()), "unknown field (expected one of: " + list + ")");
    }
    return true;
  }

  bool Number(const Json& value, const std::string& field, double* number) {
    if (!ExpectType(value, field, value.is_number(), "a number")) return false;
    *number = value.get<double>();
    if (!std::isfinite(*number)) return Fail(field, "must be finite");
    return true;
  }

  bool Integer(const Json& value, const std::string& field, int* number) {
    if (!ExpectType(value, field, value.is_number_integer(), "an integer")) return false;
    const auto wide = value.get<long long>();
    if (value.is_number_unsigned() &&
        value.get<unsigned long long>() >
            static_cast<unsigned long long>(std::numeric_limits<int>::max())) {
      return Fail(field, "is too large");
    }
    if (wide < std::numeric_limits<int>::min() || wide > std::numeric_limits<int>::max()) {
      return Fail(field, "is too large");
    }
    *number = static_cast<int>(wide);
    return true;
  }

  bool String(const Json& value, const std::string& field, std::string* text) {
    if (!ExpectType(value, field, value.is_string(), "a string")) return false;
    *text = value.get<std::string>();
    return true;
  }

  bool Vector3(const Json& value, const std::string& field, Eigen::Vector3d* vector) {
    if (!ExpectType(value, field, value.is_array() && value.size() == 3,
                    "an array of 3 numbers [x, y, z]")) {
      return false;
    }
    for (int k = 0; k < 3; ++k) {
      if (!Number(value[k], Index(field, k), &(*vector)[k])) return false;
    }
    return true;
  }

  // `depth` counts the regions around this one (0 at the top).
  bool Region(const Json& value, const std::string& field, VertexRegion* region, int depth = 0) {
    static const std::set<std::string> kKinds = {"vertices", "sphere", "slab", "any", "all",
                                                 "not"};
    if (depth > kMaxRegionDepth) {
      // The field spells every level; keep the message to one short line.
      const size_t kShown = 40;
      const std::string shown = field.size() > kShown ? field.substr(0, kShown) + "..." : field;
      return Fail(shown, "regions nest more than " + std::to_string(kMaxRegionDepth) + " deep");
    }
    if (!ExpectObject(value, field, kKinds)) return false;
    if (value.size() != 1) {
      return Fail(field,
                  "a region needs exactly one of vertices, sphere, slab, any, all, not; found " +
                      std::to_string(value.size()));
    }
    region->field = field;
    const std::string kind = value.begin().key();
    const Json& body = value.begin().value();
    const std::string at = Join(field, kind);
    if (kind == "vertices") {
      region->kind = VertexRegion::Kind::kVertices;
      if (!ExpectType(body, at, body.is_array(), "an array of vertex ids")) return false;
      if (body.empty()) return Fail(at, "empty list selects no vertex");
      for (size_t i = 0; i < body.size(); ++i) {
        int id = 0;
        if (!Integer(body[i], Index(at, i), &id)) return false;
        if (id < 0) return Fail(Index(at, i), "vertex ids are 0 or more");
        region->vertices.push_back(id);
      }
      return true;
    }
    if (kind == "sphere") {
      region->kind = VertexRegion::Kind::kSphere;
      if (!ExpectObject(body, at, {"center", "center_vertex", "radius", "radius_rel"})) {
        return false;
      }
      if (body.contains("center") == body.contains("center_vertex")) {
        return Fail(at, "needs exactly one of center, center_vertex");
      }
      if (body.contains("center")) {
        if (!Vector3(body["center"], Join(at, "center"), &region->center)) return false;
      } else {
        region->center_is_vertex = true;
        if (!Integer(body["center_vertex"], Join(at, "center_vertex"), &region->center_vertex)) {
          return false;
        }
        if (region->center_vertex < 0) {
          return Fail(Join(at, "center_vertex"), "vertex ids are 0 or more");
        }
      }
      if (body.contains("radius") == body.contains("radius_rel")) {
        return Fail(at, "needs exactly one of radius, radius_rel");
      }
      region->radius_is_relative = body.contains("radius_rel");
      const std::string radius_field =
          Join(at, region->radius_is_relative ? "radius_rel" : "radius");
      if (!Number(body[region->radius_is_relative ? "radius_rel" : "radius"], radius_field,
                  &region->radius)) {
        return false;
      }
      if (region->radius < 0.0) return Fail(radius_field, "must not be negative");
      return true;
    }
    if (kind == "slab") {
      region->kind = VertexRegion::Kind::kSlab;
      if (!ExpectObject(body, at, {"axis", "from", "to"})) return false;
      for (const char* key : {"axis", "from", "to"}) {
        if (!body.contains(key)) return Fail(Join(at, key), "missing");
      }
      std::string axis;
      if (!String(body["axis"], Join(at, "axis"), &axis)) return false;
      if (axis != "x" && axis != "y" && axis != "z") {
        return Fail(Join(at, "axis"), "expected \"x\", \"y\" or \"z\", found \"" + axis + "\"");
      }
      region->axis = axis[0] - 'x';
      if (!Number(body["from"], Join(at, "from"), &region->from)) return false;
      if (!Number(body["to"], Join(at, "to"), &region->to)) return false;
      if (region->from > region->to) {
        return Fail(at, "from must not exceed to (fractions of the extent, e.g. 0 to 0.1)");
      }
      return true;
    }
    if (kind == "not") {
      region->kind = VertexRegion::Kind::kNot;
      if (!ExpectType(body, at, body.is_object(), "a region")) return false;
      region->children.resize(1);
      return Region(body, at, &region->children[0], depth + 1);
    }
    // any / all
    region->kind = kind == "any" ? VertexRegion::Kind::kAny : VertexRegion::Kind::kAll;
    if (!ExpectType(body, at, body.is_array(), "an array of regions")) return false;
    if (body.empty()) return Fail(at, "needs at least one region");
    region->children.resize(body.size());
    for (size_t i = 0; i < body.size(); ++i) {
      if (!Region(body[i], Index(at, i), &region->children[i], depth + 1)) return false;
    }
    return true;
  }

  bool Motion(const Json& value, const std::string& field, HandleMotion* motion) {
    if (!ExpectObject(value, field, {"translation", "translation_rel", "rotation"})) return false;
    if (value.contains("translation") && value.contains("translation_rel")) {
      return Fail(field, "give translation or translation_rel, not both");
    }
    if (value.contains("translation")) {
      if (!Vector3(value["translation"], Join(field, "translation"), &motion->translation)) {
        return false;
      }
    }
    if (value.contains("translation_rel")) {
      motion->translation_is_relative = true;
      if (!Vector3(value["translation_rel"], Join(field, "translation_rel"),
                   &motion->translation)) {
        return false;
      }
    }
    if (value.contains("rotation")) {
      const std::string at = Join(field, "rotation");
      const Json& rotation = value["rotation"];
      if (!ExpectObject(rotation, at, {"axis", "angle_deg", "center"})) return false;
      for (const char* key : {"axis", "angle_deg"}) {
        if (!rotation.contains(key)) return Fail(Join(at, key), "missing");
      }
      Eigen::Vector3d axis;
      if (!Vector3(rotation["axis"], Join(at, "axis"), &axis)) return false;
      // A huge axis such as [1e300, 1e300, 1e300] has an infinite norm and
      // normalises to zeros, so check the unit axis itself.
      const Eigen::Vector3d unit = axis.normalized();
      if (!(axis.norm() > 0.0) || !unit.allFinite() || std::abs(unit.norm() - 1.0) > 1e-9) {
        return Fail(Join(at, "axis"), "must have a finite, non-zero length");
      }
      motion->rotation_axis = unit;
      if (!Number(rotation["angle_deg"], Join(at, "angle_deg"), &motion->rotation_angle_deg)) {
        return false;
      }
      if (rotation.contains("center")) {
        const Json& center = rotation["center"];
        if (center.is_string()) {
          if (center.get<std::string>() != "centroid") {
            return Fail(Join(at, "center"), "expected [x, y, z] or \"centroid\"");
          }
          motion->rotate_about_centroid = true;
        } else {
          motion->rotate_about_centroid = false;
          if (!Vector3(center, Join(at, "center"), &motion->rotation_center)) return false;
        }
      }
    }
    return true;
  }

  // A path in the file, relative to the file's folder unless absolute.
  static std::string Resolve(const std::string& scenario_path, const std::string& file) {
    const fs::path file_path(file);
    return file_path.is_absolute()
               ? file
               : (fs::path(scenario_path).parent_path() / file_path).lexically_normal().string();
  }

  bool Parse(const Json& root, const std::string& path, Scenario* scenario) {
    if (!ExpectObject(
            root, "",
            {"name", "description", "mesh", "fixed", "handle", "handles", "watch", "transform",
             "frames", "sel", "def"})) {
      return false;
    }
    scenario->name = fs::path(path).stem().string();
    if (root.contains("name") && !String(root["name"], "name", &scenario->name)) return false;
    if (root.contains("description")) {
      std::string ignored;
      if (!String(root["description"], "description", &ignored)) return false;
    }
    if (!root.contains("mesh")) return Fail("mesh", "missing (the mesh file to edit)");
    std::string mesh;
    if (!String(root["mesh"], "mesh", &mesh)) return false;
    if (mesh.empty()) return Fail("mesh", "is empty");
    scenario->mesh_path = Resolve(path, mesh);
    if (root.contains("fixed")) {
      const Json& fixed = root["fixed"];
      if (!ExpectType(fixed, "fixed", fixed.is_array(), "an array of regions")) return false;
      scenario->fixed.resize(fixed.size());
      for (size_t i = 0; i < fixed.size(); ++i) {
        if (!Region(fixed[i], Index("fixed", i), &scenario->fixed[i])) return false;
      }
    }
    if (root.contains("sel") || root.contains("def")) {
      // A Botsch-Sorkine pair instead of regions and a transform.
      for (const char* key : {"fixed", "handle", "handles", "transform"}) {
        if (root.contains(key)) {
          return Fail(key, "not allowed with \"sel\" and \"def\" (they give the handles and "
                           "the transform)");
        }
      }
      for (const char* key : {"sel", "def"}) {
        if (!root.contains(key)) {
          return Fail(key, std::string("missing (\"sel\" and \"def\" go together)"));
        }
      }
      std::string sel, def;
      if (!String(root["sel"], "sel", &sel) || !String(root["def"], "def", &def)) return false;
      scenario->sel_path = Resolve(path, sel);
      scenario->def_path = Resolve(path, def);
      std::string problem;
      if (!ReadDef(scenario->def_path, &scenario->def_transform, &problem)) {
        return Fail("def", problem);
      }
    } else if (root.contains("handles")) {
      // Several handles, each with its own transform.
      for (const char* key : {"handle", "transform"}) {
        if (root.contains(key)) {
          return Fail(key, "not allowed with \"handles\" (each handle has its region and "
                           "transform there)");
        }
      }
      const Json& handles = root["handles"];
      if (!ExpectType(handles, "handles", handles.is_array(), "an array of handles")) {
        return false;
      }
      if (handles.empty()) return Fail("handles", "is empty (give at least one handle)");
      if (handles.size() > static_cast<size_t>(kMaxHandleGroups)) {
        return Fail("handles", "has " + std::to_string(handles.size()) + " handles; at most " +
                                   std::to_string(kMaxHandleGroups));
      }
      scenario->handles.resize(handles.size());
      for (size_t i = 0; i < handles.size(); ++i) {
        const std::string at = Index("handles", i);
        if (!ExpectObject(handles[i], at, {"region", "transform"})) return false;
        if (!handles[i].contains("region")) {
          return Fail(Join(at, "region"), "missing (the region to drag)");
        }
        if (!Region(handles[i]["region"], Join(at, "region"), &scenario->handles[i].region)) {
          return false;
        }
        if (handles[i].contains("transform") &&
            !Motion(handles[i]["transform"], Join(at, "transform"),
                    &scenario->handles[i].motion)) {
          return false;
        }
      }
    } else {
      if (!root.contains("handle")) {
        return Fail("handle", "missing (the region to drag, or \"handles\")");
      }
      scenario->handles.resize(1);
      if (!Region(root["handle"], "handle", &scenario->handles[0].region)) return false;
      if (root.contains("transform") &&
          !Motion(root["transform"], "transform", &scenario->handles[0].motion)) {
        return false;
      }
    }
    if (root.contains("watch")) {
      scenario->has_watch = true;
      if (!Region(root["watch"], "watch", &scenario->watch)) return false;
    }
    if (root.contains("frames")) {
      if (!Integer(root["frames"], "frames", &scenario->frames)) return false;
      if (scenario->frames < 1) return Fail("frames", "must be at least 1");
      if (scenario->frames > kMaxScenarioFrames) {
        return Fail("frames", "must be at most " + std::to_string(kMaxScenarioFrames));
      }
    }
    return true;
  }

 private:
  std::string error_;
};

// ---------------------------------------------------------------------------
// Resolution against a mesh.

struct MeshFrame {
  Eigen::AlignedBox3d box;
  double diagonal = 0.0;
  int num_threads = 1;  // for the passes over all vertices
};

std::string Point(const Eigen::Vector3d& p) {
  std::ostringstream text;
  text << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return text.str();
}

// Selects the region's vertices (sorted, unique). On failure *problem is
// "<field>: <what>".
bool Select(const VertexRegion& region, const Mesh& mesh, const MeshFrame& frame,
            std::vector<int>* ids, std::string* problem) {
  const int n = mesh.num_vertices();
  ids->clear();
  std::string what;
  switch (region.kind) {
    case VertexRegion::Kind::kVertices: {
      for (size_t i = 0; i < region.vertices.size(); ++i) {
        const int id = region.vertices[i];
        if (id < 0 || id >= n) {
          *problem = Index(Join(region.field, "vertices"), i) + ": vertex " + std::to_string(id) +
                     " is outside the mesh's 0.." + std::to_string(n - 1);
          return false;
        }
        ids->push_back(id);
      }
      std::sort(ids->begin(), ids->end());
      ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
      what = "vertex list";
      break;
    }
    case VertexRegion::Kind::kSphere: {
      Eigen::Vector3d center = region.center;
      if (region.center_is_vertex) {
        if (region.center_vertex >= n) {
          *problem = Join(region.field, "sphere.center_vertex") + ": vertex " +
                     std::to_string(region.center_vertex) + " is outside the mesh's 0.." +
                     std::to_string(n - 1);
          return false;
        }
        center = mesh.vertices.col(region.center_vertex);
      }
      const double radius = region.radius * (region.radius_is_relative ? frame.diagonal : 1.0);
      const double radius_squared = radius * radius;
      *ids = SelectIndices(
          n, frame.num_threads,
          [&](int v) { return (mesh.vertices.col(v) - center).squaredNorm() <= radius_squared; });
      std::ostringstream text;
      text << "sphere of radius " << radius << " around " << Point(center);
      what = text.str();
      break;
    }
    case VertexRegion::Kind::kSlab: {
      const double low = frame.box.min()[region.axis];
      const double extent = frame.box.max()[region.axis] - low;
      // A little slack so that "0 to 0.1" keeps a vertex sitting exactly at
      // 10% despite rounding in low + 0.1 * extent.
      const double slack = 1e-9 * extent;
      const double from = low + region.from * extent - slack;
      const double to = low + region.to * extent + slack;
      *ids = SelectIndices(
          n, frame.num_threads,
          [&](int v) {
            const double x = mesh.vertices(region.axis, v);
            return x >= from && x <= to;
          });
      std::ostringstream text;
      text << "slab " << static_cast<char>('x' + region.axis) << " from " << region.from << " to "
           << region.to << " of the extent [" << low << ", " << low + extent << "]";
      what = text.str();
      break;
    }
    case VertexRegion::Kind::kAny:
    case VertexRegion::Kind::kAll: {
      const bool any = region.kind == VertexRegion::Kind::kAny;
      for (size_t i = 0; i < region.children.size(); ++i) {
        std::vector<int> child;
        if (!Select(region.children[i], mesh, frame, &child, problem)) return false;
        std::vector<int> merged;
        if (i == 0) {
          merged = std::move(child);
        } else if (any) {
          std::set_union(ids->begin(), ids->end(), child.begin(), child.end(),
                         std::back_inserter(merged));
        } else {
          std::set_intersection(ids->begin(), ids->end(), child.begin(), child.end(),
                                std::back_inserter(merged));
        }
        ids->swap(merged);
      }
      what = any ? "union" : "intersection of its regions";
      break;
    }
    case VertexRegion::Kind::kNot: {
      std::vector<int> excluded;
      if (!Select(region.children[0], mesh, frame, &excluded, problem)) return false;
      std::vector<char> is_excluded(n, 0);
      for (int v : excluded) is_excluded[v] = 1;
      *ids = SelectIndices(n, frame.num_threads, [&](int v) { return !is_excluded[v]; });
      what = "complement of its region";
      break;
    }
  }
  if (ids->empty()) {
    *problem = region.field + ": " + what + " selects no vertex of the mesh";
    return false;
  }
  return true;
}

Eigen::Vector3d Centroid(const Mesh& mesh, const std::vector<int>& ids) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int v : ids) sum += mesh.vertices.col(v);
  return ids.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(ids.size()));
}

// The scenario's motion, "rotate about the centre c, then translate by t", as
// a drag motion: x -> R (x - c) + c + t, pivot c, no stretch.
DragMotion ScenarioDragMotion(const HandleMotion& motion, const Eigen::Vector3d& centroid,
                              double diagonal) {
  DragMotion drag;
  drag.pivot = motion.rotate_about_centroid ? centroid : motion.rotation_center;
  drag.rotation =
      Eigen::AngleAxisd(motion.rotation_angle_deg * M_PI / 180.0, motion.rotation_axis);
  drag.pivot_displacement =
      motion.translation * (motion.translation_is_relative ? diagonal : 1.0);
  return drag;
}

}  // namespace

bool ReadScenario(const std::string& path, Scenario* scenario, std::string* error) {
  Json root;
  if (!ReadJsonFile(path, &root, error)) return false;
  Scenario result;
  result.path = path;
  ScenarioParser parser;
  if (!parser.Parse(root, path, &result)) {
    *error = path + ": " + parser.error();
    return false;
  }
  *scenario = std::move(result);
  return true;
}

std::vector<int> HandleGroupVertices(const HandleLayout& layout, int g) {
  std::vector<int> vertices;
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    if (layout.group_of(i) == g) vertices.push_back(layout.moveable[i]);
  }
  return vertices;
}

bool ResolveScenario(const Scenario& scenario, const Mesh& mesh, HandleLayout* layout,
                     std::vector<int>* watch, HandleTransforms* deformed_from_rest,
                     std::string* error, int num_threads) {
  const std::string& where = scenario.path.empty() ? std::string("scenario") : scenario.path;
  if (mesh.num_vertices() == 0) {
    *error = where + ": the mesh has no vertices";
    return false;
  }
  MeshFrame frame;
  frame.box = BoundingBox(mesh, num_threads);
  frame.diagonal = frame.box.diagonal().norm();  // BoundingBoxDiagonal (the mesh has a vertex)
  frame.num_threads = num_threads;

  HandleLayout result;
  std::string problem;
  if (scenario.uses_sel_def()) {
    if (!ReadSel(scenario.sel_path, mesh.num_vertices(), &result, &problem)) {
      *error = where + ": sel: " + problem;
      return false;
    }
  }
  for (const VertexRegion& region : scenario.fixed) {
    std::vector<int> ids;
    std::vector<int> merged;
    if (!Select(region, mesh, frame, &ids, &problem)) {
      *error = where + ": " + problem;
      return false;
    }
    std::set_union(result.fixed.begin(), result.fixed.end(), ids.begin(), ids.end(),
                   std::back_inserter(merged));
    result.fixed.swap(merged);
  }
  if (!scenario.uses_sel_def()) {
    // Each handle's vertices, tagged with its group, merged in vertex order.
    std::vector<std::pair<int, int>> tagged;  // (vertex, group)
    const int num_groups = static_cast<int>(scenario.handles.size());
    for (int g = 0; g < num_groups; ++g) {
      std::vector<int> ids;
      if (!Select(scenario.handles[g].region, mesh, frame, &ids, &problem)) {
        *error = where + ": " + problem;
        return false;
      }
      for (int v : ids) tagged.emplace_back(v, g);
    }
    std::sort(tagged.begin(), tagged.end());
    for (size_t i = 1; i < tagged.size(); ++i) {
      if (tagged[i].first == tagged[i - 1].first) {
        *error = where + ": handles[" + std::to_string(tagged[i - 1].second) + "] and handles[" +
                 std::to_string(tagged[i].second) + "] share vertex " +
                 std::to_string(tagged[i].first) + " (a vertex follows one handle)";
        return false;
      }
    }
    for (const auto& [v, g] : tagged) {
      result.moveable.push_back(v);
      if (num_groups > 1) result.group.push_back(g);
    }
  }
  std::vector<int> watched;
  if (scenario.has_watch && !Select(scenario.watch, mesh, frame, &watched, &problem)) {
    *error = where + ": " + problem;
    return false;
  }
  if (!ValidateHandles(result, mesh.num_vertices(), &problem)) {
    *error = where + ": fixed and handle regions: " + problem;
    return false;
  }
  if (scenario.uses_sel_def()) {
    *deformed_from_rest = scenario.def_transform;
  } else {
    std::vector<Eigen::Affine3d> transforms;
    for (int g = 0; g < static_cast<int>(scenario.handles.size()); ++g) {
      transforms.push_back(
          DragFrame(ScenarioDragMotion(scenario.handles[g].motion,
                                       Centroid(mesh, HandleGroupVertices(result, g)),
                                       frame.diagonal),
                    1.0));
    }
    *deformed_from_rest = transforms.size() == 1 ? HandleTransforms(transforms[0])
                                                 : HandleTransforms(std::move(transforms));
  }
  *layout = std::move(result);
  *watch = std::move(watched);
  return true;
}

std::vector<HandleTransforms> DragPath(const Scenario& scenario, const Mesh& mesh,
                                       const HandleLayout& layout, int num_threads) {
  const int frames = std::max(1, scenario.frames);
  if (scenario.uses_sel_def()) {
    const std::vector<Eigen::Affine3d> path =
        InterpolateDragPath(scenario.def_transform, Centroid(mesh, layout.moveable), frames);
    return std::vector<HandleTransforms>(path.begin(), path.end());
  }
  const double diagonal = BoundingBoxDiagonal(mesh, num_threads);
  const int num_groups = static_cast<int>(scenario.handles.size());
  std::vector<std::vector<Eigen::Affine3d>> per_group;  // [group][frame]
  for (int g = 0; g < num_groups; ++g) {
    const Eigen::Vector3d centroid =
        Centroid(mesh, num_groups == 1 ? layout.moveable : HandleGroupVertices(layout, g));
    per_group.push_back(InterpolateDragPath(
        ScenarioDragMotion(scenario.handles[g].motion, centroid, diagonal), frames));
  }
  std::vector<HandleTransforms> path;
  for (int f = 0; f < frames; ++f) {
    if (num_groups == 1) {
      path.emplace_back(per_group[0][f]);
      continue;
    }
    std::vector<Eigen::Affine3d> transforms;
    for (int g = 0; g < num_groups; ++g) transforms.push_back(per_group[g][f]);
    path.emplace_back(std::move(transforms));
  }
  return path;
}

}  // namespace msdeform
