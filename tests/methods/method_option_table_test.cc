// MethodOptionTable(): the one table of every method's options. Each of the
// methods' own rows sets its field, keeps the command line's spelling as an
// alias, and refuses a value out of its range in one line naming it.

#include "msdeform/methods/method_option_table.h"

#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/solvers/local_global_arap.h"

namespace msdeform {
namespace {

TEST(MethodOptionTableTest, EachMethodRowSetsItsField) {
  const OptionTable<MethodOptions>& table = MethodOptionTable();
  MethodOptions options;
  std::string error;
  ASSERT_TRUE(table.Set("cgal.iterations", "7", &options, &error)) << error;
  ASSERT_TRUE(table.Set("cgal.tolerance", "0.25", &options, &error)) << error;
  ASSERT_TRUE(table.Set("cgal.sre_alpha", "0.5", &options, &error)) << error;
  ASSERT_TRUE(table.Set("fastlsm.steps_per_frame", "33", &options, &error)) << error;
  ASSERT_TRUE(table.Set("fastlsm.region_half_width", "3", &options, &error)) << error;
  ASSERT_TRUE(table.Set("fastlsm.damping", "0.75", &options, &error)) << error;
  EXPECT_EQ(options.cgal.iterations, 7);
  EXPECT_EQ(options.cgal.tolerance, 0.25);
  EXPECT_EQ(options.cgal.sre_alpha, 0.5);
  EXPECT_EQ(options.fastlsm.steps_per_frame, 33);
  EXPECT_EQ(options.fastlsm.region_half_width, 3);
  EXPECT_EQ(options.fastlsm.damping, 0.75);
  // The Deformer's rows keep their names (no prefix) and set options.deformer.
  ASSERT_TRUE(table.Set("w_con", "123", &options, &error)) << error;
  EXPECT_EQ(options.deformer.w_con, 123.0);
}

TEST(MethodOptionTableTest, CommandLineSpellingsAreAliases) {
  const OptionTable<MethodOptions>& table = MethodOptionTable();
  MethodOptions options;
  std::string error;
  ASSERT_TRUE(table.Set("cgal_iterations", "9", &options, &error)) << error;
  ASSERT_TRUE(table.Set("fastlsm_steps", "11", &options, &error)) << error;
  ASSERT_TRUE(table.Set("fastlsm_damping", "0.5", &options, &error)) << error;
  EXPECT_EQ(options.cgal.iterations, 9);
  EXPECT_EQ(options.fastlsm.steps_per_frame, 11);
  EXPECT_EQ(options.fastlsm.damping, 0.5);
  EXPECT_EQ(table.Find("fastlsm_steps")->topic, "method");
}

TEST(MethodOptionTableTest, OutOfRangeIsOneLineNamingTheOption) {
  const OptionTable<MethodOptions>& table = MethodOptionTable();
  MethodOptions options;
  std::string error;
  EXPECT_FALSE(table.Set("fastlsm_steps", "0", &options, &error, "--fastlsm_steps"));
  EXPECT_EQ(error, "--fastlsm_steps=0: expected an integer in 1..100000");
  EXPECT_FALSE(table.Set("fastlsm.damping", "1", &options, &error));
  EXPECT_EQ(error, "fastlsm.damping=1: expected a number in [0, 1)");
  EXPECT_FALSE(table.Set("fastlsm.region_half_width", "9", &options, &error));
  EXPECT_EQ(error, "fastlsm.region_half_width=9: expected an integer in 1..8");
  EXPECT_FALSE(table.Set("cgal.iterations", "0", &options, &error));
  EXPECT_EQ(error, "cgal.iterations=0: expected an integer >= 1");
  EXPECT_FALSE(table.Set("cgal.sre_alpha", "-1", &options, &error));
  EXPECT_EQ(error, "cgal.sre_alpha=-1: expected a finite number >= 0");
  // Nothing was changed by the refused values.
  EXPECT_EQ(options.fastlsm.steps_per_frame, FastLsmOptions().steps_per_frame);
  EXPECT_EQ(options.cgal.iterations, CgalArapOptions().iterations);
  // Check() is the table's ranges, named as the table names the row.
  options.cgal.tolerance = -1;
  EXPECT_FALSE(options.cgal.Check(&error));
  EXPECT_EQ(error, "cgal.tolerance=-1: expected a finite number >= 0");
}

TEST(MethodOptionTableTest, DefaultsAreTheStructs) {
  const MethodOptions defaults;
  std::string error;
  EXPECT_TRUE(MethodOptionTable().CheckRanges(defaults, &error)) << error;
  const auto fields = MethodOptionTable().Describe(defaults);
  // The Deformer's rows, then each method's own in registration order: the
  // project's are these; a method registered later adds its rows after them.
  const std::vector<std::string> kProjectMethodRows = {
      "cgal.iterations",         "cgal.tolerance",
      "cgal.sre_alpha",          "fastlsm.steps_per_frame",
      "fastlsm.region_half_width", "fastlsm.damping",
      "full_arap.relative_tolerance", "full_arap.max_iterations",
      "full_arap.anderson_window",    "full_arap.factorization"};
  const size_t deformer_rows = DeformerOptionTable().rows().size();
  ASSERT_GE(fields.size(), deformer_rows + kProjectMethodRows.size());
  for (size_t i = 0; i < kProjectMethodRows.size(); ++i) {
    EXPECT_EQ(fields[deformer_rows + i].first, kProjectMethodRows[i]);
  }
  std::map<std::string, std::string> values(fields.begin(), fields.end());
  EXPECT_EQ(values["fastlsm.damping"], "0.10000000000000001");
  EXPECT_EQ(values["full_arap.anderson_window"], "5");
  EXPECT_EQ(values["full_arap.relative_tolerance"], "1.0000000000000001e-09");
  EXPECT_EQ(values["full_arap.factorization"], "auto");
}

// A method whose options struct is in its own files (full_arap's
// LocalGlobalArapOptions): its rows set options.own under their prefix, a copy
// of the options is deep, and a struct never set reads as its defaults.
TEST(MethodOptionTableTest, OwnRowsSetTheStructKeptByPrefix) {
  const OptionTable<MethodOptions>& table = MethodOptionTable();
  MethodOptions options;
  EXPECT_EQ(options.own.Get<LocalGlobalArapOptions>("full_arap").max_iterations,
            LocalGlobalArapOptions().max_iterations);
  std::string error;
  ASSERT_TRUE(table.Set("full_arap_max_iterations", "12", &options, &error)) << error;
  ASSERT_TRUE(table.Set("full_arap.anderson_window", "0", &options, &error)) << error;
  const MethodOptions copy = options;
  options.own.Mutable<LocalGlobalArapOptions>("full_arap")->max_iterations = 13;
  EXPECT_EQ(copy.own.Get<LocalGlobalArapOptions>("full_arap").max_iterations, 12);
  EXPECT_EQ(copy.own.Get<LocalGlobalArapOptions>("full_arap").anderson_window, 0);
  EXPECT_EQ(options.own.Get<LocalGlobalArapOptions>("full_arap").max_iterations, 13);
  EXPECT_FALSE(table.Set("full_arap.max_iterations", "0", &options, &error));
  EXPECT_EQ(error, "full_arap.max_iterations=0: expected an integer in 1..10000000");
  options.own.Mutable<LocalGlobalArapOptions>("full_arap")->relative_tolerance = 2.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "full_arap.relative_tolerance=2: expected a number in [0, 1]");
}

// MethodOptions::Check reads every row's range: a C++ caller gets the
// command line's words, named by the row.
TEST(MethodOptionTableTest, CheckReadsTheRowsRanges) {
  std::string error;
  EXPECT_TRUE(MethodOptions().Check(&error)) << error;
  MethodOptions options;
  options.cgal.iterations = 0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "cgal.iterations=0: expected an integer >= 1");
  options = MethodOptions();
  options.fastlsm.damping = 1.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "fastlsm.damping=1: expected a number in [0, 1)");
  options = MethodOptions();
  options.deformer.rigidity.time_step = 0.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "rigidity.time_step=0: expected a finite number > 0");
  options = MethodOptions();
  options.deformer.selection.fixed_extent_cutoff = 0.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "selection.fixed_extent_cutoff=0: expected a number in (0, 1]");
  // What a row cannot say is still checked: k_ext h^2 <= 1.
  options = MethodOptions();
  options.deformer.rigidity.external_stiffness = 2.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "external_stiffness * time_step^2 (k_ext h^2) must be <= 1 for a stable step");
}

}  // namespace
}  // namespace msdeform
