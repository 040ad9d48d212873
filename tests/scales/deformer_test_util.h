// Shared by the stage and method tests (precompute/handle_setup/session_test.cc,
// tests/methods/graph_method*_test.cc, promises_test.cc, method_test.cc,
// tests/examples/energy_terms/volume_term_test.cc, tests/solvers/arap_backends_test.cc):
// the methods, small-graph options for small procedural meshes, a bar edit,
// a vertex distance, and the stages made by hand.

#ifndef MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_
#define MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/session.h"

namespace msdeform {

inline constexpr Method kAllMethods[] = {Method::kMultiScale, Method::kStatic,
                                         Method::kStaticDense};

// `method` with graphs small enough for a few hundred vertices: 20 nodes per
// scale, a 40-node static graph, one thread.
inline DeformerOptions OptionsFor(Method method) {
  DeformerOptions options;
  options.method = method;
  options.static_nodes = 40;
  options.graph.nodes_per_scale = 20;
  options.num_threads = 1;
  return options;
}

// A bar along x (length x 1 x 1 voxels of width 1, each subdivided), its
// first voxel fixed and its last voxel the handle.
struct BarEdit {
  explicit BarEdit(int length = 12, int subdivisions = 4)
      : mesh(MakeBar(length, 1.0, subdivisions)) {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.vertices(0, v) <= 1.0) layout.fixed.push_back(v);
      if (mesh.vertices(0, v) >= length - 1.0) layout.moveable.push_back(v);
    }
  }
  Mesh mesh;
  HandleLayout layout;
};

// Largest distance between corresponding columns.
inline double MaxDistance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).colwise().norm().maxCoeff();
}

// A cylinder (radius 1, height 10 along z) and two handle layouts on it:
// bottom_fixed (z < 1 fixed, z > 9 moveable) and top_fixed (the reverse). Both
// select a coarse scale of the multi-scale method.
struct CylinderLayouts {
  Mesh mesh = MakeCylinder(1.0, 10.0, 32, 60);
  HandleLayout bottom_fixed, top_fixed;
  CylinderLayouts() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double z = mesh.vertices(2, v);
      if (z < 1.0) {
        bottom_fixed.fixed.push_back(v);
        top_fixed.moveable.push_back(v);
      }
      if (z > 9.0) {
        bottom_fixed.moveable.push_back(v);
        top_fixed.fixed.push_back(v);
      }
    }
  }
};

// OptionsFor(method) with a lattice of about 20 cells along the cylinder's
// diagonal: a few hundred DG1 nodes, so that static_dense stays quick.
inline DeformerOptions CylinderOptions(Method method) {
  DeformerOptions options = OptionsFor(method);
  options.lattice.cells_per_diagonal = 20.0;
  return options;
}

// `frames` handle transforms: a growing turn about x with a sideways shift.
inline std::vector<Eigen::Affine3d> TurnPath(int frames) {
  std::vector<Eigen::Affine3d> path;
  for (int f = 1; f <= frames; ++f) {
    Eigen::Affine3d step = Eigen::Affine3d::Identity();
    step.linear() = Eigen::AngleAxisd(0.3 * f, Eigen::Vector3d::UnitX()).toRotationMatrix();
    step.translation() << 0.2 * f, -0.5 * f, 0.0;
    path.push_back(step);
  }
  return path;
}

// The set-up of `handles` on a precompute of its own (a failed stage fails
// the test and gives nullptr).
inline std::shared_ptr<const HandleSetup> MakeHandleSetup(const Mesh& mesh,
                                                          const DeformerOptions& options,
                                                          const HandleLayout& handles) {
  std::string error;
  std::shared_ptr<const Precompute> precompute = Precompute::Create(mesh, options, &error);
  EXPECT_NE(precompute, nullptr) << error;
  if (precompute == nullptr) return nullptr;
  std::shared_ptr<const HandleSetup> setup = HandleSetup::Create(precompute, handles, &error);
  EXPECT_NE(setup, nullptr) << error;
  return setup;
}

// A session made by hand from the three stages.
inline std::unique_ptr<Session> MakeSession(const Mesh& mesh, const DeformerOptions& options,
                                            const HandleLayout& handles) {
  std::shared_ptr<const HandleSetup> setup = MakeHandleSetup(mesh, options, handles);
  if (setup == nullptr) return nullptr;
  std::string error;
  std::unique_ptr<Session> session = Session::Create(setup, &error);
  EXPECT_NE(session, nullptr) << error;
  return session;
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_
