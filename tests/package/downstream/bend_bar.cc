// The smallest program built on msdeform: deform a procedural bar with the
// multi-scale method's three stages (msdeform::scales). It checks two answers known without the solver:
// dragging the whole bar as the handle moves it rigidly, and an identity
// drag with one end fixed leaves it at rest. Exits 0 when both hold.
#include <cstdio>
#include <memory>
#include <string>

#include <msdeform/core/drag_path.h>
#include <msdeform/core/procedural_meshes.h>
#include <msdeform/scales/handle_setup.h>
#include <msdeform/scales/precompute.h>
#include <msdeform/scales/session.h>

namespace {

using msdeform::HandleLayout;

double MaxDistance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).colwise().norm().maxCoeff();
}

bool Deform(const msdeform::Mesh& bar, const HandleLayout& layout,
            const Eigen::Affine3d& motion, Eigen::Matrix3Xd* deformed) {
  std::string error;
  std::shared_ptr<const msdeform::Precompute> precompute =
      msdeform::Precompute::Create(bar, msdeform::DeformerOptions(), &error);
  std::shared_ptr<const msdeform::HandleSetup> setup =
      precompute ? msdeform::HandleSetup::Create(precompute, layout, &error) : nullptr;
  std::unique_ptr<msdeform::Session> session =
      setup ? msdeform::Session::Create(setup, &error) : nullptr;
  if (session == nullptr) {
    std::fprintf(stderr, "bend_bar: %s\n", error.c_str());
    return false;
  }
  for (const Eigen::Affine3d& frame :
       msdeform::InterpolateDragPath(motion, bar.vertices.rowwise().mean(), 4)) {
    if (!session->Drag(frame, nullptr, &error)) {
      std::fprintf(stderr, "bend_bar: %s\n", error.c_str());
      return false;
    }
  }
  *deformed = session->deformed_vertices();
  return true;
}

}  // namespace

int main() {
  const msdeform::Mesh bar = msdeform::MakeBar(12);
  const double diagonal =
      (bar.vertices.rowwise().maxCoeff() - bar.vertices.rowwise().minCoeff()).norm();

  // The whole bar is the handle: it follows a rotation and translation exactly.
  HandleLayout whole;
  for (int v = 0; v < bar.num_vertices(); ++v) whole.moveable.push_back(v);
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.6, Eigen::Vector3d(0, 1, 1).normalized()));
  motion.pretranslate(Eigen::Vector3d(2.0, -1.0, 0.5));
  Eigen::Matrix3Xd deformed;
  if (!Deform(bar, whole, motion, &deformed)) return 1;
  const double rigid_error = MaxDistance(deformed, motion * bar.vertices) / diagonal;

  // One end fixed, the other end the handle, not moved: the bar stays at rest.
  HandleLayout ends;
  for (int v = 0; v < bar.num_vertices(); ++v) {
    if (bar.vertices(0, v) <= 0.0) ends.fixed.push_back(v);
    if (bar.vertices(0, v) >= 12.0) ends.moveable.push_back(v);
  }
  if (!Deform(bar, ends, Eigen::Affine3d::Identity(), &deformed)) return 1;
  const double rest_error = MaxDistance(deformed, bar.vertices) / diagonal;

  std::printf("bend_bar: %d vertices; rigid drag error %.2e, identity drag error %.2e "
              "(of the diagonal)\n", bar.num_vertices(), rigid_error, rest_error);
  return rigid_error < 1e-6 && rest_error < 1e-9 ? 0 : 1;
}
