// The editor's model without a window: it opens inputs as msdeform does and
// gives msdeform's result, its layout changes run SetHandles, its saved
// scenario reads back as the same edit, and inline regions are the scenario's.

#include "apps/editor/edit_session.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "apps/editor/edit_inputs.h"
#include "apps/editor/inline_scenario.h"
#include "apps/editor/saved_edit.h"
#include "tests/editor/editor_test_util.h"
#include "msdeform/core/metrics.h"
#include "msdeform/core/scenario.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace editor {
namespace {

const std::string kMeshes = std::string(MSDEFORM_DATA_DIR) + "/meshes/";

OpenRequest CactusSelDef() {
  OpenRequest request;
  request.mesh = kMeshes + "cactus.off";
  request.sel = kMeshes + "cactus.sel";
  request.def = kMeshes + "cactus.def";
  return request;
}

TEST(EditSessionTest, OpensASelDefPairAsMsdeformDoes) {
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(CactusSelDef(), &inputs, &error)) << error;
  ASSERT_TRUE(inputs.has_layout);
  ASSERT_EQ(inputs.path.size(), 1u);

  // msdeform's steps (apps/msdeform_main.cc): Init, SetHandles, DragAlong.
  GraphMethod reference(Method::kMultiScale);
  ASSERT_TRUE(reference.Precompute(inputs.mesh, DeformerOptions(), &error)) << error;
  ASSERT_TRUE(reference.SetHandles(inputs.layout, &error)) << error;
  DragAlongOptions drag;
  drag.continue_after_failure = true;
  DragLog log;
  ASSERT_TRUE(DragAlong(&reference, inputs.path, drag, &log, &error)) << error;

  EditSession session;
  session.Open(inputs, DeformerOptions());
  session.Wait();
  ASSERT_TRUE(session.error().empty()) << session.error();
  ASSERT_TRUE(session.ready());
  EXPECT_EQ(session.positions(), reference.deformed_vertices());  // bit for bit
  EXPECT_TRUE(session.transform()[0].matrix() == inputs.path.back()[0].matrix());
  EXPECT_EQ(session.layout_timings().size(), 1u);
  EXPECT_TRUE(session.layout_timings()[0].init);
}

// A method by name (issue 28): the session runs any registered method as
// msdeform --method=<name> does, and refuses an unknown name.
TEST(EditSessionTest, RunsAnyRegisteredMethodByName) {
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(CactusSelDef(), &inputs, &error)) << error;
  for (const std::string name : {"cgal_sr_arap", "fastlsm", "static"}) {
    SCOPED_TRACE(name);
    std::unique_ptr<EditingMethod> reference = CreateMethod(name, &error);
    ASSERT_NE(reference, nullptr) << error;
    ASSERT_TRUE(reference->Precompute(inputs.mesh, MethodOptions(), &error)) << error;
    ASSERT_TRUE(reference->SetHandles(inputs.layout, &error)) << error;
    DragAlongOptions drag;
    drag.continue_after_failure = true;
    DragLog log;
    ASSERT_TRUE(DragAlong(reference.get(), inputs.path, drag, &log, &error)) << error;

    EditSession session;
    session.Open(inputs, DeformerOptions());
    session.Wait();
    // Then the method, as a menu choice: Precompute, SetHandles, the pose again.
    ASSERT_TRUE(session.SetMethod(name, &error)) << error;
    session.Wait();
    ASSERT_TRUE(session.ready()) << session.error();
    EXPECT_EQ(session.method_name(), name);
    EXPECT_EQ(session.positions(), reference->deformed_vertices());  // bit for bit
    EXPECT_EQ(session.normals().cols(), inputs.mesh.num_vertices());
    EXPECT_NE(session.Status().find(name), std::string::npos) << session.Status();
    // The per-frame solver is named for a graph method only.
    const bool graph = IsGraphMethod(name);
    for (const std::string& solver : SolverNames().names()) {
      EXPECT_EQ(session.Status().find(solver) != std::string::npos,
                graph && solver == SolverName(session.options().backend))
          << session.Status();
    }
    EXPECT_EQ(MethodReadsDeformerRow(name, "rigidity.model"), graph);
    EXPECT_EQ(MethodReadsDeformerRow(name, "backend"), graph);
    EXPECT_TRUE(MethodReadsDeformerRow(name, "lattice.cell_width"));
    EXPECT_TRUE(MethodReadsDeformerRow(name, "num_threads"));
    EXPECT_EQ(session.graph_method() != nullptr, name == std::string("static"));
  }
  EditSession session;
  EXPECT_FALSE(session.SetMethod("arap", &error));
  EXPECT_EQ(error, "--method=arap: expected " + MethodNameList());
  EXPECT_EQ(session.method_name(), "multiscale");
}

TEST(EditSessionTest, LabelsBecomeALayoutAtCommit) {
  EditSession session;
  ASSERT_NO_FATAL_FAILURE(OpenCactusMesh(&session));
  std::string error;
  EXPECT_FALSE(session.ready());
  EXPECT_EQ(session.positions(), session.mesh().vertices);

  // Fixed only: no handle, nothing to set up.
  std::vector<int> fixed, handle;
  ASSERT_TRUE(SelectInlineRegion({{"slab", {{"axis", "y"}, {"from", 0}, {"to", 0.1}}}},
                                 session.mesh(), "t", &fixed, &error))
      << error;
  session.Label(fixed, VertexLabel::kFixed);
  EXPECT_TRUE(session.layout_pending());
  std::string why;
  EXPECT_FALSE(session.CommitLayout(&why));
  EXPECT_NE(why.find("no moveable handle"), std::string::npos);

  ASSERT_TRUE(SelectInlineRegion({{"sphere", {{"center_vertex", 95}, {"radius_rel", 0.1}}}},
                                 session.mesh(), "t", &handle, &error))
      << error;
  session.Label(handle, VertexLabel::kHandle);
  EXPECT_TRUE(session.CommitLayout(&why));
  session.Wait();
  ASSERT_TRUE(session.ready()) << session.error();
  EXPECT_EQ(session.committed_layout().fixed, fixed);
  EXPECT_EQ(session.committed_layout().moveable, handle);
  EXPECT_EQ(session.layout_timings().size(), 2u);
  EXPECT_FALSE(session.layout_timings()[1].init);  // the deformer was reused

  const Eigen::Vector3d before = session.HandleCentroid();
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translate(Eigen::Vector3d(0, 0.05, 0));
  ASSERT_TRUE(session.Drag(lift, &error)) << error;
  EXPECT_NEAR((session.HandleCentroid() - before).y(), 0.05, 0.005);
  EXPECT_EQ(session.move_timings().size(), 1u);
  // Fixed vertices stay, up to the softness of their Position terms (a tenth
  // of the handle's motion at most).
  for (int v : fixed) {
    EXPECT_LT((session.positions().col(v) - session.mesh().vertices.col(v)).norm(), 0.005);
  }
  // Back to rest: SetHandles again.
  session.ResetPose();
  session.Wait();
  EXPECT_EQ(session.positions(), session.mesh().vertices);
  EXPECT_TRUE(session.transform().IsIdentity());
}

// Polish on release (methods/polish.h): the polished mesh replaces the frame
// when ready (lower ARAP energy, handle and fixed vertices exact), and a drag
// cancels it (the method's own frame is shown).
TEST(EditSessionTest, PolishReplacesTheFrameAndADragCancelsIt) {
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(CactusSelDef(), &inputs, &error)) << error;
  EditSession session;
  session.Open(inputs, DeformerOptions());
  session.Wait();
  ASSERT_TRUE(session.ready()) << session.error();
  const Eigen::Matrix3Xd frame = session.positions();
  const double frame_energy = NormalisedArapEnergy(ArapEnergyPerVertex(session.mesh(), frame));

  PolishOptions options;
  ASSERT_TRUE(session.StartPolish(options));
  session.WaitForPolish();
  ASSERT_TRUE(session.error().empty()) << session.error();
  ASSERT_TRUE(session.showing_polished());
  ASSERT_TRUE(session.has_polish());
  const PolishReport& report = session.last_polish();
  EXPECT_NEAR(report.energy_before, frame_energy, 1e-9 * frame_energy);
  EXPECT_LT(report.energy_after, report.energy_before);
  EXPECT_NEAR(NormalisedArapEnergy(ArapEnergyPerVertex(session.mesh(), session.positions())),
              report.energy_after, 1e-9 * frame_energy);
  EXPECT_GT(report.setup_ms, 0.0);  // the first release for the layout factorises
  for (int v : session.committed_layout().moveable) {
    EXPECT_EQ(session.positions().col(v),
              Eigen::Vector3d(session.transform()[0] * session.mesh().vertices.col(v)));
  }
  for (int v : session.committed_layout().fixed) {
    EXPECT_EQ(session.positions().col(v), session.mesh().vertices.col(v));
  }

  // A polish, then a drag at once: the polish is cancelled (or its result
  // dropped), the method's frame of the drag is shown.
  ASSERT_TRUE(session.StartPolish(options));
  ASSERT_TRUE(session.Drag(session.transform(), &error)) << error;
  EXPECT_FALSE(session.showing_polished());
  const Eigen::Matrix3Xd dragged = session.positions();
  session.WaitForPolish();
  EXPECT_FALSE(session.showing_polished());
  EXPECT_EQ(session.positions(), dragged);
  EXPECT_EQ(session.positions(), session.method()->deformed_vertices());
}

TEST(EditSessionTest, SavedScenarioReadsBackAsTheSameEdit) {
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(CactusSelDef(), &inputs, &error)) << error;
  char folder[] = "/tmp/msdeform_saved_edit_test_XXXXXX";
  ASSERT_NE(mkdtemp(folder), nullptr);
  ScenarioText what;
  what.name = "cactus_edit";
  what.mesh_path = inputs.mesh_path;
  what.scenario_path = std::string(folder) + "/cactus_edit.json";
  what.frames = 7;
  // A rotation about x by 70 degrees and a translation (cactus.def's six-digit
  // matrix is a rotation only to 1e-6, which a scenario cannot state exactly).
  Eigen::Affine3d edit = Eigen::Affine3d::Identity();
  edit.translate(Eigen::Vector3d(0.01, -0.2, 0.3));
  edit.rotate(Eigen::AngleAxisd(70.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  std::string text;
  ASSERT_TRUE(EditScenarioJson(what, inputs.mesh, inputs.layout, edit, &text, &error)) << error;
  std::ofstream(what.scenario_path) << text;
  Scenario scenario;
  ASSERT_TRUE(ReadScenario(what.scenario_path, &scenario, &error)) << error;
  EXPECT_EQ(scenario.name, "cactus_edit");
  EXPECT_EQ(scenario.frames, 7);
  EXPECT_EQ(std::filesystem::canonical(scenario.mesh_path),
            std::filesystem::canonical(inputs.mesh_path));
  HandleLayout layout;
  std::vector<int> watch;
  HandleTransforms transform;
  ASSERT_TRUE(ResolveScenario(scenario, inputs.mesh, &layout, &watch, &transform, &error)) << error;
  EXPECT_EQ(layout.fixed, inputs.layout.fixed);
  EXPECT_EQ(layout.moveable, inputs.layout.moveable);
  EXPECT_LT((transform[0].matrix() - edit.matrix()).cwiseAbs().maxCoeff(), 1e-12);

  // A transform that is not exactly a rotation and a translation cannot be one.
  for (const Eigen::Affine3d& other :
       {Eigen::Affine3d(Eigen::Scaling(1.5)), inputs.path.back()[0]}) {
    EXPECT_FALSE(EditScenarioJson(what, inputs.mesh, inputs.layout, other, &text, &error));
    EXPECT_NE(error.find("save the .sel/.def pair"), std::string::npos) << error;
  }
  std::filesystem::remove_all(folder);
}

TEST(EditSessionTest, InlineRegionsAreTheScenarioReadersWithTheScriptsNames) {
  EditInputs inputs;
  std::string error;
  ASSERT_TRUE(LoadEditInputs(CactusSelDef(), &inputs, &error)) << error;
  std::vector<int> ids;
  EXPECT_FALSE(SelectInlineRegion({{"sphere", {{"center_vertex", 5}, {"radius", "big"}}}},
                                  inputs.mesh, "s.json: actions[2]", &ids, &error));
  EXPECT_EQ(error, "s.json: actions[2].region.sphere.radius: expected a number, found a string");
  EXPECT_FALSE(SelectInlineRegion({{"vertices", {7, 100000}}}, inputs.mesh, "s.json: actions[2]",
                                  &ids, &error));
  EXPECT_EQ(error.rfind("s.json: actions[2].region.vertices[1]: vertex 100000 is outside", 0), 0u)
      << error;
  ASSERT_TRUE(SelectInlineRegion({{"vertices", {9, 3, 9}}}, inputs.mesh, "x", &ids, &error));
  EXPECT_EQ(ids, std::vector<int>({3, 9}));

  std::vector<HandleTransforms> path;
  EXPECT_FALSE(InlineMotionPath({{"translation", {0, 1}}}, 1, inputs.mesh, inputs.layout.moveable,
                                "s.json: actions[4]", &path, &error));
  EXPECT_EQ(error.rfind("s.json: actions[4].transform.translation: expected an array of 3", 0), 0u)
      << error;
  ASSERT_TRUE(InlineMotionPath({{"translation", {0, 1, 0}}}, 4, inputs.mesh, inputs.layout.moveable,
                               "x", &path, &error))
      << error;
  ASSERT_EQ(path.size(), 4u);
  EXPECT_NEAR(path[1][0].translation().y(), 0.5, 1e-12);
}

TEST(EditSessionTest, HandleGroupsArePaintedAndDraggedOneAtATime) {
  EditSession session;
  ASSERT_NO_FATAL_FAILURE(OpenCactusMesh(&session));
  std::string error;
  ASSERT_TRUE(session.SetMethod("full_arap", &error)) << error;  // exact handles
  session.Wait();
  std::vector<int> fixed, left, right;
  ASSERT_TRUE(SelectInlineRegion({{"slab", {{"axis", "x"}, {"from", 0.45}, {"to", 0.55}}}},
                                 session.mesh(), "t", &fixed, &error));
  ASSERT_TRUE(SelectInlineRegion({{"slab", {{"axis", "x"}, {"from", 0}, {"to", 0.1}}}},
                                 session.mesh(), "t", &left, &error));
  ASSERT_TRUE(SelectInlineRegion({{"slab", {{"axis", "x"}, {"from", 0.9}, {"to", 1}}}},
                                 session.mesh(), "t", &right, &error));
  session.Label(fixed, VertexLabel::kFixed);
  session.Label(left, HandleLabel(0));
  session.Label(right, HandleLabel(3));  // labels 0 and 3: layout groups 0 and 1
  ASSERT_TRUE(session.CommitLayout());
  session.Wait();
  ASSERT_TRUE(session.ready()) << session.error();
  const HandleLayout& layout = session.committed_layout();
  EXPECT_EQ(layout.num_groups(), 2);
  EXPECT_EQ(session.LayoutGroupOfLabel(3), 1);
  EXPECT_EQ(session.LayoutGroupOfLabel(1), -1);
  EXPECT_EQ(HandleGroupVertices(layout, 1), right);

  // Group 1 moves, group 0 stays where it is (at rest).
  const Eigen::Affine3d lift(Eigen::Translation3d(0, 0.05, 0));
  ASSERT_TRUE(session.Drag(HandleTransforms({Eigen::Affine3d::Identity(), lift}), &error))
      << error;
  for (int v : right) {
    EXPECT_LT((session.positions().col(v) - lift * session.mesh().vertices.col(v)).norm(), 1e-12);
  }
  for (int v : left) EXPECT_EQ(session.positions().col(v), session.mesh().vertices.col(v));
  // The labels and the layout round-trip, groups included.
  EXPECT_EQ(LayoutFromLabels(LabelsFromLayout(layout, session.mesh().num_vertices())).group,
            layout.group);
}

TEST(EditSessionTest, InputCombinationsGetTheCommandLinesMessages) {
  EditInputs inputs;
  std::string error;
  OpenRequest request = CactusSelDef();
  request.def.clear();
  EXPECT_FALSE(LoadEditInputs(request, &inputs, &error));
  EXPECT_EQ(error, "--sel and --def go together, with --mesh and without --scenario");
  request = CactusSelDef();
  request.frames = -1;
  EXPECT_FALSE(LoadEditInputs(request, &inputs, &error));
  EXPECT_EQ(error, "--frames=-1: expected 0..100000");
  request = OpenRequest();
  request.mesh = kMeshes + "no_such_mesh.off";
  EXPECT_FALSE(LoadEditInputs(request, &inputs, &error));
  EXPECT_NE(error.find("no_such_mesh.off"), std::string::npos) << error;
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
