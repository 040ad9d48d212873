#include "apps/editor/script.h"

#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include "msdeform/core/json_file.h"
#include "msdeform/core/scenario.h"

namespace msdeform {
namespace editor {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// What a field holds.
enum class Type {
  kString,
  kInt,
  kNumber,
  kBool,
  kPoint2,
  kPoint3,
  kPolygon,
  kMatrix16,
  kObject,
  kScalar,
  kGroup  // a handle group, 0 .. kMaxHandleGroups - 1
};

struct Field {
  Field(Type type, std::vector<std::string> values = {}) : type(type), values(std::move(values)) {}
  Type type;
  std::vector<std::string> values;  // kString: the allowed values, empty for any
};

struct ActionSpec {
  std::map<std::string, Field> fields;  // besides "do"
  std::vector<std::string> required;
  // At most one of these may be given; with `one_of_required`, exactly one.
  std::vector<std::string> one_of;
  bool one_of_required = false;
};

const std::vector<std::string> kLabels = {"fixed", "free", "handle"};

// The files "open" reads and "save" writes, and the scenario's frame count.
std::map<std::string, Field> FileFields() {
  return {{"mesh", {Type::kString}},
          {"sel", {Type::kString}},
          {"def", {Type::kString}},
          {"scenario", {Type::kString}},
          {"frames", {Type::kInt}}};
}

const std::map<std::string, ActionSpec>& Specs() {
  static const auto* specs = new std::map<std::string, ActionSpec>{
      {"open",
       {FileFields(),
        {},
        {},
        false}},
      {"label",
       {{{"as", {Type::kString, kLabels}}, {"region", {Type::kObject}}, {"group", {Type::kGroup}}},
        {"as", "region"},
        {},
        false}},
      {"clear", {{}, {}, {}, false}},
      {"brush",
       {{{"as", {Type::kString, kLabels}},
         {"group", {Type::kGroup}},
         {"at", {Type::kPoint2}},
         {"at_vertex", {Type::kInt}},
         {"radius_px", {Type::kNumber}},
         {"through", {Type::kBool}}},
        {"as"},
        {"at", "at_vertex"},
        true}},
      {"lasso",
       {{{"as", {Type::kString, kLabels}},
         {"group", {Type::kGroup}},
         {"polygon", {Type::kPolygon}},
         {"through", {Type::kBool}}},
        {"as", "polygon"},
        {},
        false}},
      {"drag",
       {{{"transform", {Type::kObject}},
         {"matrix", {Type::kMatrix16}},
         {"def", {Type::kString}},
         {"frames", {Type::kInt}},
         {"group", {Type::kGroup}}},
        {},
        {"transform", "matrix", "def"},
        true}},
      {"mouse_drag",
       {{{"by", {Type::kPoint2}},
         {"steps", {Type::kInt}},
         {"group", {Type::kGroup}},
         {"mode", {Type::kString, {"translate", "rotate", "roll"}}}},
        {"by"},
        {},
        false}},
      {"reset", {{}, {}, {}, false}},
      {"set",
       {{{"flag", {Type::kString}}, {"value", {Type::kScalar}}}, {"flag", "value"}, {}, false}},
      {"view",
       {{{"shading", {Type::kString, {"flat", "smooth"}}},
         {"wireframe", {Type::kBool}},
         {"overlay", {Type::kString, {"handles", "rigidity", "none"}}},
         {"nodes", {Type::kBool}},
         {"edges", {Type::kBool}},
         {"ui", {Type::kBool}}},
        {},
        {},
        false}},
      {"camera",
       {{{"fit", {Type::kBool}},
         {"yaw_deg", {Type::kNumber}},
         {"pitch_deg", {Type::kNumber}},
         {"zoom", {Type::kNumber}},
         {"pan", {Type::kPoint2}},
         {"target", {Type::kPoint3}}},
        {},
        {},
        false}},
      {"screenshot",
       {{{"path", {Type::kString}}, {"ui", {Type::kBool}}, {"camera", {Type::kString}}},
        {"path"},
        {},
        false}},
      {"save",
       {FileFields(),
        {},
        {},
        false}},
  };
  return *specs;
}

bool IsPoint(const Json& value, size_t size) {
  if (!value.is_array() || value.size() != size) return false;
  for (const Json& x : value) {
    if (!x.is_number()) return false;
  }
  return true;
}

// "" when `value` fits `field`, else what was expected.
std::string Mismatch(const Json& value, const Field& field) {
  switch (field.type) {
    case Type::kString:
      if (!value.is_string()) return "a string";
      if (!field.values.empty()) {
        for (const std::string& allowed : field.values) {
          if (value.get<std::string>() == allowed) return "";
        }
        std::string list;
        for (const std::string& allowed : field.values) {
          list += (list.empty() ? "" : ", ") + allowed;
        }
        return "one of " + list;
      }
      return "";
    case Type::kInt:
      return value.is_number_integer() ? "" : "an integer";
    case Type::kGroup:
      return value.is_number_integer() && value.get<long long>() >= 0 &&
                     value.get<long long>() < kMaxHandleGroups
                 ? ""
                 : "a handle group, an integer in 0.." + std::to_string(kMaxHandleGroups - 1);
    case Type::kNumber:
      return value.is_number() ? "" : "a number";
    case Type::kBool:
      return value.is_boolean() ? "" : "true or false";
    case Type::kPoint2:
      return IsPoint(value, 2) ? "" : "[x, y] (pixels)";
    case Type::kPoint3:
      return IsPoint(value, 3) ? "" : "[x, y, z]";
    case Type::kPolygon:
      if (!value.is_array() || value.size() < 3) return "at least 3 points [[x, y], ...]";
      for (const Json& p : value) {
        if (!IsPoint(p, 2)) return "at least 3 points [[x, y], ...]";
      }
      return "";
    case Type::kMatrix16:
      return IsPoint(value, 16) ? "" : "16 numbers, the 4x4 matrix row by row";
    case Type::kObject:
      return value.is_object() ? "" : "an object";
    case Type::kScalar:
      return value.is_string() || value.is_number() || value.is_boolean()
                 ? ""
                 : "a string, number or boolean";
  }
  return "";
}

bool CheckAction(const Json& action, const std::string& where, std::string* kind,
                 std::string* error) {
  if (!action.is_object()) {
    *error = where + ": expected an object {\"do\": ...}";
    return false;
  }
  if (!action.contains("do") || !action["do"].is_string()) {
    *error = where + ".do: missing (the action: open, label, drag, screenshot, save, ...)";
    return false;
  }
  *kind = action["do"].get<std::string>();
  const auto spec = Specs().find(*kind);
  if (spec == Specs().end()) {
    std::string list;
    for (const auto& [name, ignored] : Specs()) list += (list.empty() ? "" : ", ") + name;
    *error = where + ".do: unknown action \"" + *kind + "\" (expected one of: " + list + ")";
    return false;
  }
  for (const auto& item : action.items()) {
    if (item.key() == "do") continue;
    const auto field = spec->second.fields.find(item.key());
    if (field == spec->second.fields.end()) {
      std::string list;
      for (const auto& [name, ignored] : spec->second.fields) {
        list += (list.empty() ? "" : ", ") + name;
      }
      *error = where + "." + item.key() + ": unknown field of \"" + *kind + "\"" +
               (list.empty() ? " (it takes none)" : " (expected one of: " + list + ")");
      return false;
    }
    const std::string expected = Mismatch(item.value(), field->second);
    if (!expected.empty()) {
      *error = where + "." + item.key() + ": expected " + expected;
      return false;
    }
  }
  for (const std::string& name : spec->second.required) {
    if (!action.contains(name)) {
      *error = where + "." + name + ": missing";
      return false;
    }
  }
  if (!spec->second.one_of.empty()) {
    int given = 0;
    std::string list;
    for (const std::string& name : spec->second.one_of) {
      given += action.contains(name);
      list += (list.empty() ? "" : ", ") + name;
    }
    if (given > 1 || (given == 0 && spec->second.one_of_required)) {
      *error = where + ": needs exactly one of " + list;
      return false;
    }
  }
  // Frames of a drag or a saved scenario, and the steps of a mouse drag, are
  // one solve each and are held as ints: 1 .. kMaxScenarioFrames, as a
  // scenario's "frames" (4294967296 wrapped to 0 and aborted; 10^8 ran out
  // of memory).
  for (const char* name : {"frames", "steps"}) {
    if (!action.contains(name)) continue;
    const Json& value = action[name];
    const bool in_range = value.is_number_unsigned()
                              ? value.get<unsigned long long>() <= kMaxScenarioFrames &&
                                    value.get<unsigned long long>() >= 1
                              : value.get<long long>() >= 1 &&
                                    value.get<long long>() <= kMaxScenarioFrames;
    if (!in_range) {
      *error = where + "." + name + ": expected 1.." + std::to_string(kMaxScenarioFrames);
      return false;
    }
  }
  if (action.contains("radius_px") && !(action["radius_px"].get<double>() > 0.0)) {
    *error = where + ".radius_px: must be more than 0";
    return false;
  }
  return true;
}

}  // namespace

std::string Script::Resolve(const std::string& file) const {
  if (file.empty() || fs::path(file).is_absolute()) return file;
  return (fs::path(path).parent_path() / file).lexically_normal().string();
}

bool ReadScript(const std::string& path, Script* script, std::string* error) {
  Json root;
  if (!ReadJsonFile(path, &root, error)) return false;
  if (!root.is_array()) {
    *error = path + ": expected an array of actions [{\"do\": ...}, ...]";
    return false;
  }
  Script result;
  result.path = path;
  for (size_t i = 0; i < root.size(); ++i) {
    ScriptAction action;
    action.where = path + ": actions[" + std::to_string(i) + "]";
    if (!CheckAction(root[i], action.where, &action.kind, error)) return false;
    action.args = root[i];
    result.actions.push_back(std::move(action));
  }
  *script = std::move(result);
  return true;
}

std::vector<ScriptOutput> ScriptOutputs(const Script& script) {
  std::vector<ScriptOutput> outputs;
  for (size_t i = 0; i < script.actions.size(); ++i) {
    const ScriptAction& action = script.actions[i];
    const std::string at = "actions[" + std::to_string(i) + "].";
    auto add = [&](const char* key, std::vector<std::string> extensions) {
      if (action.args.contains(key)) {
        outputs.push_back(
            {script.Resolve(action.args[key].get<std::string>()), at + key, std::move(extensions)});
      }
    };
    if (action.kind == "screenshot") {
      add("path", {".png"});
      add("camera", {".json"});
    } else if (action.kind == "save") {
      add("mesh", {".off", ".obj", ".ply"});
      add("sel", {".sel"});
      add("def", {".def"});
      add("scenario", {".json"});
    }
  }
  return outputs;
}

std::vector<std::string> ScriptInputs(const Script& script) {
  std::vector<std::string> inputs = {script.path};
  for (const ScriptAction& action : script.actions) {
    for (const char* key : {"mesh", "sel", "def", "scenario"}) {
      if ((action.kind == "open" || (action.kind == "drag" && std::string(key) == "def")) &&
          action.args.contains(key)) {
        inputs.push_back(script.Resolve(action.args[key].get<std::string>()));
      }
    }
  }
  return inputs;
}

}  // namespace editor
}  // namespace msdeform
