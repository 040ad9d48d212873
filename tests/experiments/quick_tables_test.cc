// Runs the quick subset of the experiment runner (as `msdeform_experiments
// --quick` does) into a temporary folder and checks its tables for sanity:
// the columns are there, every number is finite, and the multi-scale method
// optimises fewer variables than the dense static graph. Then runs the same
// runner on three edits of a procedural bar whose every table cell is known
// (rigid motions and a rest pose) and checks the cells against those values.

#include "experiments/runner.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <unistd.h>

#include "experiments/tables.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// A folder under the system's temporary one, named for this process so that
// runs of this test from several checkouts at once do not share it.
std::string TemporaryFolder(const std::string& stem) {
  return (fs::temp_directory_path() / (stem + "_" + std::to_string(::getpid()))).string();
}

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
    out_dir_ = new std::string(TemporaryFolder("msdeform_quick_tables"));
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

// The cell of `column` in the row of `scenario` and `method` (first two
// columns) and, when `energy` is not empty, of that energy (the `energy`
// column), as written; a test failure when any is missing.
std::string Cell(const CsvTable& table, const std::string& scenario, const std::string& method,
                 const std::string& column, const std::string& energy = "") {
  const int c = table.Column(column);
  const int e = energy.empty() ? -1 : table.Column("energy");
  EXPECT_GE(c, 0) << column;
  EXPECT_TRUE(energy.empty() || e >= 0) << "no energy column";
  for (const auto& row : table.rows) {
    if (c >= 0 && row[0] == scenario && row[1] == method && (e < 0 || row[e] == energy)) {
      return row[c];
    }
  }
  ADD_FAILURE() << "no row " << scenario << " / " << method << " / " << energy << " with "
                << column;
  return "";
}

// The same as a number; NaN (and a failure) when the cell is empty or not a number.
double Number(const CsvTable& table, const std::string& scenario, const std::string& method,
              const std::string& column, const std::string& energy = "") {
  const std::string cell = Cell(table, scenario, method, column, energy);
  char* end = nullptr;
  const double value = std::strtod(cell.c_str(), &end);
  if (cell.empty() || *end != '\0') {
    ADD_FAILURE() << scenario << " / " << method << " " << column << ": '" << cell << "'";
    return std::nan("");
  }
  return value;
}

std::string* QuickTablesTest::out_dir_ = nullptr;
bool QuickTablesTest::ok_ = false;
std::string QuickTablesTest::error_;

// The graph methods of the registry (run once per energy).
const std::vector<std::string>& GraphMethods() {
  static const std::vector<std::string> methods = [] {
    std::vector<std::string> graph;
    for (const MethodDescriptor& method : RegisteredMethods()) {
      if (method.graph) graph.push_back(method.name);
    }
    return graph;
  }();
  return methods;
}

// What a method that is not a graph minimised: its descriptor's energy
// (methods/registry.h); "" for a graph method (the row's energy).
std::string ExpectedEnergy(const std::string& method) {
  const MethodDescriptor* descriptor = FindMethod(method);
  return descriptor == nullptr || descriptor->graph ? "" : descriptor->energy;
}

TEST_F(QuickTablesTest, Table2HasTheColumnsAndFiniteValues) {
  const CsvTable table = Read("table2");
  for (const char* column : {"scenario", "method", "energy", "vertices", "nodes_optimized",
                             "variables", "frame_ms", "handle_rms_rel", "arap_energy",
                             "leakage_rel", "fixed_max_rel", "strain", "orthogonality",
                             "iterations"}) {
    EXPECT_GE(table.Column(column), 0) << column;
  }
  // Two scenarios x (every registered method + one more row per graph method
  // for the second energy).
  ASSERT_EQ(table.rows.size(), 2 * (MethodNames().size() + GraphMethods().size()));
  ExpectFinite(table, {"scenario", "method", "energy"},
               {"leakage_rel", "leakage_max_rel", "orthogonality", "arap_energy_joint",
                "other_backend_frame_ms"});
  std::set<std::string> methods;
  for (const auto& row : table.rows) methods.insert(row[table.Column("method")]);
  const std::vector<std::string> names = MethodNames();
  EXPECT_EQ(methods, std::set<std::string>(names.begin(), names.end()));
  // Leakage only where the scenario has a watch region (hand_finger).
  for (const auto& row : table.rows) {
    const bool has_watch = row[table.Column("scenario")] == "hand_finger";
    EXPECT_EQ(row[table.Column("leakage_rel")].empty(), !has_watch) << row[0] << " " << row[1];
  }
}

TEST_F(QuickTablesTest, EveryRowSaysWhatItMinimised) {
  const CsvTable table = Read("table2");
  const int method = table.Column("method"), energy = table.Column("energy");
  ASSERT_GE(energy, 0);
  // (scenario, method) -> the energies of its rows, in table order.
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> energies;
  for (const auto& row : table.rows) energies[{row[0], row[method]}].push_back(row[energy]);
  for (const std::string scenario : {"cactus", "hand_finger"}) {
    for (const std::string& name : MethodNames()) {
      SCOPED_TRACE(scenario + " / " + name);
      const bool graph = ExpectedEnergy(name).empty();
      const std::vector<std::string> expected =
          graph ? std::vector<std::string>{"ed", "arap"}
                : std::vector<std::string>{ExpectedEnergy(name)};
      const std::pair<std::string, std::string> key(scenario, name);
      EXPECT_EQ(energies[key], expected);
    }
  }
}

// The subspace ARAP energy's exact constraints (the default): the handle
// vertices are the handle transform times rest and the fixed ones rest, so
// both errors are exactly 0; ref_distance_rel is measured against the
// converged reference (full_arap) as for the ed rows.
TEST_F(QuickTablesTest, ArapRowsHoldHandleAndFixedVerticesExactly) {
  const CsvTable table = Read("table2");
  for (const std::string scenario : {"cactus", "hand_finger"}) {
    for (const std::string& method : GraphMethods()) {
      SCOPED_TRACE(scenario + " / " + method);
      EXPECT_EQ(Number(table, scenario, method, "handle_rms_rel", "arap"), 0.0);
      EXPECT_EQ(Number(table, scenario, method, "fixed_max_rel", "arap"), 0.0);
      EXPECT_GT(Number(table, scenario, method, "ref_distance_rel", "arap"), 0.0);
      // The ed rows do not hold the handle exactly (Eq. 17's soft w_con).
      EXPECT_GT(Number(table, scenario, method, "handle_rms_rel", "ed"), 0.0);
    }
  }
}

// The converged reference (full_arap, RunnerOptions::reference_method) is
// run once per scenario and its row measures itself: ratio exactly 1,
// distances exactly 0. Every other row's ratio is its energy over that row's
// (to the printed digits), and a row that holds the handle and the fixed
// vertices exactly cannot go below the converged minimum under the same
// constraints.
TEST_F(QuickTablesTest, EveryRowIsMeasuredAgainstTheConvergedReference) {
  EXPECT_EQ(RunnerOptions().reference_method, "full_arap");
  const CsvTable table = Read("table2");
  const int energy = table.Column("energy");
  ASSERT_GE(energy, 0);
  for (const std::string scenario : {"cactus", "hand_finger"}) {
    SCOPED_TRACE(scenario);
    EXPECT_EQ(Cell(table, scenario, "full_arap", "arap_energy_ratio"), "1");
    EXPECT_EQ(Cell(table, scenario, "full_arap", "ref_distance_rel"), "0");
    EXPECT_EQ(Cell(table, scenario, "full_arap", "ref_distance_max_rel"), "0");
    const double reference = Number(table, scenario, "full_arap", "arap_energy");
    ASSERT_GT(reference, 0.0);
    for (const auto& row : table.rows) {
      if (row[0] != scenario) continue;
      SCOPED_TRACE(row[1] + " / " + row[energy]);
      auto number = [&](const std::string& column) {
        return Number(table, scenario, row[1], column, row[energy]);
      };
      const double ratio = number("arap_energy_ratio");
      EXPECT_NEAR(ratio, number("arap_energy") / reference, 2e-3 * ratio);
      EXPECT_LE(number("ref_distance_rel"), number("ref_distance_max_rel"));
      if (number("handle_rms_rel") == 0.0 && number("fixed_max_rel") == 0.0) {
        EXPECT_GE(ratio, 1.0 - 1e-3);
      }
    }
  }
  const CsvTable ablations = Read("ablations");
  const int variant_energy = ablations.Column("energy");
  ASSERT_GE(variant_energy, 0);
  for (const auto& row : ablations.rows) {
    auto number = [&](const std::string& column) {
      return Number(ablations, row[0], row[1], column, row[variant_energy]);
    };
    const double ratio = number("arap_energy_ratio");
    EXPECT_NEAR(ratio,
                number("arap_energy") / Number(table, row[0], "full_arap", "arap_energy"),
                2e-3 * ratio)
        << row[1];
  }
}

TEST_F(QuickTablesTest, MultiScaleOptimisesFewerVariablesThanTheDenseGraph) {
  const CsvTable table = Read("table2");
  const int energy = table.Column("energy");
  ASSERT_GE(energy, 0);
  std::map<std::string, std::map<std::string, double>> variables;
  std::map<std::string, std::map<std::string, double>> handle_error;
  for (const auto& row : table.rows) {
    const std::string name = row[1] + "/" + row[energy];
    variables[row[0]][name] = std::stod(row[table.Column("variables")]);
    handle_error[row[0]][name] = std::stod(row[table.Column("handle_rms_rel")]);
  }
  for (const auto& [scenario, by_method] : variables) {
    for (const std::string energy_name : {"ed", "arap"}) {
      EXPECT_LT(by_method.at("multiscale/" + energy_name),
                by_method.at("static_dense/" + energy_name))
          << scenario;
      EXPECT_GT(by_method.at("multiscale/" + energy_name), 0.0) << scenario;
    }
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
  // The cactus x fifteen variants of energy ed and four of energy arap.
  ASSERT_EQ(ablations.rows.size(), 19u);
  ExpectFinite(ablations, {"scenario", "variant", "energy"},
               {"leakage_rel", "leakage_max_rel", "arap_energy_joint"});
  const int variant = ablations.Column("variant"), energy = ablations.Column("energy");
  ASSERT_GE(energy, 0);
  const std::set<std::string> arap_variants = {"energy_arap", "arap_clusters_nodes",
                                               "arap_clusters_vertices", "arap_soft_constraints"};
  for (const auto& row : ablations.rows) {
    EXPECT_EQ(row[energy], arap_variants.count(row[variant]) ? "arap" : "ed") << row[variant];
  }
  for (const std::string& name : arap_variants) {
    EXPECT_EQ(Number(ablations, "cactus", name, "fixed_max_rel"), 0.0) << name;
  }
  // Exact constraints hold the handle exactly; soft ones pull it.
  EXPECT_EQ(Number(ablations, "cactus", "energy_arap", "handle_rms_rel"), 0.0);
  EXPECT_GT(Number(ablations, "cactus", "arap_soft_constraints", "handle_rms_rel"), 0.0);
}

// Every column but the times of the quick run's ed rows, against a run of
// energy ed alone: the arap rows beside them change nothing.
TEST_F(QuickTablesTest, EdRowsEqualARunOfEnergyEdAlone) {
  RunnerOptions options;
  options.scenario_dir = std::string(MSDEFORM_SOURCE_DIR) + "/experiments/scenarios";
  options.out_dir = *out_dir_ + "/ed_only";
  options.only = {"cactus"};
  options.frames = 5;  // as --quick
  options.ablation_scenarios = {};
  options.methods = {"multiscale", "static", "static_dense", "cgal_arap", "full_arap"};
  options.time_other_backend = false;
  options.energies = {Energy::kEd};
  std::string error;
  ASSERT_TRUE(RunExperiments(options, &error)) << error;
  CsvTable ed_only;
  ASSERT_TRUE(ReadTableCsv(options.out_dir + "/table2.csv", &ed_only.columns, &ed_only.rows,
                           &error))
      << error;
  const CsvTable both = Read("table2");
  ASSERT_EQ(ed_only.rows.size(), 5u);
  ASSERT_EQ(ed_only.columns, both.columns);
  const std::set<std::string> times = {"frame_ms",      "solve_ms",      "skin_ms",
                                       "setup_ms",      "precompute_ms", "rigidity_ms",
                                       "other_backend_frame_ms"};
  for (const auto& row : ed_only.rows) {
    const std::string energy = row[ed_only.Column("energy")];
    EXPECT_EQ(energy, row[1] == "cgal_arap" || row[1] == "full_arap" ? "arap" : "ed");
    for (size_t c = 0; c < row.size(); ++c) {
      if (times.count(ed_only.columns[c])) continue;
      EXPECT_EQ(row[c], Cell(both, row[0], row[1], ed_only.columns[c], energy))
          << row[1] << " " << ed_only.columns[c];
    }
  }
}

// Three edits of MakeBar(8): the box [0, 8] x [0, 1] x [0, 1] whose faces
// carry a grid of spacing 0.5, so 17 x 3 x 3 - 15 x 1 x 1 = 138 vertices and
// 2 x (8 + 8 + 1) unit squares x 4 quads x 2 = 272 triangles; bounding-box
// diagonal sqrt(8^2 + 1 + 1) = sqrt(66). "The first voxel" (x <= 1, slab
// 0 .. 1/8 of the extent) holds the x = 0 cap's 9 vertices and the rings of 8
// at x = 0.5 and 1: 25 vertices, of which 12 are edge-of-box corners at
// distance sqrt(0.5) from the bar's axis (y = z = 0.5), 12 edge midpoints at
// 0.5 and the cap's centre on the axis. The last voxel (x >= 7) likewise.
//   bar_translate  handle: last voxel, no fixed region, translated by
//                  (0, 0, 0.5). Nothing holds the rest, so the only result
//                  of zero energy that meets the handle (ARAP's, and the
//                  deformation graph's) is the bar translated rigidly: every
//                  vertex moves 0.5, distortion is 0.
//   bar_twist      handle: the whole bar, turned 90 degrees about x through
//                  its centroid (4, 0.5, 0.5), on its axis: every vertex moves
//                  sqrt(2) x its distance from the axis, so the first voxel's
//                  mean is (12 x 1 + 12 x sqrt(0.5)) / 25 and its max is 1.
//   bar_rest       fixed: first voxel, handle: last voxel, identity target:
//                  nothing moves.
// Every scenario watches the first voxel.
class KnownAnswerTablesTest : public ::testing::Test {
 protected:
  static constexpr int kVertices = 138;
  static constexpr int kFaces = 272;
  static constexpr int kFirstVoxelVertices = 25;

  static void SetUpTestSuite() {
    dir_ = new std::string(TemporaryFolder("msdeform_known_tables"));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_ + "/scenarios");
    const Mesh bar = MakeBar(8);
    ASSERT_EQ(bar.num_vertices(), kVertices);  // the counts above, as the generator makes them
    ASSERT_EQ(bar.num_faces(), kFaces);
    ASSERT_TRUE(WriteMesh(*dir_ + "/scenarios/bar.off", bar, &error_)) << error_;
    const std::string first_voxel = R"({"slab": {"axis": "x", "from": 0.0, "to": 0.125}})";
    const std::string last_voxel = R"({"slab": {"axis": "x", "from": 0.875, "to": 1.0}})";
    const std::string whole_bar = R"({"slab": {"axis": "x", "from": 0.0, "to": 1.0}})";
    const std::map<std::string, std::string> scenarios = {
        {"bar_translate", R"("handle": )" + last_voxel +
                              R"(, "transform": {"translation": [0, 0, 0.5]}, "frames": 3)"},
        // 30 degrees a frame: Gauss-Newton converges in about 8 iterations
        // (90 degrees in one frame does not within the 20 allowed).
        {"bar_twist", R"("handle": )" + whole_bar +
                          R"(, "transform": {"rotation": {"axis": [1, 0, 0], "angle_deg": 90}},)"
                          R"( "frames": 3)"},
        {"bar_rest", R"("fixed": [)" + first_voxel + R"(], "handle": )" + last_voxel +
                         R"(, "frames": 1)"},
        // Not in the tables (options.only): a bend of positive ARAP energy
        // for the reference columns' own tests.
        {"bar_bend", R"("fixed": [)" + first_voxel + R"(], "handle": )" + last_voxel +
                         R"(, "transform": {"translation": [0, 0, 2]}, "frames": 2)"},
    };
    for (const auto& [name, body] : scenarios) {
      std::ofstream(*dir_ + "/scenarios/" + name + ".json")
          << R"({"mesh": "bar.off", "watch": )" << first_voxel << ", " << body << "}\n";
    }
    RunnerOptions options;
    options.scenario_dir = *dir_ + "/scenarios";
    options.out_dir = *dir_ + "/tables";
    options.ablation_scenarios = {};
    // FastLSM reaches a rigid motion only as its steps settle (its own test,
    // tests/methods/fastlsm_test.cc): the exact answers below are the others'.
    // full_arap is the reference of every row (RunnerOptions::reference_method).
    options.methods = {"multiscale", "static",       "static_dense",
                       "cgal_arap",  "cgal_sr_arap", "full_arap"};
    // Both energies on every bar scenario. On bar_twist the whole bar is the
    // handle: no skinned vertex is left, and the subspace ARAP energy's global
    // matrix is 0 (its damping keeps every node where it is).
    options.only = {"bar_translate", "bar_rest", "bar_twist"};
    // The local/global iterations of energy arap carry a translation along
    // the free bar slowly (20 a frame leave its far end 7% short of 0.5;
    // with this cap they stop on the default tolerances 1.3e-6 of the
    // diagonal short, as with 20000, see kArapLength). Gauss-Newton on ed
    // converges within 20, so the cap changes no ed row.
    options.method_options.deformer.stopping.max_iterations = 2000;
    ok_ = RunExperiments(options, &error_);
    if (!ok_) return;
    for (const char* stem : {"table1", "table2"}) {
      CsvTable& table = std::string(stem) == "table1" ? table1_ : table2_;
      ok_ = ReadTableCsv(options.out_dir + "/" + stem + ".csv", &table.columns, &table.rows,
                         &error_);
      if (!ok_) return;
    }
  }
  static void TearDownTestSuite() {
    if (dir_ != nullptr) fs::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(ok_) << error_; }

  static std::string* dir_;
  static bool ok_;
  static std::string error_;
  static CsvTable table1_, table2_;
};

std::string* KnownAnswerTablesTest::dir_ = nullptr;
bool KnownAnswerTablesTest::ok_ = false;
std::string KnownAnswerTablesTest::error_;
CsvTable KnownAnswerTablesTest::table1_;
CsvTable KnownAnswerTablesTest::table2_;

// Tolerances. Lengths over the diagonal: a rigid motion is reached to the
// solver's tolerance (today 1e-11 or better), far below what a wrongly
// computed or misplaced column makes here (1e-3 of the diagonal or 4% of a
// value and more). The ARAP energy is a squared relative length. Known
// non-zero values are written with 4 significant digits.
constexpr double kLength = 1e-6;
constexpr double kEnergy = 1e-10;
constexpr double kPrinted = 1e-3;  // relative
// Lengths of the arap rows: the local/global solver converges linearly and
// stops on the default tolerances about 1e-6 of the diagonal short of the
// translation, far above the Gauss-Newton solves' rounding; still 10x below
// what a misplaced column makes.
constexpr double kArapLength = 1e-4;

TEST_F(KnownAnswerTablesTest, Table2HoldsTheKnownValuesOfRigidMotionsAndARestPose) {
  const std::vector<std::string> methods = {"multiscale", "static", "static_dense", "cgal_arap",
                                            "cgal_sr_arap"};
  // The graph methods once per energy (ed, arap), and the reference full_arap.
  ASSERT_EQ(table2_.rows.size(), 3 * (methods.size() + 1 + GraphMethods().size()));
  const double diag = std::sqrt(66.0);
  // Mean and max displacement of the first voxel, over the diagonal.
  const std::map<std::string, std::pair<double, double>> watch = {
      {"bar_translate", {0.5 / diag, 0.5 / diag}},
      {"bar_twist", {(12.0 + 12.0 * std::sqrt(0.5)) / 25.0 / diag, 1.0 / diag}},
      {"bar_rest", {0.0, 0.0}}};
  for (const auto& [scenario, leakage] : watch) {
    for (const std::string& method : methods) {
      SCOPED_TRACE(scenario + " / " + method);
      const std::string energy = ExpectedEnergy(method).empty() ? "ed" : "";
      auto number = [&](const std::string& column) {
        return Number(table2_, scenario, method, column, energy);
      };
      EXPECT_EQ(number("vertices"), kVertices);
      EXPECT_NEAR(number("handle_rms_rel"), 0.0, kLength);
      EXPECT_NEAR(number("fixed_max_rel"), 0.0, kLength);
      EXPECT_NEAR(number("arap_energy"), 0.0, kEnergy);
      EXPECT_NEAR(number("strain"), 0.0, kLength);
      // The reference (full_arap) reaches the same rigid motion: distances
      // 0; its energy is a rounding residue (below 1e-12), so no ratio (empty).
      EXPECT_NEAR(number("ref_distance_rel"), 0.0, kLength);
      EXPECT_NEAR(number("ref_distance_max_rel"), 0.0, kLength);
      EXPECT_EQ(Cell(table2_, scenario, method, "arap_energy_ratio", energy), "");
      EXPECT_NEAR(number("leakage_rel"), leakage.first, kPrinted * leakage.first + kLength);
      EXPECT_NEAR(number("leakage_max_rel"), leakage.second, kPrinted * leakage.second + kLength);
      EXPECT_EQ(number("unconverged_frames"), 0);
      EXPECT_GT(number("frame_ms"), 0.0);
      // The band within 0.05 diag = 0.41 of the fixed region along edges is
      // empty (the nearest other vertices are 0.5 away), and there is no band
      // without a fixed region: not applicable.
      EXPECT_EQ(Cell(table2_, scenario, method, "arap_energy_joint", energy), "");
      if (method == "cgal_arap" || method == "cgal_sr_arap") {
        // ROI: every vertex but the fixed ones, 3 variables each.
        const int roi = kVertices - (scenario == "bar_rest" ? kFirstVoxelVertices : 0);
        EXPECT_EQ(number("nodes_optimized"), roi);
        EXPECT_EQ(number("variables"), 3 * roi);
        EXPECT_EQ(Cell(table2_, scenario, method, "orthogonality", energy), "");
        EXPECT_EQ(number("precompute_ms"), 0.0);
        EXPECT_EQ(number("rigidity_ms"), 0.0);
      } else {
        EXPECT_NEAR(number("orthogonality"), 0.0, kLength);
        if (method != "multiscale") {
          EXPECT_EQ(number("rigidity_ms"), 0.0);  // the rigidity estimate is multiscale's
        }
        // Timed with the other backend too, except the dense graph.
        EXPECT_EQ(Cell(table2_, scenario, method, "other_backend_frame_ms", energy).empty(),
                  method == "static_dense");
      }
    }
  }
}

// The graph methods with energy arap: the translation and the rest pose are
// in every graph's subspace at zero ARAP energy, and the exact constraints
// put the handle and fixed vertices exactly where they belong.
TEST_F(KnownAnswerTablesTest, ArapRowsHoldTheKnownValuesOfATranslationAndARestPose) {
  const double diag = std::sqrt(66.0);
  const std::map<std::string, std::pair<double, double>> watch = {
      {"bar_translate", {0.5 / diag, 0.5 / diag}}, {"bar_rest", {0.0, 0.0}}};
  for (const auto& [scenario, leakage] : watch) {
    for (const std::string& method : GraphMethods()) {
      SCOPED_TRACE(scenario + " / " + method);
      auto number = [&](const std::string& column) {
        return Number(table2_, scenario, method, column, "arap");
      };
      EXPECT_EQ(number("vertices"), kVertices);
      EXPECT_EQ(number("handle_rms_rel"), 0.0);
      EXPECT_EQ(number("fixed_max_rel"), 0.0);
      EXPECT_NEAR(number("arap_energy"), 0.0, kEnergy);
      EXPECT_NEAR(number("strain"), 0.0, kArapLength);
      EXPECT_NEAR(number("ref_distance_rel"), 0.0, kArapLength);
      EXPECT_NEAR(number("ref_distance_max_rel"), 0.0, kArapLength);
      EXPECT_NEAR(number("leakage_rel"), leakage.first, kPrinted * leakage.first + kArapLength);
      EXPECT_NEAR(number("leakage_max_rel"), leakage.second,
                  kPrinted * leakage.second + kArapLength);
      // Not timed with Ceres, which does not run energy arap.
      EXPECT_EQ(Cell(table2_, scenario, method, "other_backend_frame_ms", "arap"), "");
    }
  }
}

// The reference columns of RunMethod: a run whose final mesh equals the
// reference (the same deterministic method again) has ratio exactly 1 and
// distances exactly 0, as has RunCgalArap against its own result; without a
// reference all three are NaN.
TEST_F(KnownAnswerTablesTest, ARowEqualToTheReferenceHasRatioOneAndDistanceZero) {
  ExperimentScenario bend;
  ASSERT_TRUE(LoadExperimentScenario(*dir_ + "/scenarios/bar_bend.json", 0, &bend, &error_))
      << error_;
  const MethodOptions options;
  RunResult first, again, cgal;
  Eigen::Matrix3Xd reference;
  ASSERT_TRUE(RunMethod(bend, "full_arap", options, "full_arap", nullptr, &first, &reference,
                        &error_))
      << error_;
  EXPECT_GT(first.arap_energy, 1e-4);  // a real bend
  EXPECT_TRUE(std::isnan(first.arap_energy_ratio));
  EXPECT_TRUE(std::isnan(first.ref_distance_rel));
  EXPECT_TRUE(std::isnan(first.ref_distance_max_rel));
  ASSERT_TRUE(RunMethod(bend, "full_arap", options, "full_arap", &reference, &again, nullptr,
                        &error_))
      << error_;
  EXPECT_EQ(again.arap_energy, first.arap_energy);
  EXPECT_EQ(again.arap_energy_ratio, 1.0);
  EXPECT_EQ(again.ref_distance_rel, 0.0);
  EXPECT_EQ(again.ref_distance_max_rel, 0.0);
  Eigen::Matrix3Xd cgal_result;
  ASSERT_TRUE(RunCgalArap(bend, options.cgal, &cgal, &cgal_result, &error_)) << error_;
  EXPECT_EQ(cgal.arap_energy_ratio, 1.0);
  EXPECT_EQ(cgal.ref_distance_rel, 0.0);
  EXPECT_EQ(cgal.ref_distance_max_rel, 0.0);
  // CGAL's ARAP minimises the same energy under the same constraints, with a
  // fixed number of iterations a frame: not below the converged minimum.
  RunResult cgal_measured;
  ASSERT_TRUE(RunMethod(bend, "cgal_arap", options, "cgal_arap", &reference, &cgal_measured,
                        nullptr, &error_))
      << error_;
  EXPECT_EQ(cgal_measured.arap_energy, cgal.arap_energy);
  EXPECT_GE(cgal_measured.arap_energy_ratio, 1.0 - 1e-6);
  EXPECT_DOUBLE_EQ(cgal_measured.arap_energy_ratio, cgal.arap_energy / first.arap_energy);
  EXPECT_GT(cgal_measured.ref_distance_max_rel, cgal_measured.ref_distance_rel);
}

// Against a reference of known shape: the rest pose (bar_rest's result, every
// method's) against the rest bar scaled by 1.1 about its centre. A uniform
// scale by 1.1 has ARAP energy (1.1 - 1)^2 = 0.01 and the rest pose 0, so the
// ratio is 0; each vertex is 0.1 |x - c| from the reference, so the largest
// distance is that of the bar's corners, 0.1 sqrt(16.5) = 0.05 sqrt(66) (0.05
// of the diagonal), and the mean is 0.1 times the mean distance to the centre.
TEST_F(KnownAnswerTablesTest, DistancesToAScaledReferenceAreKnown) {
  ExperimentScenario rest;
  ASSERT_TRUE(LoadExperimentScenario(*dir_ + "/scenarios/bar_rest.json", 0, &rest, &error_))
      << error_;
  const Eigen::Vector3d centre(4.0, 0.5, 0.5);
  const Eigen::Matrix3Xd& vertices = rest.mesh.vertices;
  const Eigen::Matrix3Xd scaled = (1.1 * (vertices.colwise() - centre)).colwise() + centre;
  RunResult r;
  ASSERT_TRUE(RunMethod(rest, "full_arap", MethodOptions(), "full_arap", &scaled, &r, nullptr,
                        &error_))
      << error_;
  const double diag = std::sqrt(66.0);
  EXPECT_NEAR(r.arap_energy_ratio, 0.0, 1e-12);
  EXPECT_NEAR(r.ref_distance_max_rel, 0.05, 1e-12);
  EXPECT_NEAR(r.ref_distance_rel,
              0.1 * (vertices.colwise() - centre).colwise().norm().mean() / diag, 1e-12);
}

TEST_F(KnownAnswerTablesTest, NodeAndVariableCountsFollowTheClasses) {
  // The lattice cells are smaller than the vertex spacing (a cell's diagonal
  // cell_width sqrt(3) < 0.5), so every vertex has a surface cell of its own:
  // DG1 has one node per vertex, and 138 / P = 100 gives one scale.
  ASSERT_EQ(table1_.rows.size(), 3u);
  for (const std::string scenario : {"bar_translate", "bar_twist", "bar_rest"}) {
    SCOPED_TRACE(scenario);
    auto number = [&](const std::string& column) {
      return Number(table1_, "bar", scenario, column);
    };
    ASSERT_LT(number("cell_width") * std::sqrt(3.0), 0.5);
    EXPECT_EQ(number("vertices"), kVertices);
    EXPECT_EQ(number("faces"), kFaces);
    EXPECT_EQ(number("d1"), kVertices);
    EXPECT_EQ(number("scales_n"), 1);
    EXPECT_EQ(number("selected_scale"), 1);
    EXPECT_EQ(number("scale_nodes"), kVertices);
    const double totally_free = number("totally_free"), half_free = number("half_free");
    EXPECT_EQ(number("nodes_optimized"), totally_free + half_free);
    EXPECT_EQ(number("variables"), 12 * totally_free + 9 * half_free);
    // Table 1 is the run of the first energy, ed.
    EXPECT_EQ(Number(table2_, scenario, "multiscale", "variables", "ed"), number("variables"));
    EXPECT_EQ(Number(table2_, scenario, "multiscale", "nodes_optimized", "ed"),
              number("nodes_optimized"));
    if (scenario != "bar_rest") {
      // No fixed region: every node holds a handle vertex or moves with it
      // (Totally Free), in every method's graph.
      EXPECT_EQ(totally_free, kVertices);
      EXPECT_EQ(half_free, 0);
      for (const char* method : {"multiscale", "static", "static_dense"}) {
        for (const std::string energy : {"ed", "arap"}) {
          if (scenario == "bar_twist" && energy == "arap") continue;  // not run (above)
          EXPECT_EQ(Number(table2_, scenario, method, "nodes_optimized", energy), kVertices)
              << method << " " << energy;
          EXPECT_EQ(Number(table2_, scenario, method, "variables", energy), 12 * kVertices)
              << method << " " << energy;
        }
      }
    } else {
      // Every node that skins a fixed vertex is Fixed (pin_fixed_region):
      // no Half Free node is left, and the fixed end's nodes get no
      // variables.
      EXPECT_EQ(half_free, 0);
      EXPECT_LT(totally_free, kVertices);
    }
  }
}

}  // namespace
}  // namespace msdeform
