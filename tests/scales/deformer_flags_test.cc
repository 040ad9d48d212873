// The command-line flags of DeformerOptions (scales/deformer_flags.h).

#include "msdeform/scales/deformer_flags.h"

#include <string>

#include <gflags/gflags.h>
#include <gtest/gtest.h>

#include "msdeform/scales/deformer.h"

namespace msdeform {
namespace {

// The one --threads bounds every threaded stage: the graph building (nearest
// nodes, the per-scale connection) as well as the skinning and Ceres.
TEST(DeformerFlagsTest, ThreadsReachesTheGraphBuilding) {
  gflags::FlagSaver saver;
  for (const char* threads : {"1", "3"}) {
    ASSERT_FALSE(gflags::SetCommandLineOption("threads", threads).empty());
    DeformerOptions options;
    std::string error;
    ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
    EXPECT_EQ(options.num_threads, std::stoi(threads));
    EXPECT_EQ(options.graph.num_threads, std::stoi(threads));
  }
}

// Without --threads the options are DeformerOptions()'s: the graph building
// keeps GraphOptions's default.
TEST(DeformerFlagsTest, NoThreadsFlagKeepsTheGraphDefault) {
  DeformerOptions options;
  std::string error;
  ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
  EXPECT_EQ(options.num_threads, DeformerOptions().num_threads);
  EXPECT_EQ(options.graph.num_threads, GraphOptions().num_threads);
}

TEST(DeformerFlagsTest, BadThreadsNamesTheFlag) {
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("threads", "0").empty());
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(DeformerOptionsFromFlags(&options, &error));
  EXPECT_EQ(error, "--threads=0: expected an integer in 1..1024");
}

// The two promises' switches reach the options; the paper's settings are
// their "false".
TEST(DeformerFlagsTest, PromiseSwitchesReachTheOptions) {
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("pin_fixed_region", "false").empty());
  ASSERT_FALSE(gflags::SetCommandLineOption("split_cells", "false").empty());
  ASSERT_FALSE(gflags::SetCommandLineOption("piece_margin", "1.25").empty());
  DeformerOptions options;
  std::string error;
  ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
  EXPECT_FALSE(options.selection.pin_fixed_region);
  EXPECT_FALSE(options.lattice.split_cells);
  EXPECT_EQ(options.lattice.piece_margin, 1.25);
  EXPECT_TRUE(DeformerOptions().selection.pin_fixed_region);
  EXPECT_TRUE(DeformerOptions().lattice.split_cells);
  EXPECT_FALSE(PaperProcedure(DeformerOptions()).selection.pin_fixed_region);
  EXPECT_FALSE(PaperProcedure(DeformerOptions()).lattice.split_cells);
}

TEST(DeformerFlagsTest, BadPieceMarginNamesTheFlag) {
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("piece_margin", "3").empty());
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(DeformerOptionsFromFlags(&options, &error));
  EXPECT_EQ(error, "--piece_margin=3: expected a number of cell widths in [0, 2]");
}

}  // namespace
}  // namespace msdeform
