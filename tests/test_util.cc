#include "tests/test_util.h"

#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

// The folders FreshFolder made that RemoveFreshFolders has not handled yet.
std::vector<std::string>& FreshFolders() {
  static std::vector<std::string> folders;
  return folders;
}

}  // namespace

std::string FreshFolder() {
  const testing::TestInfo* test = testing::UnitTest::GetInstance()->current_test_info();
  std::string name = test != nullptr ? test->test_suite_name() : "msdeform_test";
  for (char& c : name) {
    if (c == '/') c = '_';  // parameterised suites are named "Prefix/Suite"
  }
  std::string pattern = testing::TempDir() + "/" + name + "_XXXXXX";
  const bool made = ::mkdtemp(pattern.data()) != nullptr;
  EXPECT_TRUE(made) << pattern;
  if (made) FreshFolders().push_back(pattern);
  return pattern;
}

void RemoveFreshFolders(bool keep) {
  for (const std::string& folder : FreshFolders()) {
    if (keep) {
      std::printf("test_util: kept %s (the test failed)\n", folder.c_str());
      continue;
    }
    std::error_code error;
    std::filesystem::remove_all(folder, error);
    if (error) std::printf("test_util: cannot remove %s: %s\n", folder.c_str(), error.message().c_str());
  }
  FreshFolders().clear();
}

std::string WriteText(const std::string& path, const std::string& text) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!parent.empty()) std::filesystem::create_directories(parent, error);
  EXPECT_FALSE(error) << parent << ": " << error.message();
  std::ofstream out(path, std::ios::binary);
  out << text;
  EXPECT_TRUE(out.good()) << path;
  return path;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Eigen::Affine3d Lift(double z) {
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 0.0, z;
  return lift;
}

}  // namespace msdeform
