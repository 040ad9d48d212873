// The shared test helpers' own contract (tests/test_util.h): FreshFolder's
// folders are removed by RemoveFreshFolders (as test_main.cc does after a
// passing test, contents and all) or kept when asked (after a failing one).

#include "tests/test_util.h"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

TEST(FreshFolderTest, RemovedWithItsContentsUnlessKept) {
  const std::string removed = FreshFolder();
  ASSERT_TRUE(std::filesystem::is_directory(removed)) << removed;
  EXPECT_TRUE(std::filesystem::is_empty(removed)) << removed;
  WriteText(removed + "/sub/file.txt", "text");
  RemoveFreshFolders(/*keep=*/false);
  EXPECT_FALSE(std::filesystem::exists(removed)) << removed;

  const std::string kept = FreshFolder();
  EXPECT_NE(kept, removed);
  RemoveFreshFolders(/*keep=*/true);
  EXPECT_TRUE(std::filesystem::is_directory(kept)) << kept;
  std::filesystem::remove_all(kept);
}

}  // namespace
}  // namespace msdeform
