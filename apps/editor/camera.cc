#include "apps/editor/camera.h"

#include <algorithm>
#include <cmath>

namespace msdeform {
namespace editor {
namespace {

constexpr double kPi = 3.14159265358979323846;
double Radians(double degrees) { return degrees * kPi / 180.0; }

}  // namespace

void OrbitCamera::Fit(const Eigen::AlignedBox3d& box, const Viewport& viewport) {
  target_ = box.center();
  scene_radius_ = std::max(0.5 * box.diagonal().norm(), 1e-12);
  // The sphere of radius r at distance d spans an angle asin(r / d) each side;
  // the smaller field of view (vertical or horizontal) must hold it.
  const double half_fov_y = 0.5 * Radians(options_.fov_y_deg);
  const double half_fov_x = std::atan(std::tan(half_fov_y) * viewport.aspect());
  const double half = std::min(half_fov_x, half_fov_y) * options_.fit_fill;
  distance_ = scene_radius_ / std::sin(half);
}

void OrbitCamera::LookFrom(const Eigen::Vector3d& from_target) {
  const double length = from_target.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return;
  const Eigen::Vector3d d = from_target / length;
  // Eye() = target + distance (sin yaw cos pitch, sin pitch, cos yaw cos pitch).
  const double limit = std::min(options_.look_max_pitch_deg, options_.max_pitch_deg);
  pitch_deg_ = std::clamp(std::asin(std::clamp(d.y(), -1.0, 1.0)) * 180.0 / kPi, -limit, limit);
  // Straight up or down: any yaw; keep the current one.
  if (std::hypot(d.x(), d.z()) > 1e-12) yaw_deg_ = std::atan2(d.x(), d.z()) * 180.0 / kPi;
}

void OrbitCamera::Orbit(double dx, double dy) {
  yaw_deg_ = std::fmod(yaw_deg_ - dx * options_.orbit_deg_per_pixel, 360.0);
  set_pitch_deg(pitch_deg_ + dy * options_.orbit_deg_per_pixel);
}

void OrbitCamera::Pan(double dx, double dy, const Viewport& viewport) {
  // The target moves opposite to the scene: dragging right moves the scene
  // right under the cursor.
  target_ -= ViewPlaneDelta(Eigen::Vector2d(dx, dy), target_, viewport);
}

void OrbitCamera::Zoom(double steps) {
  set_distance(distance_ / std::pow(options_.zoom_per_step, steps));
}

void OrbitCamera::set_pitch_deg(double pitch) {
  pitch_deg_ = std::clamp(pitch, -options_.max_pitch_deg, options_.max_pitch_deg);
}

void OrbitCamera::set_distance(double distance) {
  distance_ = std::clamp(distance, 1e-3 * scene_radius_, 1e3 * scene_radius_);
}

Eigen::Vector3d OrbitCamera::Eye() const {
  const double yaw = Radians(yaw_deg_), pitch = Radians(pitch_deg_);
  const Eigen::Vector3d from_target(std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                    std::cos(yaw) * std::cos(pitch));
  return target_ + distance_ * from_target;
}

Eigen::Vector3d OrbitCamera::Forward() const { return (target_ - Eye()).normalized(); }

Eigen::Vector3d OrbitCamera::Right() const {
  const double yaw = Radians(yaw_deg_);
  return Eigen::Vector3d(std::cos(yaw), 0.0, -std::sin(yaw));
}

Eigen::Vector3d OrbitCamera::Up() const { return Right().cross(Forward()); }

Eigen::Matrix4d OrbitCamera::View() const {
  const Eigen::Vector3d right = Right(), up = Up(), back = -Forward(), eye = Eye();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = right.transpose();
  view.block<1, 3>(1, 0) = up.transpose();
  view.block<1, 3>(2, 0) = back.transpose();
  view(0, 3) = -right.dot(eye);
  view(1, 3) = -up.dot(eye);
  view(2, 3) = -back.dot(eye);
  return view;
}

double OrbitCamera::NearPlane() const {
  return std::max(0.5 * (distance_ - scene_radius_), 1e-3 * scene_radius_);
}

double OrbitCamera::FarPlane() const { return distance_ + 2.0 * scene_radius_; }

Eigen::Matrix4d OrbitCamera::Projection(const Viewport& viewport) const {
  const double n = NearPlane(), f = FarPlane();
  const double cot = 1.0 / std::tan(0.5 * Radians(options_.fov_y_deg));
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = cot / viewport.aspect();
  projection(1, 1) = cot;
  projection(2, 2) = -(f + n) / (f - n);
  projection(2, 3) = -2.0 * f * n / (f - n);
  projection(3, 2) = -1.0;
  return projection;
}

Eigen::Vector3d OrbitCamera::Project(const Eigen::Vector3d& point, const Viewport& viewport) const {
  const Eigen::Vector4d clip = Projection(viewport) * View() * point.homogeneous();
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  return Eigen::Vector3d(0.5 * (ndc.x() + 1.0) * viewport.width,
                         0.5 * (1.0 - ndc.y()) * viewport.height, 0.5 * (ndc.z() + 1.0));
}

double OrbitCamera::EyeDepth(double window_depth) const {
  const double n = NearPlane(), f = FarPlane();
  const double z_ndc = 2.0 * window_depth - 1.0;
  return 2.0 * f * n / ((f + n) - z_ndc * (f - n));
}

Eigen::Vector3d OrbitCamera::ViewPlaneDelta(const Eigen::Vector2d& pixel_delta,
                                            const Eigen::Vector3d& at,
                                            const Viewport& viewport) const {
  // At eye depth z, one pixel spans 2 z tan(fov / 2) / height world units.
  const double depth = std::max((at - Eye()).dot(Forward()), 1e-9 * scene_radius_);
  const double per_pixel =
      2.0 * depth * std::tan(0.5 * Radians(options_.fov_y_deg)) / viewport.height;
  return per_pixel * (pixel_delta.x() * Right() - pixel_delta.y() * Up());
}

Eigen::Vector3d FacingDirection(const Mesh& mesh, const std::vector<int>& vertices) {
  std::vector<char> chosen(mesh.num_vertices(), 0);
  for (int v : vertices) {
    if (v >= 0 && v < mesh.num_vertices()) chosen[v] = 1;
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3i face = mesh.faces.col(f);
    const int count = chosen[face[0]] + chosen[face[1]] + chosen[face[2]];
    if (count == 0) continue;
    const Eigen::Vector3d a = mesh.vertices.col(face[0]);
    // Twice the face's area along its normal (counter-clockwise faces).
    sum += count * (mesh.vertices.col(face[1]) - a).cross(mesh.vertices.col(face[2]) - a);
  }
  const double length = sum.norm();
  return length > 0.0 && std::isfinite(length) ? Eigen::Vector3d(sum / length)
                                               : Eigen::Vector3d::Zero();
}

Eigen::Vector3d FirstViewDirection(const Mesh& mesh, const std::vector<int>& handle) {
  const Eigen::Vector3d normal = FacingDirection(mesh, handle);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  int count = 0;
  for (int v : handle) {
    if (v < 0 || v >= mesh.num_vertices()) continue;
    centroid += mesh.vertices.col(v);
    ++count;
  }
  if (count == 0) return Eigen::Vector3d::Zero();
  Eigen::Vector3d offset = centroid / count - BoundingBox(mesh).center();
  offset.y() = 0.0;
  Eigen::Vector3d heading(normal.x(), 0.0, normal.z());
  if (offset.norm() > 0.0) heading += (1.0 - heading.norm()) * offset.normalized();
  if (!(heading.norm() > 0.0)) return normal;
  // A normal straight up or down keeps a little heading (|rise| <= 0.99), so
  // that OrbitCamera::LookFrom, which limits the pitch, still has a yaw.
  const double rise = std::clamp(normal.y(), -0.99, 0.99);
  return std::sqrt(std::max(1.0 - rise * rise, 0.0)) * heading.normalized() +
         Eigen::Vector3d(0.0, rise, 0.0);
}

}  // namespace editor
}  // namespace msdeform
