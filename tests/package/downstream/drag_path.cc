// The smallest program on msdeform's core library alone (msdeform::core):
// a procedural bar and the drag path to a rigid motion, whose last frame
// equals the motion exactly (core/drag_path.h). Exits 0 when it does.
#include <cstdio>
#include <vector>

#include <msdeform/core/drag_path.h>
#include <msdeform/core/procedural_meshes.h>

int main() {
  const msdeform::Mesh bar = msdeform::MakeBar(12);
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.6, Eigen::Vector3d(0, 1, 1).normalized()));
  motion.pretranslate(Eigen::Vector3d(2.0, -1.0, 0.5));
  const std::vector<Eigen::Affine3d> path =
      msdeform::InterpolateDragPath(motion, bar.vertices.rowwise().mean(), 4);
  const bool exact = path.size() == 4 && path.back().matrix() == motion.matrix();
  std::printf("drag_path: %d vertices, %zu frames, last frame %s the motion\n",
              bar.num_vertices(), path.size(), exact ? "equals" : "differs from");
  return exact ? 0 : 1;
}
