// Runs the quick solver lab (as `msdeform_experiments --solver_lab --quick`
// does: the cactus, 5 frames, budgets 1, 3 and converged, every variant) into
// a temporary folder and checks what must hold whatever the timings: every
// row is there, runs at the "converged" budget with exact steps reach the
// reference's minimum, no run goes below it, the budget caps the iterations,
// and the traces start at the frame's initial cost and never go up. A direct
// drag per variant checks the reported costs against EvaluateEnergy.

#include "experiments/solver_lab.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "experiments/experiment_scenario.h"
#include "experiments/tables.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

constexpr int kQuickFrames = 5;
const std::vector<std::string> kQuickBudgets = {"1", "3", "converged"};

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  int Column(const std::string& name) const {
    for (size_t c = 0; c < columns.size(); ++c)
      if (columns[c] == name) return static_cast<int>(c);
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
  const std::string& Cell(const std::vector<std::string>& row, const std::string& name) const {
    return row[Column(name)];
  }
  double Number(const std::vector<std::string>& row, const std::string& name) const {
    const std::string& cell = Cell(row, name);
    char* end = nullptr;
    const double value = std::strtod(cell.c_str(), &end);
    EXPECT_FALSE(cell.empty()) << name;
    EXPECT_EQ(*end, '\0') << name << ": '" << cell << "'";
    return value;
  }
};

std::string CactusEntry() {
  return std::string(MSDEFORM_SOURCE_DIR) + "/experiments/scenarios/cactus.json";
}

// The variant's options with the default energy settings, 1 thread.
DeformerOptions Options(const SolverVariant& variant, int budget) {
  DeformerOptions base;
  base.num_threads = 1;
  return VariantOptions(base, variant, budget);
}

class SolverLabTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(std::string(MSDEFORM_DATA_DIR) + "/meshes/cactus.off")) {
      error_ = "real meshes missing: run data/fetch_meshes.sh";  // every test fails
      return;
    }
    out_dir_ = new std::string((fs::temp_directory_path() / "msdeform_solver_lab").string());
    fs::remove_all(*out_dir_);
    SolverLabOptions options;
    options.scenario_dir = std::string(MSDEFORM_SOURCE_DIR) + "/experiments/scenarios";
    options.out_dir = *out_dir_;
    options.quick = true;
    ok_ = RunSolverLab(options, &error_);
    if (!ok_) return;
    solvers_ = new CsvTable;
    traces_ = new CsvTable;
    ok_ =
        ReadTableCsv(*out_dir_ + "/solvers.csv", &solvers_->columns, &solvers_->rows, &error_) &&
        ReadTableCsv(*out_dir_ + "/solver_traces.csv", &traces_->columns, &traces_->rows, &error_);
  }
  static void TearDownTestSuite() {
    if (out_dir_ != nullptr) fs::remove_all(*out_dir_);
    delete out_dir_;
    delete solvers_;
    delete traces_;
    out_dir_ = nullptr;
    solvers_ = traces_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(ok_) << error_;
  }

  static std::string* out_dir_;
  static bool ok_;
  static std::string error_;
  static CsvTable* solvers_;
  static CsvTable* traces_;
};

std::string* SolverLabTest::out_dir_ = nullptr;
bool SolverLabTest::ok_ = false;
std::string SolverLabTest::error_;
CsvTable* SolverLabTest::solvers_ = nullptr;
CsvTable* SolverLabTest::traces_ = nullptr;

TEST(SolverVariantsTest, NamesAreUniqueAndOnlyTheSolverDiffers) {
  const std::vector<SolverVariant> variants = SolverVariants();
  std::set<std::string> names;
  for (const SolverVariant& variant : variants) names.insert(variant.name);
  EXPECT_EQ(names.size(), variants.size());
  for (const char* name :
       {"gn_lagged", "gn_exact", "gn_per_frame", "gn_lm", "gn_pcg_jacobi", "gn_pcg_ichol",
        "gn_eigen_llt", "gn_ldlt", "gn_cholmod", "gn_cold", "gn_extrapolated", "gn_refactor_025",
        "ceres_lm_eigen_sparse", "ceres_dogleg_eigen_sparse", "ceres_cgnr", "ceres_lm_per_vertex",
        "ceres_lm_autodiff", "arap_local_global"}) {
    EXPECT_TRUE(names.count(name)) << name;
  }
  // Each variant runs its own energy, whatever the base's: the arap_*
  // variants the subspace ARAP energy, the others Eq. 17.
  DeformerOptions arap_base;
  arap_base.energy = Energy::kArap;
  for (const SolverVariant& variant : variants) {
    const Energy expected = variant.name.rfind("arap_", 0) == 0 ? Energy::kArap : Energy::kEd;
    EXPECT_EQ(variant.energy, expected) << variant.name;
    EXPECT_EQ(VariantOptions(DeformerOptions(), variant, 3).energy, expected) << variant.name;
    EXPECT_EQ(VariantOptions(arap_base, variant, 3).energy, expected) << variant.name;
  }
  // gn_lagged is the default options; every variant keeps the energy and the
  // budget's stopping rule.
  DeformerOptions base;
  base.w_con = 1e3;
  const DeformerOptions lagged = VariantOptions(base, variants[0], 3);
  EXPECT_EQ(variants[0].name, "gn_lagged");
  EXPECT_EQ(DescribeSolver(lagged), DescribeSolver(DeformerOptions()));
  for (const SolverVariant& variant : variants) {
    for (int budget : {1, 3, kConvergedBudget}) {
      const DeformerOptions options = VariantOptions(base, variant, budget);
      EXPECT_EQ(options.w_con, 1e3) << variant.name;
      EXPECT_EQ(options.stopping.max_iterations,
                budget == kConvergedBudget ? kConvergedMaxIterations : budget);
      EXPECT_EQ(options.stopping.function_tolerance, StoppingRule().function_tolerance);
      EXPECT_EQ(options.stopping.gradient_tolerance, StoppingRule().gradient_tolerance);
      EXPECT_EQ(options.stopping.parameter_tolerance, StoppingRule().parameter_tolerance);
      std::string error;
      EXPECT_TRUE(options.Check(&error)) << variant.name << ": " << error;
    }
  }
}

TEST_F(SolverLabTest, EveryVariantAndBudgetHasACleanRow) {
  const CsvTable& table = *solvers_;
  std::set<std::pair<std::string, std::string>> seen;
  for (const auto& row : table.rows) {
    EXPECT_EQ(table.Cell(row, "scenario"), "cactus");
    EXPECT_TRUE(seen.insert({table.Cell(row, "variant"), table.Cell(row, "budget")}).second)
        << "repeated row " << table.Cell(row, "variant") << " " << table.Cell(row, "budget");
    for (const char* column :
         {"vertices", "variables", "frame_ms", "solve_ms", "skin_ms", "ms_per_iteration",
          "iterations", "iterations_total", "factorizations", "energy_gap", "energy_gap_max",
          "energy_gap_last", "energy_gap_min", "cost_error", "handle_rms_rel"}) {
      EXPECT_TRUE(std::isfinite(table.Number(row, column))) << column;
    }
    EXPECT_FALSE(table.Cell(row, "description").empty());
    // The backends' reported costs are Eq. 17 to rounding on the cactus.
    EXPECT_LE(table.Number(row, "cost_error"), 1e-9) << table.Cell(row, "variant");
    // The cactus drag never fails.
    EXPECT_EQ(table.Number(row, "failed_frames"), 0.0) << table.Cell(row, "variant");
    EXPECT_EQ(table.Number(row, "nonfinite_frames"), 0.0) << table.Cell(row, "variant");
  }
  for (const SolverVariant& variant : SolverVariants()) {
    for (const std::string& budget : kQuickBudgets) {
      EXPECT_TRUE(seen.count({variant.name, budget})) << variant.name << " " << budget;
    }
  }
  EXPECT_EQ(table.rows.size(), SolverVariants().size() * kQuickBudgets.size());
  EXPECT_TRUE(fs::exists(*out_dir_ + "/solvers.md"));
}

TEST_F(SolverLabTest, ConvergedRunsWithExactStepsReachTheReferenceMinimum) {
  const CsvTable& table = *solvers_;
  std::map<std::string, SolverVariant> variants;
  for (const SolverVariant& variant : SolverVariants()) variants[variant.name] = variant;
  int exact = 0;
  for (const auto& row : table.rows) {
    if (table.Cell(row, "budget") != "converged") continue;
    const std::string& name = table.Cell(row, "variant");
    // The subspace ARAP energy's local/global solver converges linearly: its
    // 200 iterations a frame stop short of the reference
    // (ArapVariantIsMeasuredOnItsOwnEnergy).
    if (table.Cell(row, "energy") == "arap") continue;
    ASSERT_TRUE(variants.count(name)) << name;
    const double gap_max = table.Number(row, "energy_gap_max");
    if (HasExactSteps(Options(variants[name], kConvergedBudget))) {
      // Same minimum as the reference, to the default tolerances.
      EXPECT_LE(std::abs(gap_max), 1e-6) << name;
      EXPECT_LE(std::abs(table.Number(row, "energy_gap_last")), 1e-6) << name;
      ++exact;
    } else {
      // Inexact steps (PCG, CGNR) stop on the same tests; on the cactus they
      // get as close.
      EXPECT_LE(std::abs(gap_max), 1e-6) << name;
    }
  }
  EXPECT_GE(exact, 10);
}

// arap_local_global runs the subspace ARAP energy and is measured against
// the reference of that energy: its reported costs are that energy
// (EvaluateEnergy of the layout's arap energy; Eq. 17 at its solution would
// differ by orders of magnitude), and each larger budget ends closer to
// the minimum (a local/global iteration never raises the energy).
TEST_F(SolverLabTest, ArapVariantIsMeasuredOnItsOwnEnergy) {
  const CsvTable& table = *solvers_;
  std::map<std::string, double> gap_max;
  for (const auto& row : table.rows) {
    const std::string variant = table.Cell(row, "variant");
    const bool arap = variant.rfind("arap_", 0) == 0;
    EXPECT_EQ(table.Cell(row, "energy"), arap ? "arap" : "ed") << variant;
    if (variant == "arap_gauss_newton") {
      // Gauss-Newton on the same energy: its costs are that energy too, and
      // it reaches the reference's minimum (the reference is this solver).
      EXPECT_EQ(table.Cell(row, "description").rfind("ARAP Gauss-Newton", 0), 0u);
      EXPECT_LE(table.Number(row, "cost_error"), 1e-9);
      EXPECT_EQ(table.Number(row, "handle_rms_rel"), 0.0);
      continue;
    }
    if (!arap) continue;
    EXPECT_EQ(table.Cell(row, "description").rfind("ARAP local/global", 0), 0u);
    EXPECT_LE(table.Number(row, "cost_error"), 1e-9);
    EXPECT_EQ(table.Number(row, "handle_rms_rel"), 0.0);  // exact constraints
    gap_max[table.Cell(row, "budget")] = table.Number(row, "energy_gap_max");
  }
  ASSERT_EQ(gap_max.size(), 3u);
  EXPECT_GT(gap_max["1"], gap_max["3"]);
  EXPECT_GT(gap_max["3"], gap_max["converged"]);
  EXPECT_GE(gap_max["converged"], 0.0);
}

TEST_F(SolverLabTest, NoRunGoesBelowTheReferenceMinimum) {
  const CsvTable& table = *solvers_;
  for (const auto& row : table.rows) {
    for (const char* column :
         {"energy_gap", "energy_gap_max", "energy_gap_last", "energy_gap_min"}) {
      EXPECT_GE(table.Number(row, column), -1e-9)
          << table.Cell(row, "variant") << " " << table.Cell(row, "budget") << " " << column;
    }
  }
  for (const auto& row : traces_->rows) {
    EXPECT_GE(traces_->Number(row, "energy_gap"), -1e-9)
        << traces_->Cell(row, "variant") << " frame " << traces_->Cell(row, "frame");
  }
}

TEST_F(SolverLabTest, TheBudgetCapsTheIterations) {
  const CsvTable& table = *solvers_;
  for (const auto& row : table.rows) {
    const std::string& budget = table.Cell(row, "budget");
    const double cap = budget == "converged" ? kConvergedMaxIterations : std::stod(budget);
    EXPECT_LE(table.Number(row, "iterations"), cap) << table.Cell(row, "variant");
    EXPECT_LE(table.Number(row, "iterations_total"), cap * kQuickFrames)
        << table.Cell(row, "variant");
    EXPECT_GE(table.Number(row, "iterations_total"), kQuickFrames) << table.Cell(row, "variant");
  }
}

TEST_F(SolverLabTest, TracesStartAtTimeZeroAndNeverGoUp) {
  const CsvTable& traces = *traces_;
  const CsvTable& table = *solvers_;
  // (variant, frame) -> points in file order.
  std::map<std::pair<std::string, int>, std::vector<std::tuple<int, double, double, double>>> runs;
  for (const auto& row : traces.rows) {
    EXPECT_EQ(traces.Cell(row, "scenario"), "cactus");
    runs[{traces.Cell(row, "variant"), static_cast<int>(traces.Number(row, "frame"))}].push_back(
        {static_cast<int>(traces.Number(row, "iteration")), traces.Number(row, "ms"),
         traces.Number(row, "cost"), traces.Number(row, "energy_gap")});
  }
  std::map<std::string, double> gap_last;
  for (const auto& row : table.rows) {
    if (table.Cell(row, "budget") == "converged") {
      gap_last[table.Cell(row, "variant")] = table.Number(row, "energy_gap_last");
    }
  }
  for (const SolverVariant& variant : SolverVariants()) {
    for (int frame : {1, kQuickFrames}) {
      const auto found = runs.find({variant.name, frame});
      ASSERT_NE(found, runs.end()) << variant.name << " frame " << frame;
      const auto& points = found->second;
      ASSERT_GE(points.size(), 2u) << variant.name;
      EXPECT_EQ(std::get<0>(points[0]), 0);
      EXPECT_EQ(std::get<1>(points[0]), 0.0);
      for (size_t i = 1; i < points.size(); ++i) {
        EXPECT_EQ(std::get<0>(points[i]), static_cast<int>(i));
        EXPECT_GE(std::get<1>(points[i]), std::get<1>(points[i - 1])) << variant.name;
        // Accepted steps lower the cost; a rejected one repeats it.
        EXPECT_LE(std::get<2>(points[i]), std::get<2>(points[i - 1]) * (1.0 + 1e-12))
            << variant.name << " frame " << frame << " iteration " << i;
      }
      if (frame == kQuickFrames) {
        // The trace ends at the frame's final cost.
        EXPECT_NEAR(std::get<3>(points.back()), gap_last[variant.name],
                    1e-3 * std::abs(gap_last[variant.name]) + 1e-12)
            << variant.name;
      }
    }
  }
}

// Every variant on its own, budget 2: per frame at most two iterations, a
// trace from the initial cost (at time 0) whose lowest point is the final
// cost, and a final cost that is Eq. 17 evaluated term by term. The
// Gauss-Newton trace never goes up (a rejected step repeats the cost); a
// Ceres trace may (a rejected step shows the rejected candidate's cost).
TEST_F(SolverLabTest, ReportedCostsAreTheEnergy) {
  ExperimentScenario scenario;
  std::string error;
  ASSERT_TRUE(LoadExperimentScenario(CactusEntry(), kQuickFrames, &scenario, &error)) << error;
  for (const SolverVariant& variant : SolverVariants()) {
    const DeformerOptions options = Options(variant, 2);
    GraphMethod deformer(options.method);
    ASSERT_TRUE(deformer.Precompute(scenario.mesh, options, &error)) << error;
    ASSERT_TRUE(deformer.SetHandles(scenario.layout, &error)) << error;
    DragLog log;
    ASSERT_TRUE(DragAlong(&deformer, scenario.path, DragAlongOptions(), &log, &error))
        << variant.name << ": " << error;
    ASSERT_EQ(log.frames.size(), scenario.path.size());
    for (const DragStats& stats : log.frames) {
      EXPECT_LE(stats.iterations, 2) << variant.name;
      ASSERT_FALSE(stats.trace.empty()) << variant.name;
      EXPECT_EQ(stats.trace.front().ms, 0.0) << variant.name;
      EXPECT_DOUBLE_EQ(stats.trace.front().cost, stats.initial_cost) << variant.name;
      double lowest = stats.trace.front().cost;
      for (size_t i = 1; i < stats.trace.size(); ++i) {
        if (options.backend == Solver::kGaussNewton) {
          EXPECT_LE(stats.trace[i].cost, stats.trace[i - 1].cost) << variant.name;
        }
        lowest = std::min(lowest, stats.trace[i].cost);
      }
      EXPECT_DOUBLE_EQ(lowest, stats.final_cost) << variant.name;
    }
    const double energy =
        EvaluateEnergy(deformer.energy(), deformer.transforms(), scenario.path.back());
    EXPECT_NEAR(log.frames.back().final_cost, energy, 1e-9 * energy) << variant.name;
  }
}

}  // namespace
}  // namespace msdeform
