// Replays saved fuzzer inputs through the fuzz target bodies in the normal
// test suite (and so under the sanitizer build of scripts/run_tests.sh):
// every crash the fuzzers found is kept in tests/data/fuzz/<target>/, and the
// bad-input corpus tests/data/bad/ is fed to the parser of its extension too.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/fuzz/fuzz_targets.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// Runs `target` on every file of tests/data/fuzz/<name>/ and on every file of
// tests/data/bad/ whose extension is one of `extensions`. Returns the count.
template <typename Target>
int Replay(const std::string& name, const std::vector<std::string>& extensions, Target target) {
  int count = 0;
  const fs::path saved = fs::path(MSDEFORM_TEST_DATA_DIR) / "fuzz" / name;
  if (fs::is_directory(saved)) {
    for (const auto& entry : fs::directory_iterator(saved)) {
      if (!entry.is_regular_file()) continue;
      SCOPED_TRACE(entry.path().string());
      const std::vector<uint8_t> bytes = ReadBytes(entry.path());
      target(bytes.data(), bytes.size());
      ++count;
    }
  }
  for (const auto& entry : fs::directory_iterator(fs::path(MSDEFORM_TEST_DATA_DIR) / "bad")) {
    if (!entry.is_regular_file()) continue;
    const std::string extension = entry.path().extension().string();
    if (std::find(extensions.begin(), extensions.end(), extension) == extensions.end()) continue;
    SCOPED_TRACE(entry.path().string());
    const std::vector<uint8_t> bytes = ReadBytes(entry.path());
    target(bytes.data(), bytes.size());
    ++count;
  }
  return count;
}

TEST(FuzzRegressionTest, Sel) {
  EXPECT_GT(Replay("sel", {".sel"}, fuzz::FuzzSel), 0);
}

TEST(FuzzRegressionTest, Def) {
  EXPECT_GT(Replay("def", {".def"}, fuzz::FuzzDef), 0);
}

TEST(FuzzRegressionTest, Scenario) {
  EXPECT_GT(Replay("scenario", {".json"}, fuzz::FuzzScenario), 0);
}

// The mesh readers: saved inputs of tests/data/fuzz/<extension>/ and the
// corpus files with that extension.
void ReplayMeshes(const std::string& extension) {
  const std::string dotted = "." + extension;
  EXPECT_GT(Replay(extension, {dotted},
                   [&](const uint8_t* data, size_t size) { fuzz::FuzzMesh(data, size, dotted); }),
            0);
}

TEST(FuzzRegressionTest, Off) { ReplayMeshes("off"); }
TEST(FuzzRegressionTest, Obj) { ReplayMeshes("obj"); }
TEST(FuzzRegressionTest, Ply) { ReplayMeshes("ply"); }
TEST(FuzzRegressionTest, Stl) { ReplayMeshes("stl"); }

}  // namespace
}  // namespace msdeform
