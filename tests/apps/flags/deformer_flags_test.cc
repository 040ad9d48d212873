// The command-line flags of DeformerOptions (apps/flags/deformer_flags.h).

#include "apps/flags/deformer_flags.h"

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gflags/gflags.h>
#include <gtest/gtest.h>

#include "msdeform/scales/deformer_options.h"

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

// DescribeOptions(DeformerOptions()) as the hand-written DescribeOptions of
// 3cb6faf printed it: the report's "options" and the tables' headers.
TEST(DeformerOptionTableTest, DescribeOfTheDefaultsIsUnchanged) {
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"method", "multiscale"},
      {"lattice.cell_width", "0"},
      {"lattice.cells_per_diagonal", "48"},
      {"lattice.max_grid_cells", "268435456"},
      {"lattice.split_cells", "true"},
      {"lattice.piece_margin", "0.5"},
      {"graph.k", "4"},
      {"graph.nodes_per_scale", "100"},
      {"graph.seed", "1"},
      {"graph.extra_rings", "1"},
      {"graph.num_threads", "0"},
      {"rigidity.model", "harmonic"},
      {"rigidity.num_steps", "20"},
      {"rigidity.time_step", "1"},
      {"rigidity.external_stiffness", "0.01"},
      {"rigidity.initial_speed", "0.5"},
      {"rigidity.damping", "0"},
      {"rigidity.region_half_width", "2"},
      {"rigidity.seed", "1"},
      {"rigidity.region_summation", "box"},
      {"rigidity.max_rotation_iterations", "20"},
      {"rigidity.rotation_tolerance", "9.9999999999999995e-07"},
      {"selection.threshold_floor", "0.10000000000000001"},
      {"selection.fixed_extent_cutoff", "0.5"},
      {"selection.member_extent", "max"},
      {"selection.local_detail_distance", "0.10000000000000001"},
      {"selection.omega_max", "4"},
      {"selection.alpha_all_one", "false"},
      {"selection.half_free", "next_to_totally_free"},
      {"selection.border", "totally_free"},
      {"selection.pin_fixed_region", "true"},
      {"static_nodes", "220"},
      {"energy", "ed"},
      {"arap.clusters", "weights"},
      {"arap.num_clusters", "300"},
      {"arap.kmeans_iterations", "8"},
      {"arap.constraints", "exact"},
      {"arap.soft_weight", "1000"},
      {"arap.solver", "local_global"},
      {"arap.anderson_window", "0"},
      {"w_rot", "1"},
      {"w_coh", "10"},
      {"w_con", "100"},
      {"length_unit", "0"},
      {"hold_fixed_vertices", "true"},
      {"keep_left_out_terms", "false"},
      {"fix_fixed_handle_nodes", "false"},
      {"num_threads", "2"},
      {"cached_scales", "4"},
      {"backend", "gauss_newton"},
      {"stopping.max_iterations", "20"},
      {"stopping.function_tolerance", "1e-08"},
      {"stopping.gradient_tolerance", "1e-10"},
      {"stopping.parameter_tolerance", "1e-10"},
      {"initial_guess", "previous"},
      {"gauss_newton.linear_solver", "cholesky"},
      {"gauss_newton.cholesky", "supernodal"},
      {"gauss_newton.factorization", "lagged"},
      {"gauss_newton.refactor_ratio", "0.80000000000000004"},
      {"gauss_newton.damping", "gauss_newton"},
      {"gauss_newton.min_damping", "1.0000000000000001e-09"},
      {"gauss_newton.initial_damping", "0.0001"},
      {"gauss_newton.forcing_term", "0.10000000000000001"},
      {"gauss_newton.max_cg_iterations", "200"},
      {"ceres.trust_region", "levenberg_marquardt"},
      {"ceres.linear_solver", "sparse_normal_cholesky"},
      {"ceres.sparse_library", "eigen_sparse"},
      {"ceres.group_position_terms", "true"},
      {"ceres.jacobians", "analytic"},
  };
  EXPECT_EQ(DescribeOptions(DeformerOptions()), expected);
}

// A value of `row` other than its value in `options`, within its range.
std::string OtherValue(const OptionRow<DeformerOptions>& row, const DeformerOptions& options) {
  const std::string current = row.get(options);
  switch (row.type) {
    case OptionType::kBool:
      return current == "true" ? "false" : "true";
    case OptionType::kEnum:
      for (const std::string& choice : row.choices) {
        if (choice != current) return choice;
      }
      return current;  // a one-value enum (a Ceres with one sparse library)
    case OptionType::kInt: {
      const long long value = std::stoll(current);
      return std::to_string(row.InRange(double(value + 1)) ? value + 1 : value - 1);
    }
    default: {
      const double value = std::stod(current);
      return OptionNumberText(row.InRange(value + 0.25) ? value + 0.25 : value / 2);
    }
  }
}

// Every row sets its own field: changing one row's value changes that entry
// of the description and no other, and the struct is not the default.
TEST(DeformerOptionTableTest, EveryRowIsItsOwnField) {
  const OptionTable<DeformerOptions>& table = DeformerOptionTable();
  const auto defaults = DescribeOptions(DeformerOptions());
  ASSERT_EQ(table.rows().size(), defaults.size());
  std::set<std::string> names;
  int changed_rows = 0;
  for (size_t i = 0; i < table.rows().size(); ++i) {
    const auto& row = table.rows()[i];
    EXPECT_TRUE(names.insert(row.name).second) << row.name << " declared twice";
    const std::string value = OtherValue(row, DeformerOptions());
    if (value == defaults[i].second) continue;
    DeformerOptions options;
    std::string error;
    ASSERT_TRUE(table.Set(row.name, value, &options, &error)) << error;
    const auto described = DescribeOptions(options);
    for (size_t j = 0; j < described.size(); ++j) {
      if (j == i) {
        EXPECT_EQ(described[j].second, value) << row.name;
      } else {
        EXPECT_EQ(described[j], defaults[j]) << "setting " << row.name;
      }
    }
    ++changed_rows;
  }
  EXPECT_GE(changed_rows, static_cast<int>(defaults.size()) - 1);
}

// Describe, then set every row from the description: the same options.
TEST(DeformerOptionTableTest, DescribeThenSetRoundTrips) {
  const OptionTable<DeformerOptions>& table = DeformerOptionTable();
  DeformerOptions changed;
  std::string error;
  for (const auto& row : table.rows()) {
    ASSERT_TRUE(table.Set(row.name, OtherValue(row, changed), &changed, &error)) << error;
  }
  changed.w_rot = 0.1;  // a number that %.17g must carry exactly
  DeformerOptions rebuilt;
  for (const auto& [name, value] : DescribeOptions(changed)) {
    ASSERT_TRUE(table.Set(name, value, &rebuilt, &error)) << error;
  }
  EXPECT_EQ(DescribeOptions(rebuilt), DescribeOptions(changed));
  EXPECT_EQ(rebuilt.w_rot, 0.1);
}

TEST(DeformerOptionTableTest, RangeErrorsAreOneLineNamingTheOption) {
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(DeformerOptionTable().Set("w_con", "0", &options, &error));
  EXPECT_EQ(error, "w_con=0: expected a finite weight > 0 (at 0 the handle would not follow its "
                   "target)");
  EXPECT_FALSE(DeformerOptionTable().Set("rigidity.damping", "1", &options, &error));
  EXPECT_EQ(error, "rigidity.damping=1: expected a number in [0, 1)");
  EXPECT_FALSE(DeformerOptionTable().Set("backend", "newton", &options, &error));
  EXPECT_EQ(error, "backend=newton: expected gauss_newton or ceres");
  EXPECT_EQ(error.find('\n'), std::string::npos);
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("w_con", "-0.1").empty());
  EXPECT_FALSE(DeformerOptionsFromFlags(&options, &error));
  EXPECT_EQ(error, "--w_con=-0.1: expected a finite weight > 0 (at 0 the handle would not "
                   "follow its target)");
}

// The subspace ARAP energy's options under another energy would be silently
// unused: Check refuses the first changed one; WithEnergy, for one set of
// options run under several energies, puts them back for the others.
TEST(DeformerOptionTableTest, ArapOptionsUnderAnotherEnergyAreRefused) {
  DeformerOptions options;
  options.energy = Energy::kArap;
  options.arap.clusters = RotationClusters::kVertices;
  options.arap.soft_weight = 50.0;
  std::string error;
  EXPECT_TRUE(options.Check(&error)) << error;
  DeformerOptions ed = options;
  ed.energy = Energy::kEd;
  EXPECT_FALSE(ed.Check(&error));
  EXPECT_EQ(error, "arap.clusters=vertices: read only by energy=arap (energy=ed)");
  ed.arap.clusters = ArapOptions().clusters;
  EXPECT_FALSE(ed.Check(&error));
  EXPECT_EQ(error, "arap.soft_weight=50: read only by energy=arap (energy=ed)");
  const DeformerOptions rows = WithEnergy(options, Energy::kEd);
  EXPECT_EQ(rows.energy, Energy::kEd);
  EXPECT_TRUE(rows.Check(&error)) << error;
  EXPECT_EQ(WithEnergy(options, Energy::kArap).arap.clusters, RotationClusters::kVertices);
}

// arap.anderson_window accelerates the subspace local/global iteration only;
// under any other solve a window would be ignored, so Check refuses it.
TEST(DeformerOptionTableTest, AndersonWindowOutsideLocalGlobalIsRefused) {
  DeformerOptions options;
  options.energy = Energy::kArap;
  options.arap.anderson_window = 5;
  std::string error;
  EXPECT_TRUE(options.Check(&error)) << error;
  const std::string refused =
      "arap.anderson_window=5: read only by energy=arap with backend=gauss_newton and "
      "arap.solver=local_global (0 turns it off)";
  DeformerOptions ed = options;
  ed.energy = Energy::kEd;
  EXPECT_FALSE(ed.Check(&error));
  EXPECT_EQ(error, refused);
  DeformerOptions ceres = options;
  ceres.backend = Solver::kCeres;
  EXPECT_FALSE(ceres.Check(&error));
  EXPECT_EQ(error, refused);
  DeformerOptions gauss_newton = options;
  gauss_newton.arap.solver = ArapSolver::kGaussNewton;
  EXPECT_FALSE(gauss_newton.Check(&error));
  EXPECT_EQ(error, refused);
  gauss_newton.arap.anderson_window = 0;
  EXPECT_TRUE(gauss_newton.Check(&error)) << error;
}

// The command line's spellings before the table keep working, each setting
// the row it is an alias of; the one spelling (the struct's) works too.
TEST(DeformerFlagsTest, OldAndNewSpellingsParse) {
  const OptionTable<DeformerOptions>& table = DeformerOptionTable();
  for (const auto& row : table.rows()) {
    std::vector<std::string> spellings = row.aliases;
    if (!row.topic.empty() && row.name.find('.') == std::string::npos) {
      spellings.push_back(row.name);
    }
    for (const std::string& spelling : spellings) {
      gflags::FlagSaver saver;
      const std::string value = OtherValue(row, DeformerOptions());
      if (value == row.get(DeformerOptions())) continue;
      ASSERT_FALSE(gflags::SetCommandLineOption(spelling.c_str(), value.c_str()).empty())
          << "--" << spelling;
      // The arap.* options are read only under --energy=arap (Check refuses
      // them otherwise).
      if (row.name.rfind("arap.", 0) == 0) {
        ASSERT_FALSE(gflags::SetCommandLineOption("energy", "arap").empty());
      }
      DeformerOptions options;
      std::string error;
      ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
      EXPECT_EQ(row.get(options), value) << "--" << spelling;
    }
  }
}

TEST(DeformerFlagsTest, SolverAndBackendAreOneOption) {
  for (const char* spelling : {"solver", "backend"}) {
    gflags::FlagSaver saver;
    ASSERT_FALSE(gflags::SetCommandLineOption(spelling, "ceres").empty()) << spelling;
    DeformerOptions options;
    std::string error;
    ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
    EXPECT_EQ(options.backend, Solver::kCeres) << spelling;
  }
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("solver", "ceres").empty());
  ASSERT_FALSE(gflags::SetCommandLineOption("backend", "gauss_newton").empty());
  DeformerOptions options;
  std::string error;
  EXPECT_FALSE(DeformerOptionsFromFlags(&options, &error));
  EXPECT_EQ(error, "--backend=gauss_newton and --solver=ceres: one option (backend), given twice");
}

// A value not of its flag's type is one line in the tables' words, before
// gflags parses argv (which would print its own "ERROR: illegal value").
TEST(DeformerFlagsTest, ValuesNotOfTheFlagsTypeAreOneLine) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--w_con=abc"}, "--w_con=abc: expected a number"},
      {{"--w_con="}, "--w_con=: expected a number"},
      {{"-w_con", "abc"}, "--w_con=abc: expected a number"},
      {{"--max_iterations=2.5"}, "--max_iterations=2.5: expected an integer"},
      {{"--threads=99999999999"}, "--threads=99999999999: expected an integer"},
      {{"--split_cells=maybe"}, "--split_cells=maybe: expected true or false"},
      {{"--seed=-1"}, "--seed=-1: expected an integer >= 0"},
  };
  for (const auto& [args, expected] : cases) {
    std::vector<std::string> words = {"msdeform"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    std::string error;
    EXPECT_FALSE(CheckFlagValues(static_cast<int>(argv.size()), argv.data(), &error)) << expected;
    EXPECT_EQ(error, expected);
  }
  // What gflags takes passes: its spellings of a bool, a bare bool, numbers.
  std::vector<std::string> good = {"msdeform", "--w_con=1e3", "--split_cells=YES", "--nosplit_cells",
                                   "--alpha_all_one", "--threads", "3", "--unknown=x", "--",
                                   "--w_con=abc"};
  std::vector<char*> argv;
  for (std::string& word : good) argv.push_back(word.data());
  std::string error;
  EXPECT_TRUE(CheckFlagValues(static_cast<int>(argv.size()), argv.data(), &error)) << error;
}

// The rows of the flags given, each once with the spelling given; none when
// every flag is at its default.
TEST(DeformerFlagsTest, GivenFlagRowsAreThoseSet) {
  EXPECT_TRUE(GivenFlagRows().empty());
  gflags::FlagSaver saver;
  ASSERT_FALSE(gflags::SetCommandLineOption("solver", "ceres").empty());
  ASSERT_FALSE(gflags::SetCommandLineOption("w_con", "5").empty());
  const std::vector<FlagValue> given = GivenFlagRows();
  ASSERT_EQ(given.size(), 2u);
  std::map<std::string, std::pair<std::string, std::string>> by_row;
  for (const FlagValue& value : given) by_row[value.row] = {value.spelling, value.text};
  EXPECT_EQ(by_row["backend"], std::make_pair(std::string("solver"), std::string("ceres")));
  EXPECT_EQ(by_row["w_con"], std::make_pair(std::string("w_con"), std::string("5")));
}

// A report records every flag and --rerun sets them all: the spellings of
// one option record the value it took, so the rerun builds the same options.
TEST(DeformerFlagsTest, RecordedFlagsRebuildTheOptions) {
  DeformerOptions first;
  std::vector<std::pair<std::string, std::string>> recorded;
  {
    gflags::FlagSaver saver;
    ASSERT_FALSE(gflags::SetCommandLineOption("threads", "1").empty());
    ASSERT_FALSE(gflags::SetCommandLineOption("solver", "ceres").empty());
    std::string error;
    ASSERT_TRUE(DeformerOptionsFromFlags(&first, &error)) << error;
    recorded = ProgramFlagValues();
  }
  std::map<std::string, std::string> by_name(recorded.begin(), recorded.end());
  EXPECT_EQ(by_name["num_threads"], "1");
  EXPECT_EQ(by_name["backend"], "ceres");
  gflags::FlagSaver saver;
  for (const auto& [name, value] : recorded) {
    ASSERT_FALSE(gflags::SetCommandLineOption(name.c_str(), value.c_str()).empty()) << name;
  }
  DeformerOptions rerun;
  std::string error;
  ASSERT_TRUE(DeformerOptionsFromFlags(&rerun, &error)) << error;
  EXPECT_EQ(DescribeOptions(rerun), DescribeOptions(first));
}

}  // namespace
}  // namespace msdeform
