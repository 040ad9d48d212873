// The one test main: initialises glog and gflags, seeds the C library's
// random generator so that a test using it is reproducible (tests that need
// randomness should still take an explicit seed, std::mt19937 with a
// constant), and removes the folders a passing test made (FreshFolder).
#include <cstdlib>

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace {

// Removes the folders each test made with FreshFolder when it passed; keeps
// (and names) those of a failed test, and at the end those made outside a
// test if any test failed.
class FreshFolderCleanup : public testing::EmptyTestEventListener {
 public:
  void OnTestEnd(const testing::TestInfo& test) override {
    msdeform::RemoveFreshFolders(/*keep=*/test.result()->Failed());
  }
  void OnTestProgramEnd(const testing::UnitTest& unit_test) override {
    msdeform::RemoveFreshFolders(/*keep=*/unit_test.Failed());
  }
};

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  std::srand(20080101);
  testing::UnitTest::GetInstance()->listeners().Append(new FreshFolderCleanup);
  return RUN_ALL_TESTS();
}
