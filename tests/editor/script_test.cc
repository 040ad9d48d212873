#include "apps/editor/script.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace msdeform {
namespace editor {
namespace {

namespace fs = std::filesystem;

class ScriptTest : public testing::Test {
 protected:
  void SetUp() override {
    char folder[] = "/tmp/msdeform_script_test_XXXXXX";
    ASSERT_NE(mkdtemp(folder), nullptr);
    folder_ = folder;
  }
  void TearDown() override { fs::remove_all(folder_); }

  // Writes `text` as s.json in the test's folder and reads it back.
  bool Read(const std::string& text, Script* script, std::string* error) {
    path_ = folder_ + "/s.json";
    std::ofstream(path_) << text;
    return ReadScript(path_, script, error);
  }

  std::string folder_, path_;
};

TEST_F(ScriptTest, ReadsActionsAndResolvesPathsAgainstItsFolder) {
  Script script;
  std::string error;
  ASSERT_TRUE(Read(R"([
    // comments are allowed
    {"do": "open", "mesh": "../m.off", "frames": 3},
    {"do": "label", "as": "handle", "region": {"sphere": {"center_vertex": 1, "radius_rel": 0.1}}},
    {"do": "drag", "transform": {"translation_rel": [0, 0.1, 0]}},
    {"do": "screenshot", "path": "out/a.png", "camera": "/abs/cam.json"},
    {"do": "save", "mesh": "a.obj", "sel": "a.sel", "scenario": "a.json"}
  ])",
                   &script, &error))
      << error;
  ASSERT_EQ(script.actions.size(), 5u);
  EXPECT_EQ(script.actions[1].kind, "label");
  EXPECT_EQ(script.actions[1].where, path_ + ": actions[1]");
  EXPECT_EQ(script.Resolve("../m.off"), fs::path(folder_).parent_path().string() + "/m.off");
  EXPECT_EQ(script.Resolve("/abs/cam.json"), "/abs/cam.json");
  const std::vector<ScriptOutput> outputs = ScriptOutputs(script);
  ASSERT_EQ(outputs.size(), 5u);
  EXPECT_EQ(outputs[0].path, folder_ + "/out/a.png");
  EXPECT_EQ(outputs[0].field, "actions[3].path");
  EXPECT_EQ(outputs[1].path, "/abs/cam.json");
  EXPECT_EQ(outputs[2].field, "actions[4].mesh");
  EXPECT_EQ(outputs[2].extensions, std::vector<std::string>({".off", ".obj", ".ply"}));
  const std::vector<std::string> inputs = ScriptInputs(script);
  EXPECT_EQ(inputs,
            std::vector<std::string>({path_, fs::path(folder_).parent_path().string() + "/m.off"}));
}

TEST_F(ScriptTest, RefusesWhatItCannotRunWithOneLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"{", "invalid JSON"},
      {R"({"do": "open"})", "expected an array of actions"},
      {R"([3])", "actions[0]: expected an object"},
      {R"([{"mesh": "a.off"}])", "actions[0].do: missing"},
      {R"([{"do": "fly"}])", "actions[0].do: unknown action \"fly\""},
      {R"([{"do": "open", "msh": "a.off"}])", "actions[0].msh: unknown field of \"open\""},
      {R"([{"do": "clear", "all": true}])",
       "actions[0].all: unknown field of \"clear\" (it takes none)"},
      {R"([{"do": "label", "region": {}}])", "actions[0].as: missing"},
      {R"([{"do": "label", "as": "pinned", "region": {}}])",
       "actions[0].as: expected one of fixed, free, handle"},
      {R"([{"do": "brush", "as": "fixed"}])", "actions[0]: needs exactly one of at, at_vertex"},
      {R"([{"do": "brush", "as": "fixed", "at": [1, 2, 3]}])", "actions[0].at: expected [x, y]"},
      {R"([{"do": "brush", "as": "fixed", "at": [1, 2], "radius_px": 0}])",
       "actions[0].radius_px: must be more than 0"},
      {R"([{"do": "drag", "matrix": [1, 0], "def": "a.def"}])",
       "actions[0].matrix: expected 16 numbers"},
      {R"([{"do": "drag", "frames": 2}])",
       "actions[0]: needs exactly one of transform, matrix, def"},
      {R"([{"do": "drag", "def": "a.def", "frames": 0}])", "actions[0].frames: expected 1..100000"},
      // 2^32 wrapped to 0 and aborted in the drag path; 2^31 went negative.
      {R"([{"do": "drag", "def": "a.def", "frames": 4294967296}])",
       "actions[0].frames: expected 1..100000"},
      {R"([{"do": "drag", "def": "a.def", "frames": 2147483648}])",
       "actions[0].frames: expected 1..100000"},
      {R"([{"do": "drag", "def": "a.def", "frames": 100001}])",
       "actions[0].frames: expected 1..100000"},
      {R"([{"do": "drag", "def": "a.def", "frames": 18446744073709551615}])",
       "actions[0].frames: expected 1..100000"},
      {R"([{"do": "mouse_drag", "by": [1, 0], "steps": 4294967296}])",
       "actions[0].steps: expected 1..100000"},
      {R"([{"do": "save", "scenario": "s.json", "frames": 100000000}])",
       "actions[0].frames: expected 1..100000"},
      {R"([{"do": "view", "wireframe": "yes"}])", "actions[0].wireframe: expected true or false"},
      {R"([{"do": "lasso", "as": "free", "polygon": [[0, 0], [1, 1]]}])",
       "actions[0].polygon: expected at least 3 points"},
      {R"([{"do": "set", "flag": "method", "value": [1]}])",
       "actions[0].value: expected a string, number or boolean"},
      {R"([{"do": "label", "as": "handle", "group": 64, "region": {}}])",
       "actions[0].group: expected a handle group, an integer in 0..63"},
      {R"([{"do": "mouse_drag", "by": [1, 0], "group": -1}])",
       "actions[0].group: expected a handle group, an integer in 0..63"},
  };
  for (const auto& [text, expected] : cases) {
    Script script;
    std::string error;
    EXPECT_FALSE(Read(text, &script, &error)) << text;
    EXPECT_NE(error.find(expected), std::string::npos) << text << " -> " << error;
    EXPECT_EQ(error.rfind(path_, 0), 0u) << error;  // names the file first
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  Script script;
  std::string error;
  EXPECT_FALSE(ReadScript(folder_ + "/missing.json", &script, &error));
  EXPECT_NE(error.find("missing.json: cannot open"), std::string::npos) << error;
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
