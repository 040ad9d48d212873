#include "msdeform/core/scenario.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/mesh.h"
#include "msdeform/core/procedural_meshes.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;

// A flat strip: vertex 2i + j sits at (i, j, 0) for i = 0..10, j = 0..1.
// Bounding box [0,10] x [0,1] x [0,0], diagonal sqrt(101).
Mesh Strip() {
  Mesh mesh;
  mesh.vertices.resize(3, 22);
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 1; ++j) mesh.vertices.col(2 * i + j) << i, j, 0;
  }
  mesh.faces.resize(3, 20);
  for (int i = 0; i < 10; ++i) {
    mesh.faces.col(2 * i) << 2 * i, 2 * i + 2, 2 * i + 1;
    mesh.faces.col(2 * i + 1) << 2 * i + 1, 2 * i + 2, 2 * i + 3;
  }
  return mesh;
}

// Reads and resolves a scenario given as JSON text against the strip.
struct Resolved {
  bool ok = false;
  std::string error;
  Scenario scenario;
  HandleLayout layout;
  std::vector<int> watch;
  HandleTransforms transforms;
  Eigen::Affine3d deformed_from_rest = Eigen::Affine3d::Identity();  // transforms[0]
};

Resolved ReadAndResolveOn(const std::string& json, const Mesh& mesh) {
  Resolved result;
  const std::string path = WriteText(FreshFolder() + "/scenario.json", json);
  if (!ReadScenario(path, &result.scenario, &result.error)) return result;
  result.ok = ResolveScenario(result.scenario, mesh, &result.layout, &result.watch,
                              &result.transforms, &result.error);
  result.deformed_from_rest = result.transforms[0];
  return result;
}

Resolved ReadAndResolve(const std::string& json) { return ReadAndResolveOn(json, Strip()); }

// A scenario whose handle is the region given as JSON text.
std::vector<int> SelectHandle(const std::string& region) {
  const Resolved resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": )" + region + "}");
  EXPECT_TRUE(resolved.ok) << resolved.error;
  return resolved.layout.moveable;
}

TEST(ScenarioTest, SlabSelectsAFractionOfTheExtent) {
  EXPECT_EQ(SelectHandle(R"({"slab": {"axis": "x", "from": 0, "to": 0.1}})"),
            (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(SelectHandle(R"({"slab": {"axis": "x", "from": 0.95, "to": 1}})"),
            (std::vector<int>{20, 21}));
  EXPECT_EQ(SelectHandle(R"({"slab": {"axis": "y", "from": 0.5, "to": 1}})"),
            (std::vector<int>{1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21}));
  // A flat extent (z here) selects everything at its one value.
  EXPECT_EQ(SelectHandle(R"({"slab": {"axis": "z", "from": 0, "to": 0}})").size(), 22u);
}

TEST(ScenarioTest, SphereByPointOrVertexAndAbsoluteOrRelativeRadius) {
  // Distance 1 is inside (closed ball), sqrt(2) is not.
  EXPECT_EQ(SelectHandle(R"({"sphere": {"center": [10, 0, 0], "radius": 1}})"),
            (std::vector<int>{18, 20, 21}));
  // radius_rel 0.1 of sqrt(101) is about 1.005.
  EXPECT_EQ(SelectHandle(R"({"sphere": {"center_vertex": 20, "radius_rel": 0.1}})"),
            (std::vector<int>{18, 20, 21}));
}

TEST(ScenarioTest, VertexListIsSortedAndDeduplicated) {
  EXPECT_EQ(SelectHandle(R"({"vertices": [5, 3, 3]})"), (std::vector<int>{3, 5}));
}

TEST(ScenarioTest, AnyIsUnionAndAllIsIntersection) {
  EXPECT_EQ(SelectHandle(R"({"any": [{"vertices": [21]}, {"vertices": [0, 21]}]})"),
            (std::vector<int>{0, 21}));
  EXPECT_EQ(SelectHandle(R"({"all": [{"slab": {"axis": "x", "from": 0, "to": 0.5}},
                                     {"slab": {"axis": "y", "from": 0.5, "to": 1}}]})"),
            (std::vector<int>{1, 3, 5, 7, 9, 11}));
}

TEST(ScenarioTest, NotIsTheComplementInTheMesh) {
  // x < 1 on the strip: the slab keeps x >= 1 (0.1 of the extent).
  EXPECT_EQ(SelectHandle(R"({"not": {"slab": {"axis": "x", "from": 0.1, "to": 1}}})"),
            (std::vector<int>{0, 1}));
  EXPECT_EQ(SelectHandle(R"({"not": {"not": {"vertices": [7, 3]}}})"),
            (std::vector<int>{3, 7}));
}

TEST(ScenarioTest, NotFixesEverythingButALimbOfTheOctahedron) {
  // MakeOctahedron: vertex 0 (1,0,0), 1 (-1,0,0), 2 (0,1,0), 3 (0,-1,0),
  // 4 (0,0,1), 5 (0,0,-1); bounding box [-1, 1]^3. The ball of radius 0.5
  // around vertex 1 holds only vertex 1 (the others are sqrt(2) or 2 away):
  // "everything but it" is fixed, it is the handle.
  const Mesh octahedron = MakeOctahedron();
  Resolved resolved = ReadAndResolveOn(R"({
    "mesh": "m.off",
    "fixed": [{"not": {"sphere": {"center_vertex": 1, "radius": 0.5}}}],
    "handle": {"vertices": [1]}
  })",
                                       octahedron);
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_EQ(resolved.layout.fixed, (std::vector<int>{0, 2, 3, 4, 5}));
  EXPECT_EQ(resolved.layout.moveable, (std::vector<int>{1}));

  // "The upper half but not vertices 2 and 4": z >= 0 is {0, 1, 2, 3, 4}
  // (the slab is closed, z = 0 is its lower face).
  resolved = ReadAndResolveOn(R"({"mesh": "m.off", "handle": {"all": [
      {"slab": {"axis": "z", "from": 0.5, "to": 1}}, {"not": {"vertices": [4, 2]}}]}})",
                              octahedron);
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_EQ(resolved.layout.moveable, (std::vector<int>{0, 1, 3}));
}

TEST(ScenarioTest, FixedIsTheUnionAndWatchIsOptional) {
  Resolved resolved = ReadAndResolve(R"({
    "mesh": "m.off",
    "fixed": [{"vertices": [0, 1]}, {"vertices": [1, 2]}],
    "handle": {"vertices": [21]}
  })");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_EQ(resolved.layout.fixed, (std::vector<int>{0, 1, 2}));
  EXPECT_FALSE(resolved.scenario.has_watch);
  EXPECT_TRUE(resolved.watch.empty());

  resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [21]},
                                "watch": {"vertices": [9, 8]}})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_TRUE(resolved.scenario.has_watch);
  EXPECT_EQ(resolved.watch, (std::vector<int>{8, 9}));
}

TEST(ScenarioTest, RotationAboutTheHandleCentroidThenTranslation) {
  // Handle: the two vertices at x = 10, centroid (10, 0.5, 0). A quarter turn
  // about z through the centroid maps (10, 0, 0) to (10.5, 0.5, 0), then the
  // translation moves it by (1, 0, 1). (Translating first would give
  // (10.5, 1.5, 1).)
  const Resolved resolved = ReadAndResolve(R"({
    "mesh": "m.off",
    "handle": {"vertices": [20, 21]},
    "transform": {"translation": [1, 0, 1],
                  "rotation": {"axis": [0, 0, 2], "angle_deg": 90, "center": "centroid"}}
  })");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  const Eigen::Affine3d& transform = resolved.deformed_from_rest;
  EXPECT_TRUE((transform * Eigen::Vector3d(10, 0, 0)).isApprox(Eigen::Vector3d(11.5, 0.5, 1)));
  EXPECT_TRUE((transform * Eigen::Vector3d(10, 1, 0)).isApprox(Eigen::Vector3d(10.5, 0.5, 1)));
  EXPECT_TRUE((transform * Eigen::Vector3d(0, 0, 0)).isApprox(Eigen::Vector3d(11.5, -9.5, 1)));
}

TEST(ScenarioTest, CentroidIsTheDefaultCentreAndAPointCanBeGiven) {
  Resolved resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [20, 21]},
      "transform": {"rotation": {"axis": [0, 0, 1], "angle_deg": 180}}})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_TRUE((resolved.deformed_from_rest * Eigen::Vector3d(10, 0, 0))
                  .isApprox(Eigen::Vector3d(10, 1, 0)));

  resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [20, 21]},
      "transform": {"rotation": {"axis": [0, 0, 1], "angle_deg": 180, "center": [0, 0, 0]}}})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_TRUE((resolved.deformed_from_rest * Eigen::Vector3d(10, 0, 0))
                  .isApprox(Eigen::Vector3d(-10, 0, 0)));
}

TEST(ScenarioTest, RelativeTranslationIsInBoundingBoxDiagonals) {
  const Resolved resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [0]},
      "transform": {"translation_rel": [0, 0, 0.5]}})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_TRUE(resolved.deformed_from_rest.translation().isApprox(
      Eigen::Vector3d(0, 0, 0.5 * std::sqrt(101.0))));
  EXPECT_TRUE(resolved.deformed_from_rest.linear().isIdentity());
}

TEST(ScenarioTest, DragPathSplitsTheMotionIntoEqualSteps) {
  const Resolved resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [20, 21]},
      "transform": {"translation": [0, 0, 1], "rotation": {"axis": [0, 0, 1], "angle_deg": 90}},
      "frames": 4})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  const std::vector<HandleTransforms> path = DragPath(resolved.scenario, Strip(), resolved.layout);
  ASSERT_EQ(path.size(), 4u);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(path.back()[0].matrix()(r, c), resolved.deformed_from_rest.matrix()(r, c), 1e-12);
    }
  }
  // Frame 2 of 4: 45 degrees about the centroid (10, 0.5, 0), lifted by 0.5.
  const double h = 0.5 * std::sqrt(0.5);
  EXPECT_TRUE(
      (path[1][0] * Eigen::Vector3d(10, 0, 0)).isApprox(Eigen::Vector3d(10 + h, 0.5 - h, 0.5)));
}

TEST(ScenarioTest, SeveralHandlesEachMoveAboutTheirOwnCentroid) {
  const Resolved resolved = ReadAndResolve(R"({"mesh": "m.off",
      "handles": [{"region": {"vertices": [20, 21]},
                   "transform": {"rotation": {"axis": [0, 0, 1], "angle_deg": 90}}},
                  {"region": {"vertices": [1, 0]}, "transform": {"translation": [0, 0, 2]}},
                  {"region": {"vertices": [10]}}],
      "frames": 2})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_EQ(resolved.layout.moveable, (std::vector<int>{0, 1, 10, 20, 21}));
  EXPECT_EQ(resolved.layout.group, (std::vector<int>{1, 1, 2, 0, 0}));
  ASSERT_EQ(resolved.transforms.size(), 3);
  // Group 0 turns about its own centroid (10, 0.5, 0): (10, 0, 0) goes to (10.5, 0.5, 0).
  EXPECT_TRUE((resolved.transforms[0] * Eigen::Vector3d(10, 0, 0))
                  .isApprox(Eigen::Vector3d(10.5, 0.5, 0), 1e-12));
  EXPECT_TRUE(resolved.transforms[1].translation().isApprox(Eigen::Vector3d(0, 0, 2)));
  EXPECT_TRUE(resolved.transforms[2].matrix().isIdentity(0.0));  // no transform: stays
  const std::vector<HandleTransforms> path = DragPath(resolved.scenario, Strip(), resolved.layout);
  ASSERT_EQ(path.size(), 2u);
  EXPECT_TRUE(path[0][1].translation().isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_EQ(path[1][0].matrix(), resolved.transforms[0].matrix());
}

TEST(ScenarioTest, HandlesThatShareAVertexOrMixWithHandleAreErrors) {
  Resolved resolved = ReadAndResolve(R"({"mesh": "m.off",
      "handles": [{"region": {"vertices": [3, 4]}}, {"region": {"vertices": [4, 5]}}]})");
  EXPECT_FALSE(resolved.ok);
  EXPECT_NE(resolved.error.find(": handles[0] and handles[1] share vertex 4 (a vertex follows "
                                "one handle)"),
            std::string::npos)
      << resolved.error;
  resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [3]},
      "handles": [{"region": {"vertices": [4]}}]})");
  EXPECT_FALSE(resolved.ok);
  EXPECT_NE(resolved.error.find(": handle: not allowed with \"handles\""), std::string::npos)
      << resolved.error;
  resolved = ReadAndResolve(R"({"mesh": "m.off", "handles": []})");
  EXPECT_NE(resolved.error.find(": handles: is empty"), std::string::npos) << resolved.error;
  resolved = ReadAndResolve(R"({"mesh": "m.off", "handles": [{"transform": {}}]})");
  EXPECT_NE(resolved.error.find(": handles[0].region: missing"), std::string::npos)
      << resolved.error;
}

TEST(ScenarioTest, DragPathTurnsTheLongWayPastHalfATurn) {
  // 270 degrees about z: the mid frame has turned 135 degrees, not -45 (the
  // short way round that a slerp to the final rotation would take).
  const Resolved resolved = ReadAndResolve(R"({"mesh": "m.off", "handle": {"vertices": [20, 21]},
      "transform": {"rotation": {"axis": [0, 0, 1], "angle_deg": 270}}, "frames": 2})");
  ASSERT_TRUE(resolved.ok) << resolved.error;
  const std::vector<HandleTransforms> path = DragPath(resolved.scenario, Strip(), resolved.layout);
  ASSERT_EQ(path.size(), 2u);
  const Eigen::Matrix3d turn_135 =
      Eigen::AngleAxisd(0.75 * M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT((path[0][0].linear() - turn_135).norm(), 1e-12) << path[0][0].linear();
  // About the centroid (10, 0.5, 0): (10, 0, 0) is 0.5 below it.
  const double h = 0.5 * std::sqrt(0.5);
  EXPECT_TRUE(
      (path[0][0] * Eigen::Vector3d(10, 0, 0)).isApprox(Eigen::Vector3d(10 + h, 0.5 + h, 0), 1e-12));
  EXPECT_EQ(path[1][0].matrix(), resolved.deformed_from_rest.matrix());
}

TEST(ScenarioTest, MeshPathIsRelativeToTheScenarioFolderAndNameDefaultsToStem) {
  const std::string folder = FreshFolder();
  const std::string path =
      WriteText(folder + "/scenarios/bend.json",
                R"({"mesh": "../meshes/bar.off", "handle": {"vertices": [0]}})");
  Scenario scenario;
  std::string error;
  ASSERT_TRUE(ReadScenario(path, &scenario, &error)) << error;
  EXPECT_EQ(fs::path(scenario.mesh_path), fs::path(folder + "/meshes/bar.off").lexically_normal());
  EXPECT_EQ(scenario.name, "bend");
  EXPECT_EQ(scenario.frames, 1);

  WriteText(path, R"({"name": "n", "mesh": "/abs/bar.off", "handle": {"vertices": [0]}})");
  ASSERT_TRUE(ReadScenario(path, &scenario, &error)) << error;
  EXPECT_EQ(scenario.mesh_path, "/abs/bar.off");
  EXPECT_EQ(scenario.name, "n");
}

TEST(ScenarioTest, CommentsAreAllowed) {
  const Resolved resolved = ReadAndResolve(R"({
    // the handle
    "mesh": "m.off",  /* a block comment */
    "handle": {"vertices": [4]}
  })");
  EXPECT_TRUE(resolved.ok) << resolved.error;
}

struct BadScenario {
  const char* name;
  const char* json;
  const char* expected;
};

void PrintTo(const BadScenario& bad, std::ostream* out) { *out << bad.name; }

class BadScenarioTest : public testing::TestWithParam<BadScenario> {};

TEST_P(BadScenarioTest, FailsNamingTheFileAndTheField) {
  const BadScenario& bad = GetParam();
  const Resolved resolved = ReadAndResolve(bad.json);
  EXPECT_FALSE(resolved.ok);
  EXPECT_NE(resolved.error.find("scenario.json: "), std::string::npos) << resolved.error;
  EXPECT_NE(resolved.error.find(bad.expected), std::string::npos) << resolved.error;
  EXPECT_EQ(resolved.error.find('\n'), std::string::npos) << resolved.error;
}

INSTANTIATE_TEST_SUITE_P(
    ReadErrors, BadScenarioTest,
    testing::Values(
        BadScenario{"radius_string",
                    R"({"mesh": "m.off", "fixed": [{"vertices": [0]},
                        {"sphere": {"center": [0, 0, 0], "radius": "big"}}],
                        "handle": {"vertices": [1]}})",
                    "fixed[1].sphere.radius: expected a number, found a string"},
        BadScenario{"missing_handle", R"({"mesh": "m.off"})", "handle: missing"},
        BadScenario{"missing_mesh", R"({"handle": {"vertices": [1]}})", "mesh: missing"},
        BadScenario{"unknown_field",
                    R"({"mesh": "m.off", "fixd": [], "handle": {"vertices": [1]}})",
                    "fixd: unknown field"},
        BadScenario{"two_kinds", R"({"mesh": "m.off", "handle": {"vertices": [1], "any": []}})",
                    "handle: a region needs exactly one of"},
        BadScenario{"unknown_kind", R"({"mesh": "m.off", "handle": {"box": {}}})",
                    "handle.box: unknown field"},
        BadScenario{"bad_axis",
                    R"({"mesh": "m.off", "handle": {"slab": {"axis": "w", "from": 0, "to": 1}}})",
                    "handle.slab.axis: expected \"x\", \"y\" or \"z\""},
        BadScenario{"slab_missing_to",
                    R"({"mesh": "m.off", "handle": {"slab": {"axis": "x", "from": 0}}})",
                    "handle.slab.to: missing"},
        BadScenario{"slab_backwards",
                    R"({"mesh": "m.off", "handle": {"slab": {"axis": "x", "from": 1, "to": 0}}})",
                    "handle.slab: from must not exceed to"},
        BadScenario{"two_centres",
                    R"({"mesh": "m.off", "handle": {"sphere": {"center": [0, 0, 0],
                        "center_vertex": 1, "radius": 1}}})",
                    "handle.sphere: needs exactly one of center, center_vertex"},
        BadScenario{"fractional_id", R"({"mesh": "m.off", "handle": {"vertices": [1, 1.5]}})",
                    "handle.vertices[1]: expected an integer"},
        BadScenario{"negative_id", R"({"mesh": "m.off", "handle": {"vertices": [-1]}})",
                    "handle.vertices[0]: vertex ids are 0 or more"},
        BadScenario{"frames_zero", R"({"mesh": "m.off", "handle": {"vertices": [1]}, "frames": 0})",
                    "frames: must be at least 1"},
        BadScenario{"frames_string",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]}, "frames": "ten"})",
                    "frames: expected an integer, found a string"},
        BadScenario{"zero_axis",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "transform": {"rotation": {"axis": [0, 0, 0], "angle_deg": 10}}})",
                    "transform.rotation.axis: must have a finite, non-zero length"},
        BadScenario{"huge_axis",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "transform": {"rotation": {"axis": [1e300, 1e300, 1e300],
                                                   "angle_deg": 10}}})",
                    "transform.rotation.axis: must have a finite, non-zero length"},
        BadScenario{"bad_centre",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "transform": {"rotation": {"axis": [0, 0, 1], "angle_deg": 10,
                                                   "center": "middle"}}})",
                    "transform.rotation.center: expected [x, y, z] or \"centroid\""},
        BadScenario{"short_translation",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "transform": {"translation": [0, 1]}})",
                    "transform.translation: expected an array of 3 numbers"},
        BadScenario{"both_translations",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "transform": {"translation": [0, 1, 0], "translation_rel": [0, 1, 0]}})",
                    "transform: give translation or translation_rel, not both"},
        BadScenario{"empty_all",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "watch": {"any": [{"vertices": [0]}, {"all": []}]}})",
                    "watch.any[1].all: needs at least one region"},
        BadScenario{"not_of_a_list",
                    R"({"mesh": "m.off", "handle": {"not": [{"vertices": [1]}]}})",
                    "handle.not: expected a region, found an array"},
        BadScenario{"not_of_nothing", R"({"mesh": "m.off", "handle": {"not": {}}})",
                    "handle.not: a region needs exactly one of"},
        BadScenario{"not_of_a_bad_region",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "fixed": [{"not": {"slab": {"axis": "x", "from": 0}}}]})",
                    "fixed[0].not.slab.to: missing"},
        BadScenario{"not_an_object", R"([1, 2])", "expected an object, found an array"},
        BadScenario{"syntax", "{\"mesh\": \"m.off\",\n \"handle\": }",
                    "invalid JSON: parse error at line 2"}),
    [](const testing::TestParamInfo<BadScenario>& info) { return std::string(info.param.name); });

INSTANTIATE_TEST_SUITE_P(
    ResolveErrors, BadScenarioTest,
    testing::Values(
        BadScenario{
            "empty_sphere",
            R"({"mesh": "m.off", "handle": {"sphere": {"center": [5, 5, 5], "radius": 1}}})",
            "handle: sphere of radius 1 around (5, 5, 5) selects no vertex"},
        BadScenario{"empty_nested",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "fixed": [{"any": [{"vertices": [0]},
                                           {"slab": {"axis": "x", "from": 2, "to": 3}}]}]})",
                    "fixed[0].any[1]: slab x from 2 to 3"},
        BadScenario{
            "empty_intersection",
            R"({"mesh": "m.off", "handle": {"all": [{"vertices": [0]}, {"vertices": [1]}]}})",
            "handle: intersection of its regions selects no vertex"},
        BadScenario{"not_everything",
                    R"({"mesh": "m.off", "handle": {"vertices": [1]},
                        "fixed": [{"not": {"slab": {"axis": "y", "from": 0, "to": 1}}}]})",
                    "fixed[0]: complement of its region selects no vertex of the mesh"},
        BadScenario{"not_of_an_empty_region",
                    R"({"mesh": "m.off",
                        "handle": {"not": {"sphere": {"center": [5, 5, 5], "radius": 1}}}})",
                    "handle.not: sphere of radius 1 around (5, 5, 5) selects no vertex"},
        BadScenario{"not_out_of_range",
                    R"({"mesh": "m.off", "handle": {"not": {"vertices": [0, 22]}}})",
                    "handle.not.vertices[1]: vertex 22 is outside the mesh's 0..21"},
        BadScenario{"id_out_of_range", R"({"mesh": "m.off", "handle": {"vertices": [1, 2, 99]}})",
                    "handle.vertices[2]: vertex 99 is outside the mesh's 0..21"},
        BadScenario{
            "centre_out_of_range",
            R"({"mesh": "m.off", "handle": {"sphere": {"center_vertex": 22, "radius": 1}}})",
            "handle.sphere.center_vertex: vertex 22 is outside"},
        BadScenario{"overlap",
                    R"({"mesh": "m.off", "fixed": [{"vertices": [0, 1]}],
                        "handle": {"vertices": [1, 2]}})",
                    "vertex 1 is both fixed and moveable"}),
    [](const testing::TestParamInfo<BadScenario>& info) { return std::string(info.param.name); });

// A handle region of `depth` nested "not"s around one vertex.
std::string NestedNot(int depth) {
  std::string region = R"({"vertices": [1]})";
  for (int i = 0; i < depth; ++i) region = R"({"not": )" + region + "}";
  return R"({"mesh": "m.off", "handle": )" + region + "}";
}

TEST(ScenarioTest, RegionsNestUpToTheLimit) {
  // An even number of "not"s selects the vertex itself.
  const Resolved resolved = ReadAndResolve(NestedNot(kMaxRegionDepth));
  ASSERT_TRUE(resolved.ok) << resolved.error;
  EXPECT_EQ(resolved.layout.moveable, std::vector<int>({1}));
}

TEST(ScenarioTest, DeeperRegionsAreRefusedNotRecursedInto) {
  // 20000 levels overflowed the stack of the recursive parser.
  for (int depth : {kMaxRegionDepth + 1, 20000}) {
    const Resolved resolved = ReadAndResolve(NestedNot(depth));
    EXPECT_FALSE(resolved.ok);
    EXPECT_NE(resolved.error.find("scenario.json: handle.not.not"), std::string::npos)
        << resolved.error;
    EXPECT_NE(resolved.error.find("regions nest more than 64 deep"), std::string::npos)
        << resolved.error;
    EXPECT_LT(resolved.error.size(), 200u) << resolved.error;
  }
}

// On a mesh of more than one chunk of vertices (76,500), the regions, the
// transform and the drag path are the same on 1, 2 and 3 threads, and the
// regions are those a plain walk over the vertices selects.
TEST(ScenarioTest, SameRegionsAndPathAtAnyThreadCount) {
  const Mesh sphere = MakeSphere(2.0, 300, 256);
  ASSERT_GT(sphere.num_vertices(), 70000);
  const std::string path = WriteText(FreshFolder() + "/scenario.json", R"({
    "mesh": "m.off",
    "fixed": [{"slab": {"axis": "y", "from": 0, "to": 0.1}}],
    "handle": {"all": [{"sphere": {"center_vertex": 70000, "radius_rel": 0.3}},
                       {"not": {"slab": {"axis": "z", "from": 0, "to": 0.5}}}]},
    "watch": {"not": {"sphere": {"center": [0, 2, 0], "radius": 1.5}}},
    "transform": {"translation_rel": [0.1, 0.2, 0.0]},
    "frames": 5})");
  Scenario scenario;
  std::string error;
  ASSERT_TRUE(ReadScenario(path, &scenario, &error)) << error;
  HandleLayout reference;
  std::vector<int> reference_watch;
  HandleTransforms reference_transform;
  ASSERT_TRUE(ResolveScenario(scenario, sphere, &reference, &reference_watch,
                              &reference_transform, &error, 1))
      << error;
  const std::vector<HandleTransforms> reference_path = DragPath(scenario, sphere, reference, 1);

  // The plain walk: the fixed slab and the watched vertices.
  const Eigen::AlignedBox3d box = BoundingBox(sphere);
  const double low = box.min().y(), extent = box.max().y() - box.min().y();
  std::vector<int> slab, outside;
  for (int v = 0; v < sphere.num_vertices(); ++v) {
    const double y = sphere.vertices(1, v);
    if (y >= low - 1e-9 * extent && y <= low + 0.1 * extent + 1e-9 * extent) slab.push_back(v);
    if ((sphere.vertices.col(v) - Eigen::Vector3d(0, 2, 0)).squaredNorm() > 1.5 * 1.5) {
      outside.push_back(v);
    }
  }
  EXPECT_EQ(reference.fixed, slab);
  EXPECT_EQ(reference_watch, outside);
  EXPECT_FALSE(reference.moveable.empty());

  for (int threads : {2, 3}) {
    HandleLayout layout;
    std::vector<int> watch;
    HandleTransforms transform;
    ASSERT_TRUE(ResolveScenario(scenario, sphere, &layout, &watch, &transform, &error, threads))
        << error;
    EXPECT_EQ(layout.fixed, reference.fixed) << threads;
    EXPECT_EQ(layout.moveable, reference.moveable) << threads;
    EXPECT_EQ(watch, reference_watch) << threads;
    EXPECT_EQ(transform[0].matrix(), reference_transform[0].matrix()) << threads;
    const std::vector<HandleTransforms> drag = DragPath(scenario, sphere, layout, threads);
    ASSERT_EQ(drag.size(), reference_path.size());
    for (size_t k = 0; k < drag.size(); ++k) {
      EXPECT_EQ(drag[k][0].matrix(), reference_path[k][0].matrix()) << threads << " " << k;
    }
  }
}

TEST(ScenarioTest, MissingFileNamesIt) {
  const std::string path = FreshFolder() + "/none.json";
  Scenario scenario;
  std::string error;
  EXPECT_FALSE(ReadScenario(path, &scenario, &error));
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
}

}  // namespace
}  // namespace msdeform
