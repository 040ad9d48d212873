#include "msdeform/core/handles.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace msdeform {
namespace {

TEST(HandlesTest, ReadSelSplitsStatusesIntoFixedAndMoveable) {
  const std::string path =
      WriteText(FreshFolder() + "/six.sel",
                "# per vertex status: 0=fixed, 1=deformable-region, 2=handle\n"
                "# 6 vertices\n"
                "1\n0\n2\n  0  \n\n2\r\n1\n");
  HandleLayout layout;
  std::string error;
  ASSERT_TRUE(ReadSel(path, 6, &layout, &error)) << error;
  EXPECT_EQ(layout.fixed, (std::vector<int>{1, 3}));
  EXPECT_EQ(layout.moveable, (std::vector<int>{2, 4}));
}

TEST(HandlesTest, ReadSelWithoutACountTakesTheFiles) {
  const std::string path =
      WriteText(FreshFolder() + "/six.sel", "# 6 vertices\n1\n0\n2\n  0  \n\n2\r\n1\n");
  HandleLayout layout;
  int num_vertices = 0;
  std::string error;
  ASSERT_TRUE(ReadSel(path, &layout, &num_vertices, &error)) << error;
  EXPECT_EQ(num_vertices, 6);
  EXPECT_EQ(layout.fixed, (std::vector<int>{1, 3}));
  EXPECT_EQ(layout.moveable, (std::vector<int>{2, 4}));
  // The other checks stay: a bad status, no handle.
  const std::string bad = WriteText(FreshFolder() + "/bad.sel", "0\n3\n");
  EXPECT_FALSE(ReadSel(bad, &layout, &num_vertices, &error));
  EXPECT_NE(error.find("line 2: status 3 for vertex 1"), std::string::npos) << error;
  const std::string none = WriteText(FreshFolder() + "/none.sel", "0\n1\n");
  EXPECT_FALSE(ReadSel(none, &layout, &num_vertices, &error));
  EXPECT_NE(error.find("no handle vertex"), std::string::npos) << error;
}

struct BadSel {
  const char* name;
  const char* contents;
  int num_vertices;
  const char* expected;
};

void PrintTo(const BadSel& bad, std::ostream* out) { *out << bad.name; }

class BadSelTest : public testing::TestWithParam<BadSel> {};

TEST_P(BadSelTest, FailsNamingFileAndProblem) {
  const BadSel& bad = GetParam();
  const std::string path = WriteText(FreshFolder() + "/" + bad.name, bad.contents);
  HandleLayout layout;
  std::string error;
  EXPECT_FALSE(ReadSel(path, bad.num_vertices, &layout, &error));
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_NE(error.find(bad.expected), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Errors, BadSelTest,
    testing::Values(BadSel{"too_few", "# c\n0\n2\n", 3, "has 2 statuses but the mesh has 3"},
                    BadSel{"too_many", "0\n2\n1\n1\n", 3, "line 4: more statuses"},
                    BadSel{"status_three", "0\n3\n2\n", 3, "line 2: status 3 for vertex 1"},
                    BadSel{"negative", "0\n-1\n2\n", 3, "line 2: status -1"},
                    BadSel{"junk", "# c\n0\nfixed\n2\n", 3,
                           "line 3: 'fixed' is not a vertex status"},
                    BadSel{"two_per_line", "0 2\n1\n", 3, "line 1: expected one status"},
                    BadSel{"fraction", "0\n1.5\n2\n", 3, "line 2: '1.5' is not"},
                    BadSel{"no_handle", "0\n1\n0\n", 3, "no handle vertex"}),
    [](const testing::TestParamInfo<BadSel>& info) { return std::string(info.param.name); });

TEST(HandlesTest, ReadSelOfMissingFileFails) {
  const std::string path = FreshFolder() + "/missing.sel";
  HandleLayout layout;
  std::string error;
  EXPECT_FALSE(ReadSel(path, 3, &layout, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
}

TEST(HandlesTest, WriteSelRoundTrips) {
  const std::string path = FreshFolder() + "/out.sel";
  HandleLayout layout;
  layout.fixed = {0, 4, 5};
  layout.moveable = {2, 6};
  std::string error;
  ASSERT_TRUE(WriteSel(path, layout, 8, &error)) << error;
  HandleLayout read;
  ASSERT_TRUE(ReadSel(path, 8, &read, &error)) << error;
  EXPECT_EQ(read.fixed, layout.fixed);
  EXPECT_EQ(read.moveable, layout.moveable);
}

TEST(HandlesTest, WriteSelRefusesAnInvalidLayout) {
  const std::string folder = FreshFolder();
  HandleLayout layout;
  layout.fixed = {1};
  layout.moveable = {1};
  std::string error;
  EXPECT_FALSE(WriteSel(folder + "/bad.sel", layout, 3, &error));
  EXPECT_NE(error.find("both fixed and moveable"), std::string::npos) << error;
  EXPECT_FALSE(std::ifstream(folder + "/bad.sel").good());
}

TEST(HandlesTest, ValidateHandlesNamesTheProblem) {
  std::string error;
  HandleLayout layout;
  layout.fixed = {0, 1};
  layout.moveable = {3};
  EXPECT_TRUE(ValidateHandles(layout, 4, &error)) << error;

  layout.moveable = {4};
  EXPECT_FALSE(ValidateHandles(layout, 4, &error));
  EXPECT_NE(error.find("vertex 4 is outside 0..3"), std::string::npos) << error;

  layout.moveable = {};
  EXPECT_FALSE(ValidateHandles(layout, 4, &error));
  EXPECT_NE(error.find("no vertex"), std::string::npos) << error;

  layout.moveable = {1, 2};
  EXPECT_FALSE(ValidateHandles(layout, 4, &error));
  EXPECT_NE(error.find("vertex 1 is both fixed and moveable"), std::string::npos) << error;

  layout.moveable = {3, 2};
  EXPECT_FALSE(ValidateHandles(layout, 4, &error));
  EXPECT_NE(error.find("sorted"), std::string::npos) << error;
}

// cactus.def from CGAL's Surface_mesh_deformation example.
constexpr char kCactusDef[] =
    "# 4x4 handle transformation matrix\n"
    "0.999641 0.021031 0.016579 -0.019322\n"
    "-0.022776 0.342021 0.939416 -0.134331\n"
    "0.014087 -0.939457 0.342378 0.821073\n"
    "0.000000 0.000000 0.000000 1.000000\n";

TEST(HandlesTest, ReadDefReadsRowByRow) {
  const std::string path = WriteText(FreshFolder() + "/cactus.def", kCactusDef);
  Eigen::Affine3d transform;
  std::string error;
  ASSERT_TRUE(ReadDef(path, &transform, &error)) << error;
  EXPECT_DOUBLE_EQ(transform.matrix()(0, 1), 0.021031);
  EXPECT_DOUBLE_EQ(transform.matrix()(1, 0), -0.022776);
  EXPECT_DOUBLE_EQ(transform.translation().z(), 0.821073);
  // Applying it moves the origin to the translation column.
  EXPECT_TRUE((transform * Eigen::Vector3d::Zero())
                  .isApprox(Eigen::Vector3d(-0.019322, -0.134331, 0.821073)));
}

TEST(HandlesTest, WriteDefRoundTripsExactly) {
  const std::string path = FreshFolder() + "/out.def";
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  transform.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  transform.pretranslate(Eigen::Vector3d(0.1, -2.0 / 3.0, 5));
  std::string error;
  ASSERT_TRUE(WriteDef(path, transform, &error)) << error;
  Eigen::Affine3d read;
  ASSERT_TRUE(ReadDef(path, &read, &error)) << error;
  EXPECT_EQ(read.matrix(), transform.matrix());
}

struct BadDef {
  const char* name;
  const char* contents;
  const char* expected;
};

void PrintTo(const BadDef& bad, std::ostream* out) { *out << bad.name; }

class BadDefTest : public testing::TestWithParam<BadDef> {};

TEST_P(BadDefTest, FailsNamingFileAndProblem) {
  const BadDef& bad = GetParam();
  const std::string path = WriteText(FreshFolder() + "/" + bad.name, bad.contents);
  Eigen::Affine3d transform;
  std::string error;
  EXPECT_FALSE(ReadDef(path, &transform, &error));
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_NE(error.find(bad.expected), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Errors, BadDefTest,
    testing::Values(
        BadDef{"fifteen", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0\n", "has 15 numbers"},
        BadDef{"seventeen", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1 7\n", "line 4: more than 16"},
        BadDef{"junk", "1 0 0 0\n0 1 zero 0\n0 0 1 0\n0 0 0 1\n", "line 2: 'zero' is not a number"},
        BadDef{"nan", "1 0 0 0\n0 1 0 nan\n0 0 1 0\n0 0 0 1\n",
               "line 2: matrix entry 'nan' is not finite"},
        BadDef{"projective", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0.5 1\n", "expected 0 0 0 1"},
        BadDef{"empty", "# only a comment\n", "has 0 numbers"}),
    [](const testing::TestParamInfo<BadDef>& info) { return std::string(info.param.name); });

// The two sorted lists merged by vertex id, each entry marked with its
// handle group, or -1 for fixed; hand-merged answer.
TEST(HandlesTest, ConstrainedVerticesMergesMoveableAndFixedInOrder) {
  HandleLayout layout;
  layout.moveable = {2, 5, 9};
  layout.group = {0, 1, 0};
  layout.fixed = {0, 3, 4, 10};
  std::vector<int> constrained = {7};  // replaced, not appended to
  std::vector<int> handle_group;
  ConstrainedVertices(layout, &constrained, &handle_group);
  EXPECT_EQ(constrained, (std::vector<int>{0, 2, 3, 4, 5, 9, 10}));
  EXPECT_EQ(handle_group, (std::vector<int>{-1, 0, -1, -1, 1, 0, -1}));

  // Each group goes to its own transform, the fixed ones stay at rest.
  Eigen::Matrix3Xd rest = Eigen::Matrix3Xd::Zero(3, 11);
  for (int v = 0; v < 11; ++v) rest.col(v) = Eigen::Vector3d(v, 0, 0);
  const Eigen::Affine3d up(Eigen::Translation3d(0, 1, 0)), down(Eigen::Translation3d(0, -2, 0));
  const Eigen::Matrix3Xd targets =
      ConstrainedTargets(rest, constrained, handle_group, HandleTransforms({up, down}));
  EXPECT_EQ(targets.col(1), Eigen::Vector3d(2, 1, 0));   // vertex 2, group 0
  EXPECT_EQ(targets.col(4), Eigen::Vector3d(5, -2, 0));  // vertex 5, group 1
  EXPECT_EQ(targets.col(2), Eigen::Vector3d(3, 0, 0));   // vertex 3, fixed
  // One transform moves every group.
  const Eigen::Matrix3Xd together = ConstrainedTargets(rest, constrained, handle_group, up);
  EXPECT_EQ(together.col(4), Eigen::Vector3d(5, 1, 0));
}

TEST(HandlesTest, HandleGroupsAreValidated) {
  HandleLayout layout;
  layout.moveable = {2, 5, 9};
  std::string error;
  EXPECT_EQ(layout.num_groups(), 1);
  layout.group = {0, 1, 0};
  ASSERT_TRUE(ValidateHandles(layout, 11, &error)) << error;
  EXPECT_EQ(layout.num_groups(), 2);
  EXPECT_EQ(layout.GroupOfVertex(5), 1);
  EXPECT_EQ(layout.GroupOfVertex(9), 0);
  EXPECT_EQ(layout.GroupOfVertex(4), -1);

  layout.group = {0, 1};
  EXPECT_FALSE(ValidateHandles(layout, 11, &error));
  EXPECT_EQ(error, "the handle groups list 2 entries for 3 moveable vertices");
  layout.group = {0, 2, 0};
  EXPECT_FALSE(ValidateHandles(layout, 11, &error));
  EXPECT_EQ(error, "handle group 1 has no vertex (groups are 0..2, each used)");
  layout.group = {0, -1, 0};
  EXPECT_FALSE(ValidateHandles(layout, 11, &error));
  EXPECT_EQ(error, "moveable vertex 5 has handle group -1, outside 0..63");

  // Transforms: one for all groups, or one a group.
  layout.group = {0, 1, 0};
  EXPECT_TRUE(HandleTransforms(Eigen::Affine3d::Identity()).Fits(layout, &error));
  EXPECT_TRUE(HandleTransforms({Eigen::Affine3d::Identity(), Eigen::Affine3d::Identity()})
                  .Fits(layout, &error));
  const HandleTransforms three(std::vector<Eigen::Affine3d>(3, Eigen::Affine3d::Identity()));
  EXPECT_FALSE(three.Fits(layout, &error));
  EXPECT_EQ(error, "3 handle transforms for a layout of 2 handle groups (give one, or one a group)");
  Eigen::Affine3d bad = Eigen::Affine3d::Identity();
  bad(0, 3) = std::nan("");
  EXPECT_FALSE(HandleTransforms({Eigen::Affine3d::Identity(), bad}).CheckFinite(&error));
  EXPECT_EQ(error, "the transform of handle group 1 is not finite");
}

// Per-vertex targets: a rigid motion of a flat group (coplanar: no unique
// affine map) and an affine map of a solid one are found exactly; targets
// that bend a group are refused, naming it.
TEST(HandlesTest, TargetsBecomeEachGroupsRigidOrAffineMap) {
  Eigen::Matrix3Xd rest(3, 9);
  rest << 0, 1, 0, 1, 5, 6, 5, 5, 6,  // group 0 a flat square, group 1 a solid
      0, 0, 1, 1, 0, 0, 1, 0, 1,      //
      0, 0, 0, 0, 0, 0, 0, 1, 1;
  HandleLayout layout;
  layout.moveable = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  layout.group = {0, 0, 0, 0, 1, 1, 1, 1, 1};
  Eigen::Affine3d turn = Eigen::Affine3d::Identity();
  turn.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  turn.pretranslate(Eigen::Vector3d(0.5, -1, 2));
  Eigen::Affine3d stretch = Eigen::Affine3d::Identity();
  stretch.linear() << 2, 0.5, 0, 0, 1, 0, 0, 0.25, 3;
  stretch.translation() = Eigen::Vector3d(1, 1, 1);
  Eigen::Matrix3Xd targets(3, 9);
  for (int i = 0; i < 9; ++i) {
    targets.col(i) = (i < 4 ? turn : stretch) * Eigen::Vector3d(rest.col(i));
  }
  HandleTransforms fitted;
  std::string error;
  ASSERT_TRUE(HandleTransformsFromTargets(rest, layout, targets, 1e-9, &fitted, &error)) << error;
  ASSERT_EQ(fitted.size(), 2);
  EXPECT_LT((fitted[0].matrix() - turn.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((fitted[1].matrix() - stretch.matrix()).cwiseAbs().maxCoeff(), 1e-12);

  targets(2, 5) += 0.1;  // group 1 no longer moves as one piece
  EXPECT_FALSE(HandleTransformsFromTargets(rest, layout, targets, 1e-9, &fitted, &error));
  EXPECT_EQ(error.rfind("the targets of handle group 1 are no affine map", 0), 0u) << error;
  EXPECT_FALSE(HandleTransformsFromTargets(rest, layout, targets.leftCols(8), 1e-9, &fitted,
                                           &error));
  EXPECT_EQ(error, "8 targets for 9 moveable vertices");
}

// A group on a line leaves the spin about it free: a translation of it is
// fitted with no rotation, and a turn of the line by the least rotation.
TEST(HandlesTest, TargetsOfAGroupOnALineGetTheLeastRotation) {
  Eigen::Matrix3Xd rest(3, 3);
  rest << 0, 1, 2,  //
      0, 0, 0,      //
      0, 0, 0;
  HandleLayout layout;
  layout.moveable = {0, 1, 2};
  HandleTransforms fitted;
  std::string error;
  const Eigen::Vector3d shift(0.5, -1.0, 2.0);
  ASSERT_TRUE(HandleTransformsFromTargets(rest, layout, rest.colwise() + shift, 1e-9, &fitted,
                                          &error))
      << error;
  EXPECT_LT((fitted[0].linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((fitted[0].translation() - shift).norm(), 1e-12);
  // The line turned onto the y axis: a quarter turn about z.
  Eigen::Matrix3Xd turned(3, 3);
  turned << 0, 0, 0,  //
      0, 1, 2,        //
      0, 0, 0;
  ASSERT_TRUE(HandleTransformsFromTargets(rest, layout, turned, 1e-9, &fitted, &error)) << error;
  const Eigen::Matrix3d quarter =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT((fitted[0].linear() - quarter).norm(), 1e-12);
}

// A .sel file holds one group: a layout of two is refused, no file written.
TEST(HandlesTest, WriteSelRefusesSeveralHandleGroups) {
  HandleLayout layout;
  layout.moveable = {2, 5};
  layout.group = {0, 1};
  const std::string path = ::testing::TempDir() + "/two_groups.sel";
  std::remove(path.c_str());
  std::string error;
  EXPECT_FALSE(WriteSel(path, layout, 11, &error));
  EXPECT_EQ(error, path + ": a .sel file holds one handle group; this layout has 2 (save a "
                          "scenario instead)");
  EXPECT_FALSE(std::ifstream(path).good());
}

}  // namespace
}  // namespace msdeform
