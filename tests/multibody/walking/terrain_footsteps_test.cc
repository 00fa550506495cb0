// Footsteps placed on a terrain (multibody/walking/terrain_footsteps.h) and the walk planned on
// them: a slope's exact plane, no sampled point under a curved ground, and the joint reference
// realising the tilted, raised soles.
#include "contact/cylinder_terrain.h"
#include "contact/rough_terrain.h"
#include "contact/slope_terrain.h"
#include "contact/terrain.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/walking/terrain_footsteps.h"
#include "multibody/walking/walking_reference.h"
#include "tests/multibody/walking/hrp2_humanoid.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <vector>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;

constexpr double kLength = 0.2172, kWidth = 0.138; // the public HRP-2 sole
const SolePoints kGrid = sole_grid(kLength, kWidth, 9);

/// Lowest and highest vertical gap p_z - h(p_x, p_y) of the placed sole's grid of m x m points.
Eigen::Vector2d gap_range(const plantar::contact::Terrain& terrain, const Footstep& f, int m) {
  const Eigen::Matrix3d rotation = footstep_rotation(f.yaw, f.pitch, f.roll);
  Eigen::Vector2d range(1e9, -1e9);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const Eigen::Vector3d local(kLength * (double(i) / (m - 1) - 0.5),
                                  kWidth * (double(j) / (m - 1) - 0.5), 0.0);
      const Eigen::Vector3d p = Eigen::Vector3d(f.x, f.y, f.z) + rotation * local;
      const double gap = p.z() - terrain.height(p.x(), p.y());
      range = Eigen::Vector2d(std::min(range(0), gap), std::max(range(1), gap));
    }
  return range;
}

TEST(TerrainFootsteps, SoleRestsOnASlopesPlane) {
  // 5 deg about an axis at 30 deg from x, through (0.1, 0.2, 0.05).
  const plantar::contact::SlopeTerrain slope(5.0 * M_PI / 180, 30.0 * M_PI / 180,
                                             Eigen::Vector3d(0.1, 0.2, 0.05));
  for (const double yaw : {0.0, 0.4, -2.0}) {
    const Footstep placed = place_on_terrain(slope, {0.3, -0.1, yaw}, kGrid);
    const Eigen::Matrix3d rotation = footstep_rotation(placed.yaw, placed.pitch, placed.roll);
    const Eigen::Vector3d normal =
        plantar::contact::terrain_normal(slope.gradient(placed.x, placed.y));
    const Eigen::Vector2d gaps = gap_range(slope, placed, 21);
    std::printf("yaw %.1f: z - h %.1e m, normal %.1e, heading %.1e rad, gaps [%.1e, %.1e] m\n", yaw,
                placed.z - slope.height(0.3, -0.1), (rotation.col(2) - normal).norm(),
                std::remainder(std::atan2(rotation(1, 0), rotation(0, 0)) - yaw, 2 * M_PI), gaps(0),
                gaps(1));
    EXPECT_NEAR(placed.z, slope.height(0.3, -0.1), 1e-12);
    EXPECT_LT((rotation.col(2) - normal).norm(), 1e-12);
    // The sole's x axis keeps the heading yaw.
    EXPECT_NEAR(std::remainder(std::atan2(rotation(1, 0), rotation(0, 0)) - yaw, 2 * M_PI), 0.0,
                1e-12);
    EXPECT_LT(gaps.cwiseAbs().maxCoeff(), 1e-12); // every point of the sole on the plane
  }
}

TEST(TerrainFootsteps, NoSampledPointUnderACurvedGround) {
  // A cylindrical bump (R 0.3 m, 2 cm) under part of the sole, and the flat ground around it.
  const plantar::contact::CylinderTerrain bump(0.3, 0.02, 20.0 * M_PI / 180,
                                               Eigen::Vector2d(0.05, 0.0), 0.0);
  for (const double x : {-0.05, 0.0, 0.08}) {
    const Footstep placed = place_on_terrain(bump, {x, 0.01, 0.3}, kGrid);
    const Eigen::Vector2d gaps = gap_range(bump, placed, 9);
    std::printf("x %.2f: z %.5f m, roll %.4f, pitch %.4f rad, sampled gaps [%.1e, %.2e] m\n", x,
                placed.z, placed.roll, placed.pitch, gaps(0), gaps(1));
    EXPECT_NEAR(gaps(0), 0.0, 1e-14); // the lowest sampled point on the ground, none below
    EXPECT_GT(placed.z, 0.0);
  }
}

TEST(TerrainFootsteps, WalkReferenceRealisesTiltedRaisedSoles) {
  // The paper's walk placed on a 3 deg slope rising towards +x (1 cm per 19 cm).
  const plantar::contact::SlopeTerrain slope(3.0 * M_PI / 180, -90.0 * M_PI / 180,
                                             Eigen::Vector3d::Zero());
  WalkingParameters walk;
  place_walk_on_terrain(slope, kGrid, walk);
  ASSERT_GT(walk.footsteps.back().z, 0.03);
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const WalkingPattern pattern = make_walking_pattern(model, humanoid, walk);
  const FootstepPlan& plan = pattern.plan;
  const JointReference& ref = pattern.reference;
  plantar::multibody::Data data(model);
  Eigen::VectorXd q = model.neutral_configuration();
  double position_error = 0, rotation_error = 0, ground_error = 0, max_rise = 0;
  for (int k = 0; k < ref.n_samples(); ++k) {
    Eigen::Isometry3d base;
    Eigen::VectorXd angles(ref.q.cols());
    ref.sample(ref.time(k), angles, base);
    q.head<3>() = base.translation();
    const Eigen::Quaterniond rotation(base.linear());
    q.segment<4>(3) << rotation.x(), rotation.y(), rotation.z(), rotation.w();
    humanoid.to_configuration(model, angles, q);
    plantar::multibody::forward_kinematics(model, data, q);
    for (int side = 0; side < 2; ++side) {
      const auto sole =
          plantar::multibody::frame_placement(model, data, humanoid.sole_frames[side]);
      const Eigen::Vector3d planned = (side == 0 ? plan.right_sole : plan.left_sole).row(k);
      const Eigen::Vector2d tilt = (side == 0 ? plan.right_tilt : plan.left_tilt).row(k);
      const double yaw = side == 0 ? plan.right_yaw(k) : plan.left_yaw(k);
      position_error = std::max(position_error, (sole.translation - planned).norm());
      rotation_error = std::max(
          rotation_error,
          Eigen::AngleAxisd(footstep_rotation(yaw, tilt(1), tilt(0)).transpose() * sole.rotation)
              .angle());
      // A foot down rests on the slope: its ground column is the slope under its centre.
      if (planned.z() - plan.ground(k, side) < 1e-12)
        ground_error = std::max(
            ground_error, std::abs(plan.ground(k, side) - slope.height(planned.x(), planned.y())));
    }
    max_rise = std::max(max_rise, ref.base_position(k, 2) - ref.base_position(0, 2));
  }
  const double expected_rise = 0.5 * (walk.footsteps[4].z + walk.footsteps[5].z) -
                               0.5 * (walk.initial_right.z + walk.initial_left.z);
  std::printf("sole position error %.1e m, orientation %.1e rad, ground column %.1e m; waist "
              "rise %.5f m (placements' mean rise %.5f m)\n",
              position_error, rotation_error, ground_error, max_rise, expected_rise);
  EXPECT_LT(position_error, 1e-9);
  EXPECT_LT(rotation_error, 1e-9);
  EXPECT_LT(ground_error, 1e-12);
  EXPECT_NEAR(max_rise, expected_rise, 1e-12);
  // The landing sample of each step: the swing sole on its placement.
  for (size_t i = 0; i < walk.footsteps.size(); ++i) {
    const Footstep& f = walk.footsteps[i];
    EXPECT_NEAR(f.z, slope.height(f.x, f.y), 1e-12);
  }
}

TEST(TerrainFootsteps, RigidOutlineRestsOnThreePointsAroundItsCentre) {
  // The 8 points of a rigid sole's outline (corners and edge midpoints) on a rough ground: the
  // plane passes through three of them, the others are above the ground, and the centre's
  // triangle holds it. Checked against a dense search: no plane above all points is lower at
  // the centre (sampled slopes).
  plantar::contact::RoughTerrainParameters rough;
  rough.rms = 0.005;
  rough.correlation_length = 0.1;
  const plantar::contact::RoughTerrain ground(rough);
  SolePoints outline(2, 8);
  outline << -0.5, 0, 0.5, 0.5, 0.5, 0, -0.5, -0.5, -0.5, -0.5, -0.5, 0, 0.5, 0.5, 0.5, 0;
  outline.row(0) *= kLength;
  outline.row(1) *= kWidth;
  for (const double x : {0.0, 0.135, 0.27, 0.405}) {
    const Footstep step{x, -0.105, 0.2};
    const Footstep placed = place_on_terrain(ground, step, outline);
    const Eigen::Matrix3d rotation = footstep_rotation(placed.yaw, placed.pitch, placed.roll);
    std::vector<double> gaps;
    double lowest = 1e9;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d p = Eigen::Vector3d(placed.x, placed.y, placed.z) +
                                rotation * Eigen::Vector3d(outline(0, i), outline(1, i), 0);
      const double gap = p.z() - ground.height(p.x(), p.y());
      lowest = std::min(lowest, gap);
      gaps.push_back(gap);
    }
    // Dense check of the minimum: slopes on a grid, the lowest plane above the 8 heights.
    const Eigen::Matrix2d yaw = Eigen::Rotation2Dd(step.yaw).toRotationMatrix();
    double heights[8];
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector2d w = Eigen::Vector2d(step.x, step.y) + yaw * outline.col(i);
      heights[i] = ground.height(w.x(), w.y());
    }
    double dense = 1e9;
    for (int a = -200; a <= 200; ++a)
      for (int b = -200; b <= 200; ++b) {
        const Eigen::Vector2d slope(a * 5e-4, b * 5e-4);
        double centre = -1e9;
        for (int i = 0; i < 8; ++i)
          centre = std::max(centre, heights[i] - slope.dot(outline.col(i)));
        dense = std::min(dense, centre);
      }
    std::sort(gaps.begin(), gaps.end());
    std::printf("x %.3f: z %.5f m (dense search %.5f m), roll %.4f, pitch %.4f rad, three lowest "
                "gaps %.1e %.1e %.1e m\n",
                x, placed.z, dense, placed.roll, placed.pitch, gaps[0], gaps[1], gaps[2]);
    // Three points on the ground, to the tilt's horizontal shift of the points (second order).
    EXPECT_LT(gaps[2], 1e-4);
    EXPECT_NEAR(lowest, 0.0, 1e-14);
    // The dense grid over the untilted points' positions: within the tilt's horizontal shift
    // (tilt^2 / 2 x 0.11 m x slope 0.1: 6e-5 m at 0.1 rad) and the grid's slope step (5e-4 x
    // 0.11 m).
    EXPECT_NEAR(placed.z, dense, 1.2e-4);
  }
}

TEST(TerrainFootsteps, BadPointsAreReported) {
  const plantar::contact::SlopeTerrain slope(0.05, 0.0, Eigen::Vector3d::Zero());
  EXPECT_THROW(sole_grid(0.0, 0.1, 9), std::invalid_argument);
  EXPECT_THROW(sole_grid(0.2, 0.1, 1), std::invalid_argument);
  SolePoints two(2, 2);
  two << 0.1, -0.1, 0.0, 0.0;
  EXPECT_THROW(place_on_terrain(slope, {}, two), std::invalid_argument);
  SolePoints off_centre(2, 3);
  off_centre << 0.1, 0.2, 0.1, 0.1, 0.1, 0.2;
  EXPECT_THROW(place_on_terrain(slope, {}, off_centre), std::invalid_argument);
}

} // namespace
