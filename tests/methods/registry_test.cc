#include "msdeform/methods/registry.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/methods/method_option_table.h"

namespace msdeform {
namespace {

// The project's methods, registered in this order; a method added later
// comes after them and needs no change here.
// The order is methods/CMakeLists.txt's method_files list.
const std::vector<std::string> kProjectMethods = {
    "multiscale", "static",  "static_dense", "cgal_arap",
    "cgal_sr_arap", "fastlsm", "rigid_cells",  "full_arap"};

TEST(RegistryTest, ListsEveryMethodOnceInRegistrationOrder) {
  const std::vector<std::string> names = MethodNames();
  ASSERT_GE(names.size(), kProjectMethods.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + kProjectMethods.size()),
            kProjectMethods);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  EXPECT_EQ(MethodNameList(), list);
  EXPECT_EQ(MethodNameList().rfind(
                "multiscale, static, static_dense, cgal_arap, cgal_sr_arap, fastlsm, "
                "rigid_cells, full_arap",
                0),
            0u);
}

// The descriptors the front ends read: graph or not, what each minimises,
// the prefix of its own rows (known answers).
TEST(RegistryTest, DescriptorsSayGraphEnergyAndOwnRows) {
  DeformerOptions ed, arap;
  arap.energy = Energy::kArap;
  for (const char* name : {"multiscale", "static", "static_dense"}) {
    const MethodDescriptor* d = FindMethod(name);
    ASSERT_NE(d, nullptr) << name;
    EXPECT_TRUE(d->graph) << name;
    EXPECT_TRUE(IsGraphMethod(name));
    EXPECT_EQ(d->options, "") << name;
    EXPECT_EQ(MinimisedEnergy(name, ed), "ed");
    EXPECT_EQ(MinimisedEnergy(name, arap), "arap");
  }
  const struct {
    const char* name;
    const char* energy;
    const char* options;
  } kOthers[] = {{"cgal_arap", "arap", "cgal"},
                 {"cgal_sr_arap", "sr_arap", "cgal"},
                 {"fastlsm", "shape_matching", "fastlsm"},
                 {"rigid_cells", "rigid_cells", ""},
                 {"full_arap", "arap", "full_arap"}};
  for (const auto& other : kOthers) {
    const MethodDescriptor* d = FindMethod(other.name);
    ASSERT_NE(d, nullptr) << other.name;
    EXPECT_FALSE(d->graph);
    EXPECT_FALSE(IsGraphMethod(other.name));
    EXPECT_EQ(d->energy, other.energy);
    EXPECT_EQ(d->options, other.options);
    EXPECT_EQ(MinimisedEnergy(other.name, arap), other.energy);
  }
  EXPECT_EQ(MinimisedEnergy("no_such_method", ed), "-");
  EXPECT_EQ(FindMethod("no_such_method"), nullptr);
  // The methods' own rows come from the descriptors' prefixes.
  EXPECT_EQ(MethodsOfRow("cgal.iterations"), (std::vector<std::string>{"cgal_arap", "cgal_sr_arap"}));
  EXPECT_EQ(MethodsOfRow("fastlsm.damping"), (std::vector<std::string>{"fastlsm"}));
  EXPECT_EQ(MethodsOfRow("full_arap.max_iterations"), (std::vector<std::string>{"full_arap"}));
  EXPECT_TRUE(MethodsOfRow("w_con").empty());
  for (const MethodDescriptor& d : RegisteredMethods()) {
    if (d.options.empty()) continue;
    bool has_row = false;
    for (const auto& row : MethodOptionTable().rows()) {
      has_row = has_row || row.name.rfind(d.options + ".", 0) == 0;
    }
    EXPECT_TRUE(has_row) << d.name << ": no row " << d.options << ".*";
  }
}

// Which rows each method reads, from the descriptors (known answers): what
// the command line and Python refuse when given for another method.
TEST(RegistryTest, SaysWhichRowsAMethodReads) {
  EXPECT_TRUE(MethodReadsRow("multiscale", "w_con"));
  EXPECT_TRUE(MethodReadsRow("static", "backend"));
  EXPECT_TRUE(MethodReadsRow("multiscale", "lattice.cell_width"));
  EXPECT_FALSE(MethodReadsRow("multiscale", "cgal.iterations"));
  EXPECT_TRUE(MethodReadsRow("cgal_arap", "cgal.iterations"));
  EXPECT_TRUE(MethodReadsRow("cgal_sr_arap", "cgal.sre_alpha"));
  EXPECT_FALSE(MethodReadsRow("cgal_arap", "w_con"));
  EXPECT_FALSE(MethodReadsRow("cgal_arap", "backend"));
  EXPECT_FALSE(MethodReadsRow("cgal_arap", "num_threads"));
  EXPECT_FALSE(MethodReadsRow("cgal_arap", "fastlsm.damping"));
  EXPECT_TRUE(MethodReadsRow("fastlsm", "lattice.cell_width"));
  EXPECT_TRUE(MethodReadsRow("fastlsm", "fastlsm.steps_per_frame"));
  EXPECT_FALSE(MethodReadsRow("fastlsm", "num_threads"));
  EXPECT_TRUE(MethodReadsRow("rigid_cells", "lattice.cell_width"));
  EXPECT_FALSE(MethodReadsRow("rigid_cells", "lattice.cells_per_diagonal"));
  EXPECT_TRUE(MethodReadsRow("rigid_cells", "num_threads"));
  EXPECT_TRUE(MethodReadsRow("full_arap", "num_threads"));
  EXPECT_FALSE(MethodReadsRow("full_arap", "energy"));
  for (const std::string& name : MethodNames()) EXPECT_TRUE(MethodReadsRow(name, "method"));
  EXPECT_FALSE(MethodReadsRow("no_such_method", "method"));
  EXPECT_FALSE(MethodReadsRow("multiscale", "no_such_row"));
  const std::vector<std::string> w_con = MethodsReadingRow("w_con");
  ASSERT_GE(w_con.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(w_con.begin(), w_con.begin() + 3),
            (std::vector<std::string>{"multiscale", "static", "static_dense"}));
  EXPECT_EQ(MethodsReadingRow("fastlsm.damping"), std::vector<std::string>{"fastlsm"});
  // Every descriptor's deformer_rows name rows of the table.
  for (const MethodDescriptor& d : RegisteredMethods()) {
    for (const std::string& row : d.deformer_rows) {
      bool found = false;
      for (const auto& r : MethodOptionTable().rows()) {
        found = found || r.name == row || r.name.rfind(row + ".", 0) == 0;
      }
      EXPECT_TRUE(found) << d.name << ": deformer_rows names no row '" << row << "'";
    }
  }
}

TEST(RegistryTest, CreatesEachByItsName) {
  for (const std::string& name : MethodNames()) {
    std::string error;
    const std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
    ASSERT_NE(method, nullptr) << name << ": " << error;
    EXPECT_EQ(method->name(), name);
    EXPECT_FALSE(method->precomputed());
    EXPECT_TRUE(IsMethodName(name));
    EXPECT_EQ(method->graph_method() == nullptr, !FindMethod(name)->graph) << name;
  }
}

TEST(RegistryTest, UnknownNameIsOneLineNamingItAndTheChoices) {
  std::string error;
  EXPECT_EQ(CreateMethod("arap", &error), nullptr);
  EXPECT_EQ(error, "unknown method 'arap' (expected " + MethodNameList() + ")");
  EXPECT_EQ(error.find('\n'), std::string::npos);
  EXPECT_FALSE(IsMethodName("arap"));
  EXPECT_FALSE(IsMethodName(""));
}

}  // namespace
}  // namespace msdeform
