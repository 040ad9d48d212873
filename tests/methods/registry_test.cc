#include "msdeform/methods/registry.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

TEST(RegistryTest, ListsEveryMethod) {
  EXPECT_EQ(MethodNames(), (std::vector<std::string>{"multiscale", "static", "static_dense",
                                                      "cgal_arap", "cgal_sr_arap", "fastlsm",
                                                      "rigid_cells"}));
  EXPECT_EQ(MethodNameList(), "multiscale, static, static_dense, cgal_arap, cgal_sr_arap, fastlsm, "
                             "rigid_cells");
}

TEST(RegistryTest, CreatesEachByItsName) {
  for (const std::string& name : MethodNames()) {
    std::string error;
    const std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
    ASSERT_NE(method, nullptr) << name << ": " << error;
    EXPECT_EQ(method->name(), name);
    EXPECT_FALSE(method->precomputed());
    EXPECT_TRUE(IsMethodName(name));
  }
}

TEST(RegistryTest, UnknownNameIsOneLineNamingItAndTheChoices) {
  std::string error;
  EXPECT_EQ(CreateMethod("arap", &error), nullptr);
  EXPECT_EQ(error, "unknown method 'arap' (expected multiscale, static, static_dense, cgal_arap, "
                   "cgal_sr_arap, fastlsm, rigid_cells)");
  EXPECT_EQ(error.find('\n'), std::string::npos);
  EXPECT_FALSE(IsMethodName("arap"));
  EXPECT_FALSE(IsMethodName(""));
}

}  // namespace
}  // namespace msdeform
