// The one test main: initialises glog and gflags, and seeds the C library's
// random generator so that a test using it is reproducible. Tests that need
// randomness should still take an explicit seed (std::mt19937 with a constant).
#include <cstdlib>

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  std::srand(20080101);
  return RUN_ALL_TESTS();
}
