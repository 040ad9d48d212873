#include "msdeform/core/drag_path.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The linear part of data/meshes/cactus.def (Botsch-Sorkine), six printed
// digits: a turn of about 70 degrees about x with ||A^T A - I||_F = 1.47e-6.
Eigen::Affine3d CactusDef() {
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  transform.matrix() << 0.999641, 0.021031, 0.016579, -0.019322,  //
      -0.022776, 0.342021, 0.939416, -0.134331,                   //
      0.014087, -0.939457, 0.342378, 0.821073,                    //
      0, 0, 0, 1;
  return transform;
}

Eigen::Matrix3d RoundedToSixDigits(const Eigen::Matrix3d& matrix) {
  return (matrix * 1e6).array().round().matrix() / 1e6;
}

double RotationError(const Eigen::Matrix3d& matrix) {
  return (matrix.transpose() * matrix - Eigen::Matrix3d::Identity()).norm();
}

TEST(DragPathTest, EveryFrameOfTheCactusDefIsARotation) {
  const Eigen::Affine3d def = CactusDef();
  ASSERT_GT(RotationError(def.linear()), 1e-6);  // what the old exact-rotation test refused
  const std::vector<Eigen::Affine3d> path =
      InterpolateDragPath(def, Eigen::Vector3d(0.1, 0.2, 0.3), 30);
  ASSERT_EQ(path.size(), 30u);
  for (size_t k = 0; k < path.size(); ++k) {
    EXPECT_LT(RotationError(path[k].linear()), 1e-5) << "frame " << k;
    EXPECT_NEAR(path[k].linear().determinant(), 1.0, 1e-5) << "frame " << k;
  }
}

TEST(DragPathTest, MidDragOfARoundedRotationIsHalfTheTurn) {
  // A known turn, rounded as a .def with six digits prints it.
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 0.02, -0.03).normalized();
  const double angle = 70.0 * kPi / 180.0;
  Eigen::Affine3d def = Eigen::Affine3d::Identity();
  def.linear() = RoundedToSixDigits(Eigen::AngleAxisd(angle, axis).toRotationMatrix());
  def.translation() = Eigen::Vector3d(-0.019322, -0.134331, 0.821073);
  ASSERT_GT(RotationError(def.linear()), 1e-7);
  const Eigen::Vector3d pivot(0.3, -0.1, 0.5);
  const std::vector<Eigen::Affine3d> path = InterpolateDragPath(def, pivot, 2);
  ASSERT_EQ(path.size(), 2u);
  const Eigen::Matrix3d half_turn = Eigen::AngleAxisd(0.5 * angle, axis).toRotationMatrix();
  EXPECT_LT((path[0].linear() - half_turn).norm(), 1e-5) << path[0].linear();
  // The pivot moves half way on the straight line to where the transform takes it.
  EXPECT_TRUE((path[0] * pivot).isApprox(0.5 * (pivot + def * pivot), 1e-12));
}

TEST(DragPathTest, LastFrameIsTheGivenTransformExactly) {
  Eigen::Affine3d shear = Eigen::Affine3d::Identity();
  shear.matrix() << 1.0, 0.7, 0.0, 0.25,  //
      0.0, 1.0, 0.0, -1.5,                //
      0.0, 0.3, 2.0, 3.0,                 //
      0, 0, 0, 1;
  Eigen::Affine3d mirror = Eigen::Affine3d::Identity();
  mirror.linear() = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  for (const Eigen::Affine3d& def : {CactusDef(), shear, mirror}) {
    for (int frames : {1, 3, 30}) {
      const std::vector<Eigen::Affine3d> path =
          InterpolateDragPath(def, Eigen::Vector3d(0.4, 0.5, 0.6), frames);
      ASSERT_EQ(path.size(), static_cast<size_t>(frames));
      EXPECT_EQ(path.back().matrix(), def.matrix());
      for (const Eigen::Affine3d& frame : path) EXPECT_TRUE(frame.matrix().allFinite());
    }
  }
}

TEST(DragPathTest, APureScaleIsBlendedLinearly) {
  Eigen::Affine3d scale = Eigen::Affine3d::Identity();
  scale.linear() = Eigen::Vector3d(2.0, 0.5, 1.0).asDiagonal();
  const std::vector<Eigen::Affine3d> path =
      InterpolateDragPath(scale, Eigen::Vector3d::Zero(), 4);
  ASSERT_EQ(path.size(), 4u);
  const Eigen::Matrix3d quarter = Eigen::Vector3d(1.25, 0.875, 1.0).asDiagonal();
  EXPECT_LT((path[0].linear() - quarter).norm(), 1e-12) << path[0].linear();
  const Eigen::Matrix3d half = Eigen::Vector3d(1.5, 0.75, 1.0).asDiagonal();
  EXPECT_LT((path[1].linear() - half).norm(), 1e-12) << path[1].linear();
}

TEST(DragPathTest, ARotatedStretchTurnsAndBlendsOnlyTheStretch) {
  // A = R P: a 60-degree turn about z after a symmetric stretch P. The turn is
  // slerped and only the stretch is blended linearly: the mid frame is
  // R(30 degrees) (I + P) / 2, not (I + A) / 2.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(kPi / 3.0, Eigen::Vector3d::UnitZ()).matrix();
  const Eigen::Matrix3d frame_of_stretch =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  const Eigen::Matrix3d stretch = frame_of_stretch * Eigen::Vector3d(1.5, 0.8, 1.2).asDiagonal() *
                                  frame_of_stretch.transpose();
  Eigen::Affine3d def = Eigen::Affine3d::Identity();
  def.linear() = turn * stretch;
  def.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  const std::vector<Eigen::Affine3d> path = InterpolateDragPath(def, Eigen::Vector3d::Zero(), 2);
  ASSERT_EQ(path.size(), 2u);
  const Eigen::Matrix3d expected =
      Eigen::AngleAxisd(kPi / 6.0, Eigen::Vector3d::UnitZ()).matrix() * 0.5 *
      (Eigen::Matrix3d::Identity() + stretch);
  EXPECT_LT((path[0].linear() - expected).norm(), 1e-12) << path[0].linear();
  EXPECT_TRUE(path[0].translation().isApprox(Eigen::Vector3d(0.5, 1.0, 1.5), 1e-12));
  EXPECT_EQ(path[1].matrix(), def.matrix());
}

}  // namespace
}  // namespace msdeform
