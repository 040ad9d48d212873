// The editor's orbit camera: a target point, a distance and two angles,
// turned into OpenGL's view and projection matrices and into pixels.
//
// Conventions. World +y is up. yaw 0, pitch 0 puts the eye on the +z side of
// the target looking down -z; yaw turns the eye about world y (positive:
// towards +x), pitch lifts it (positive: above the target). Pixels are
// measured from the top-left corner of the viewport, x to the right and y
// down; pixel (i, j) covers [i, i + 1) x [j, j + 1), so a projected point at
// x = 10.7 lies in pixel column 10. Window depth is OpenGL's: 0 at the near
// plane, 1 at the far plane.

#ifndef MSDEFORM_APPS_EDITOR_CAMERA_H_
#define MSDEFORM_APPS_EDITOR_CAMERA_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "msdeform/core/mesh.h"

namespace msdeform {
namespace editor {

struct Viewport {
  int width = 1;   // pixels
  int height = 1;  // pixels
  double aspect() const { return static_cast<double>(width) / height; }
};

struct CameraOptions {
  // Vertical field of view, degrees.
  double fov_y_deg = 30.0;
  // Fit: the eye's distance makes the bounding sphere fill this fraction of
  // the smaller viewport side.
  double fit_fill = 0.9;
  // Orbit speed, degrees of yaw or pitch per pixel of mouse motion.
  double orbit_deg_per_pixel = 0.35;
  // Zoom: the distance is divided by this per scroll step.
  double zoom_per_step = 1.12;
  // Pitch is kept within +-this, degrees (the view never flips over the pole).
  double max_pitch_deg = 89.0;
  // LookFrom keeps the pitch within +-this, degrees: a handle facing up or
  // down is seen at a slant, the mesh still upright on the screen.
  double look_max_pitch_deg = 45.0;
};

class OrbitCamera {
 public:
  explicit OrbitCamera(const CameraOptions& options = CameraOptions()) : options_(options) {}

  // Looks at the centre of `box` from a distance at which its bounding sphere
  // fits the viewport (with fit_fill), keeping yaw and pitch; `box` also sets
  // the scene radius used for the near and far planes.
  void Fit(const Eigen::AlignedBox3d& box, const Viewport& viewport);

  // Turns the eye to the side `from_target` points to (any length), keeping
  // target and distance: yaw and pitch of that direction, the pitch within
  // +-look_max_pitch_deg. A zero vector changes nothing.
  void LookFrom(const Eigen::Vector3d& from_target);

  // Mouse gestures, in pixels moved.
  void Orbit(double dx, double dy);
  void Pan(double dx, double dy, const Viewport& viewport);
  // Positive steps move closer.
  void Zoom(double steps);

  // Column-vector 4x4 matrices, world -> eye and eye -> clip.
  Eigen::Matrix4d View() const;
  Eigen::Matrix4d Projection(const Viewport& viewport) const;

  // World point -> (pixel x, pixel y, window depth). Points behind the eye get
  // depth outside [0, 1].
  Eigen::Vector3d Project(const Eigen::Vector3d& point, const Viewport& viewport) const;
  // Window depth -> distance in front of the eye along the view axis.
  double EyeDepth(double window_depth) const;
  // The world translation that moves a point at `at` by `pixel_delta` on the
  // screen, in the view plane through `at` (the dragged handle follows the
  // cursor).
  Eigen::Vector3d ViewPlaneDelta(const Eigen::Vector2d& pixel_delta, const Eigen::Vector3d& at,
                                 const Viewport& viewport) const;

  // The eye's frame in world coordinates.
  Eigen::Vector3d Eye() const;
  Eigen::Vector3d Forward() const;  // from the eye to the target, unit
  Eigen::Vector3d Right() const;    // unit
  Eigen::Vector3d Up() const;       // unit, completes the frame

  double yaw_deg() const { return yaw_deg_; }
  double pitch_deg() const { return pitch_deg_; }
  double distance() const { return distance_; }
  const Eigen::Vector3d& target() const { return target_; }
  double scene_radius() const { return scene_radius_; }
  void set_yaw_deg(double yaw) { yaw_deg_ = yaw; }
  void set_pitch_deg(double pitch);
  void set_distance(double distance);
  void set_target(const Eigen::Vector3d& target) { target_ = target; }
  const CameraOptions& options() const { return options_; }

 private:
  double NearPlane() const;
  double FarPlane() const;

  CameraOptions options_;
  double yaw_deg_ = 0.0;
  double pitch_deg_ = 0.0;
  double distance_ = 3.0;
  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();
  double scene_radius_ = 1.0;
};

// The side a set of vertices faces: the sum of their area-weighted normals
// (each face's area vector counted once per vertex of the set it has),
// normalised; zero when the set is empty or its normals cancel.
Eigen::Vector3d FacingDirection(const Mesh& mesh, const std::vector<int>& vertices);

// The editor's first view of an edit (EditorApp::FirstView) looks at the whole
// mesh from this side of it, unit (zero: no preference). Its height (sine of
// the pitch) is FacingDirection(mesh, handle)'s; its heading is that normal's
// horizontal part, completed, as far as the normal is vertical (a sole facing
// down, a cap facing up), by the handle centroid's horizontal offset from the
// bounding box's centre, the side of the mesh the handle is on.
Eigen::Vector3d FirstViewDirection(const Mesh& mesh, const std::vector<int>& handle);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_CAMERA_H_
