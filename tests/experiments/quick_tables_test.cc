// Runs the quick subset of the experiment runner (as `msdeform_experiments
// --quick` does) into a temporary folder and checks its tables for sanity:
// the columns are there, every number is finite, and the multi-scale method
// optimises fewer variables than the dense static graph.

#include "experiments/runner.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "experiments/tables.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  int Column(const std::string& name) const {
    for (size_t c = 0; c < columns.size(); ++c)
      if (columns[c] == name) return static_cast<int>(c);
    return -1;
  }
};

class QuickTablesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(std::string(MSDEFORM_DATA_DIR) + "/meshes/cactus.off") ||
        !fs::exists(std::string(MSDEFORM_DATA_DIR) + "/meshes/hand.off")) {
      error_ = "real meshes missing: run data/fetch_meshes.sh";  // every test fails
      return;
    }
    out_dir_ = new std::string((fs::temp_directory_path() / "msdeform_quick_tables").string());
    fs::remove_all(*out_dir_);
    RunnerOptions options;
    options.scenario_dir = std::string(MSDEFORM_SOURCE_DIR) + "/experiments/scenarios";
    options.out_dir = *out_dir_;
    options.quick = true;
    ok_ = RunExperiments(options, &error_);
  }
  static void TearDownTestSuite() {
    if (out_dir_ != nullptr) fs::remove_all(*out_dir_);
    delete out_dir_;
    out_dir_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(ok_) << error_;
  }
  static CsvTable Read(const std::string& stem) {
    CsvTable table;
    std::string error;
    EXPECT_TRUE(ReadTableCsv(*out_dir_ + "/" + stem + ".csv", &table.columns, &table.rows, &error))
        << error;
    EXPECT_TRUE(fs::exists(*out_dir_ + "/" + stem + ".md")) << stem;
    return table;
  }
  // Every cell of a numeric column parses as a finite number; cells of
  // `may_be_empty` columns may be empty (not applicable).
  static void ExpectFinite(const CsvTable& table, const std::set<std::string>& text_columns,
                           const std::set<std::string>& may_be_empty) {
    for (const auto& row : table.rows) {
      for (size_t c = 0; c < row.size(); ++c) {
        const std::string& name = table.columns[c];
        if (text_columns.count(name)) continue;
        if (row[c].empty()) {
          EXPECT_TRUE(may_be_empty.count(name)) << name << " is empty in row of " << row[0];
          continue;
        }
        char* end = nullptr;
        const double value = std::strtod(row[c].c_str(), &end);
        EXPECT_EQ(*end, '\0') << name << ": '" << row[c] << "'";
        EXPECT_TRUE(std::isfinite(value)) << name << ": " << row[c];
      }
    }
  }

  static std::string* out_dir_;
  static bool ok_;
  static std::string error_;
};

std::string* QuickTablesTest::out_dir_ = nullptr;
bool QuickTablesTest::ok_ = false;
std::string QuickTablesTest::error_;

TEST_F(QuickTablesTest, Table2HasTheColumnsAndFiniteValues) {
  const CsvTable table = Read("table2");
  for (const char* column : {"scenario", "method", "vertices", "nodes_optimized", "variables",
                             "frame_ms", "handle_rms_rel", "arap_energy", "leakage_rel",
                             "fixed_max_rel", "strain", "orthogonality", "iterations"}) {
    EXPECT_GE(table.Column(column), 0) << column;
  }
  // Two scenarios x four methods.
  ASSERT_EQ(table.rows.size(), 8u);
  ExpectFinite(table, {"scenario", "method"},
               {"leakage_rel", "leakage_max_rel", "orthogonality", "arap_energy_joint",
                "other_backend_frame_ms"});
  std::set<std::string> methods;
  for (const auto& row : table.rows) methods.insert(row[table.Column("method")]);
  EXPECT_EQ(methods, (std::set<std::string>{"multiscale", "static", "static_dense", "cgal_arap"}));
  // Leakage only where the scenario has a watch region (hand_finger).
  for (const auto& row : table.rows) {
    const bool has_watch = row[table.Column("scenario")] == "hand_finger";
    EXPECT_EQ(row[table.Column("leakage_rel")].empty(), !has_watch) << row[0] << " " << row[1];
  }
}

TEST_F(QuickTablesTest, MultiScaleOptimisesFewerVariablesThanTheDenseGraph) {
  const CsvTable table = Read("table2");
  std::map<std::string, std::map<std::string, double>> variables;
  std::map<std::string, std::map<std::string, double>> handle_error;
  for (const auto& row : table.rows) {
    variables[row[0]][row[1]] = std::stod(row[table.Column("variables")]);
    handle_error[row[0]][row[1]] = std::stod(row[table.Column("handle_rms_rel")]);
  }
  for (const auto& [scenario, by_method] : variables) {
    EXPECT_LT(by_method.at("multiscale"), by_method.at("static_dense")) << scenario;
    EXPECT_GT(by_method.at("multiscale"), 0.0) << scenario;
    // Every method reaches its handle within 5% of the diagonal.
    for (const auto& [method, error] : handle_error[scenario]) {
      EXPECT_LT(error, 0.05) << scenario << " " << method;
    }
  }
}

TEST_F(QuickTablesTest, OtherTablesAreComplete) {
  const CsvTable table1 = Read("table1");
  ASSERT_EQ(table1.rows.size(), 2u);
  for (const char* column : {"model", "vertices", "faces", "cell_width", "particles", "d1",
                             "scales_n", "precompute_ms", "rigidity_ms", "selected_scale",
                             "nodes_optimized", "variables", "frame_ms"}) {
    EXPECT_GE(table1.Column(column), 0) << column;
  }
  ExpectFinite(table1, {"model", "scenario"}, {});
  const CsvTable ablations = Read("ablations");
  EXPECT_EQ(ablations.rows.size(), 13u);  // the cactus x thirteen variants
  ExpectFinite(ablations, {"scenario", "variant"},
               {"leakage_rel", "arap_energy_joint", "arap_distance_rel"});
}

}  // namespace
}  // namespace msdeform
