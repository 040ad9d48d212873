// The mesh-only stage (scales/precompute.h): refused inputs, and set-ups made
// from several threads at once on one precompute (its graph cache and rigidity
// estimator behind locks). That GraphMethod's Precompute builds the same data:
// tests/methods/graph_method_test.cc.

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/session.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

TEST(PrecomputeTest, BadOptionsOrMeshAreRefusedWithAMessage) {
  const CylinderLayouts cylinder;
  std::string error;
  DeformerOptions options = CylinderOptions(Method::kMultiScale);
  options.w_con = 0.0;
  EXPECT_EQ(Precompute::Create(cylinder.mesh, options, &error), nullptr);
  EXPECT_NE(error.find("w_con"), std::string::npos) << error;
  Mesh broken = cylinder.mesh;
  broken.faces(0, 0) = broken.num_vertices();
  error.clear();
  EXPECT_EQ(Precompute::Create(broken, CylinderOptions(Method::kMultiScale), &error), nullptr);
  EXPECT_FALSE(error.empty());
}

// Pinned graphs stay connected beyond cached_scales; once the pins are gone
// the cache is back within its bound.
TEST(PrecomputeTest, PinsHoldGraphsBeyondTheBoundUntilReleased) {
  const CylinderLayouts cylinder;
  DeformerOptions options = CylinderOptions(Method::kMultiScale);
  options.cached_scales = 1;
  std::string error;
  std::shared_ptr<const Precompute> precompute =
      Precompute::Create(cylinder.mesh, options, &error);
  ASSERT_NE(precompute, nullptr) << error;
  ASSERT_GE(precompute->graphs().size(), 4u);
  auto num_connected = [&precompute] {
    int connected = 0;
    for (size_t i = 1; i < precompute->graphs().size(); ++i) {
      connected += precompute->graphs()[i].is_connected();
    }
    return connected;
  };
  {
    const Precompute::GraphPin first = precompute->ConnectAndPin(1);
    const Precompute::GraphPin second = precompute->ConnectAndPin(2);
    precompute->ConnectedGraph(3);
    EXPECT_TRUE(precompute->graphs()[1].is_connected());
    EXPECT_TRUE(precompute->graphs()[2].is_connected());
    EXPECT_EQ(num_connected(), 3);
  }
  EXPECT_EQ(num_connected(), 1);
}

// Layouts and sessions made in four threads at once on one precompute (two
// layouts, each twice, one cached coarse scale) drag as they do made one
// after another.
TEST(PrecomputeTest, LayoutsFromSeveralThreadsMatchSerialOnes) {
  const CylinderLayouts cylinder;
  DeformerOptions options = CylinderOptions(Method::kMultiScale);
  options.cached_scales = 1;
  const std::vector<Eigen::Affine3d> path = TurnPath(2);
  const std::vector<const HandleLayout*> layouts = {&cylinder.bottom_fixed, &cylinder.top_fixed,
                                                    &cylinder.bottom_fixed, &cylinder.top_fixed};
  std::string error;
  auto drag = [&path](const std::shared_ptr<const Precompute>& precompute,
                      const HandleLayout& handles, Eigen::Matrix3Xd* result) {
    std::string error;
    std::shared_ptr<const HandleSetup> setup = HandleSetup::Create(precompute, handles, &error);
    if (setup == nullptr) return;
    std::unique_ptr<Session> session = Session::Create(setup, &error);
    if (session == nullptr) return;
    for (const Eigen::Affine3d& step : path) {
      if (!session->Drag(step, nullptr, &error)) return;
    }
    *result = session->deformed_vertices();
  };
  std::vector<Eigen::Matrix3Xd> serial(layouts.size());
  std::shared_ptr<const Precompute> serial_precompute =
      Precompute::Create(cylinder.mesh, options, &error);
  ASSERT_NE(serial_precompute, nullptr) << error;
  for (size_t i = 0; i < layouts.size(); ++i) drag(serial_precompute, *layouts[i], &serial[i]);

  std::vector<Eigen::Matrix3Xd> parallel(layouts.size());
  std::shared_ptr<const Precompute> shared = Precompute::Create(cylinder.mesh, options, &error);
  ASSERT_NE(shared, nullptr) << error;
  std::vector<std::thread> threads;
  for (size_t i = 0; i < layouts.size(); ++i) {
    threads.emplace_back(drag, shared, std::cref(*layouts[i]), &parallel[i]);
  }
  for (std::thread& thread : threads) thread.join();
  for (size_t i = 0; i < layouts.size(); ++i) {
    ASSERT_EQ(serial[i].cols(), cylinder.mesh.num_vertices()) << i;
    EXPECT_EQ(parallel[i], serial[i]) << i;
  }
  EXPECT_NE(serial[0], serial[1]);
}

}  // namespace
}  // namespace msdeform
