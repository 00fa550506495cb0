// Footsteps placed on a terrain (multibody/walking/terrain_footsteps.h) and the walk planned on
// them: a slope's exact plane, no sampled point under a curved ground, the joint reference
// realising the tilted, raised soles, and each placement's support polygon and ZMP target
// (multibody/walking/support_polygon.h) against closed forms and dense searches.
#include "contact/cylinder_terrain.h"
#include "contact/flat_terrain.h"
#include "contact/rough_terrain.h"
#include "contact/slope_terrain.h"
#include "contact/step_terrain.h"
#include "contact/terrain.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/walking/support_polygon.h"
#include "multibody/walking/terrain_footsteps.h"
#include "multibody/walking/walking_reference.h"
#include "tests/multibody/walking/hrp2_humanoid.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <limits>
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
    const Footstep placed = place_on_terrain(slope, {0.3, -0.1, yaw}, kGrid, 0.03);
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
    // On a plane the whole sole supports (its four corners) and the ZMP target is its centre.
    ASSERT_EQ(placed.support.cols(), 4);
    EXPECT_NEAR(placed.support.cwiseAbs().row(0).minCoeff(), kLength / 2, 1e-15);
    EXPECT_NEAR(placed.support.cwiseAbs().row(1).minCoeff(), kWidth / 2, 1e-15);
    EXPECT_EQ(placed.zmp_x, 0.0);
    EXPECT_EQ(placed.zmp_y, 0.0);
  }
}

/// The distance of x inside the convex polygon (counter-clockwise) to its nearest edge line
/// (negative outside).
double depth(const Eigen::Vector2d& x, const Eigen::Matrix2Xd& polygon) {
  double d = 1e9;
  for (int i = 0; i < polygon.cols(); ++i) {
    const Eigen::Vector2d a = polygon.col(i), e = polygon.col((i + 1) % polygon.cols()) - a;
    d = std::min(d, (e.x() * (x - a).y() - e.y() * (x - a).x()) / e.norm());
  }
  return d;
}

/// The radius of a triangle's inscribed circle, 2 area / perimeter [m].
double inscribed_radius(const Eigen::Matrix2Xd& t) {
  const Eigen::Vector2d a = t.col(0), b = t.col(1), c = t.col(2);
  const double area = 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  return 2 * area / ((b - a).norm() + (c - b).norm() + (a - c).norm());
}

/// The point of the polygon at depth >= margin nearest to p, by Dykstra's alternating
/// projections onto the edges' offset half-planes (an iterative method independent of
/// nearest_in_polygon's enumeration; it converges to the projection on their intersection).
Eigen::Vector2d dykstra_nearest(const Eigen::Vector2d& p, const Eigen::Matrix2Xd& polygon,
                                double margin) {
  const int m = static_cast<int>(polygon.cols());
  std::vector<Eigen::Vector2d> correction(m, Eigen::Vector2d::Zero());
  Eigen::Vector2d x = p;
  for (int sweep = 0; sweep < 200000; ++sweep) {
    const Eigen::Vector2d start = x;
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector2d a = polygon.col(i), e = polygon.col((i + 1) % m) - a;
      const Eigen::Vector2d n = Eigen::Vector2d(-e.y(), e.x()).normalized();
      const Eigen::Vector2d y = x + correction[i];
      const double violation = margin - n.dot(y - a);
      const Eigen::Vector2d projected = violation > 0 ? Eigen::Vector2d(y + violation * n) : y;
      correction[i] = y - projected;
      x = projected;
    }
    if ((x - start).norm() < 1e-16)
      break;
  }
  return x;
}

TEST(SupportPolygon, HullAndNearestPointAgainstClosedFormsAndDykstra) {
  // Hull: a square's corners among interior and edge points, returned counter-clockwise.
  Eigen::Matrix2Xd points(2, 9);
  points << 0.5, 1, 0, 1, 0.5, 0, 0, 1, 0.7, 0, 0, 1, 1, 0.5, 0.5, 0, 0.5, 0.9;
  const Eigen::Matrix2Xd hull = convex_hull(points);
  Eigen::Matrix2Xd square(2, 4);
  square << 0, 1, 1, 0, 0, 0, 1, 1;
  ASSERT_EQ(hull.cols(), 4);
  EXPECT_EQ((hull - square).cwiseAbs().maxCoeff(), 0.0);
  // Nearest point of the unit right triangle shrunk by d = 0.05: inside, unchanged; beyond the
  // hypotenuse, on the offset line x + y = 1 - d sqrt(2); beyond the right angle, its vertex
  // (d, d).
  Eigen::Matrix2Xd triangle(2, 3);
  triangle << 0, 1, 0, 0, 0, 1;
  const double d = 0.05;
  EXPECT_EQ((nearest_in_polygon({0.2, 0.3}, triangle, d) - Eigen::Vector2d(0.2, 0.3)).norm(), 0);
  const double c = 0.5 * (1 - d * std::sqrt(2.0));
  EXPECT_LT((nearest_in_polygon({2, 2}, triangle, d) - Eigen::Vector2d(c, c)).norm(), 1e-15);
  EXPECT_LT((nearest_in_polygon({-1, -2}, triangle, d) - Eigen::Vector2d(d, d)).norm(), 1e-15);
  // Too thin for the margin (inscribed radius (2 - sqrt(2)) / 2 = 0.29): margin 0.
  EXPECT_LT((nearest_in_polygon({-1, -2}, triangle, 0.4) - Eigen::Vector2d(0, 0)).norm(), 1e-15);
  // Random points around a pentagon against Dykstra's projection.
  Eigen::Matrix2Xd pentagon(2, 5);
  for (int i = 0; i < 5; ++i)
    pentagon.col(i) << 0.1 * std::cos(2 * M_PI * i / 5 + 0.3),
        0.07 * std::sin(2 * M_PI * i / 5 + 0.3);
  double worst = 0;
  std::srand(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector2d p = 0.2 * Eigen::Vector2d::Random();
    const Eigen::Vector2d x = nearest_in_polygon(p, pentagon, 0.02);
    EXPECT_GE(depth(x, pentagon), 0.02 - 1e-12);
    worst = std::max(worst, (x - dykstra_nearest(p, pentagon, 0.02)).norm());
  }
  std::printf("pentagon, margin 2 cm: largest distance to Dykstra's projection %.1e m\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(TerrainFootsteps, NoSampledPointUnderACurvedGround) {
  // A cylindrical bump (R 0.3 m, 2 cm) under part of the sole, and the flat ground around it.
  const plantar::contact::CylinderTerrain bump(0.3, 0.02, 20.0 * M_PI / 180,
                                               Eigen::Vector2d(0.05, 0.0), 0.0);
  for (const double x : {-0.05, 0.0, 0.08}) {
    const Footstep placed = place_on_terrain(bump, {x, 0.01, 0.3}, kGrid, 0.03);
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
  place_walk_on_terrain(slope, kGrid, 0.03, walk);
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

/// A rough ground of RMS 5 mm, correlation length 10 cm (seed 1).
plantar::contact::RoughTerrain rough_ground() {
  plantar::contact::RoughTerrainParameters rough;
  rough.rms = 0.005;
  rough.correlation_length = 0.1;
  return plantar::contact::RoughTerrain(rough);
}

/// A rigid sole's 8 outline points: corners and edge midpoints of the HRP-2 sole.
SolePoints rigid_outline() {
  SolePoints outline(2, 8);
  outline << -0.5, 0, 0.5, 0.5, 0.5, 0, -0.5, -0.5, -0.5, -0.5, -0.5, 0, 0.5, 0.5, 0.5, 0;
  outline.row(0) *= kLength;
  outline.row(1) *= kWidth;
  return outline;
}

TEST(TerrainFootsteps, RigidOutlineRestsOnThreePointsAroundItsCentre) {
  // The 8 points of a rigid sole's outline (corners and edge midpoints) on a rough ground: the
  // plane passes through three of them, the others are above the ground, and the centre's
  // triangle holds it. Checked against a dense search: no plane above all points is lower at
  // the centre (sampled slopes).
  const plantar::contact::RoughTerrain ground = rough_ground();
  const SolePoints outline = rigid_outline();
  for (const double x : {0.0, 0.135, 0.27, 0.405}) {
    const Footstep step{x, -0.105, 0.2};
    const Footstep placed = place_on_terrain(ground, step, outline, 0.03);
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
    // The support: at least the facet's three points, each on the ground (as above); the ZMP
    // target 3 cm inside it (in a triangle too thin for that, 0), the nearest such point to the
    // centre (Dykstra's projection).
    ASSERT_EQ(placed.support.cols(), 3);
    for (int s = 0; s < placed.support.cols(); ++s) {
      const Eigen::Vector3d p =
          Eigen::Vector3d(placed.x, placed.y, placed.z) +
          rotation * Eigen::Vector3d(placed.support(0, s), placed.support(1, s), 0);
      EXPECT_LT(p.z() - ground.height(p.x(), p.y()), 1e-4);
    }
    const Eigen::Vector2d zmp(placed.zmp_x, placed.zmp_y);
    const double margin = inscribed_radius(placed.support) >= 0.03 ? 0.03 : 0.0;
    const Eigen::Vector2d projected =
        dykstra_nearest(Eigen::Vector2d::Zero(), placed.support, margin);
    std::printf("  support of %d points (inscribed radius %.4f m); ZMP target (%.4f, %.4f) m, "
                "%.4f m inside it, %.1e m from Dykstra's projection\n",
                int(placed.support.cols()), inscribed_radius(placed.support), zmp.x(), zmp.y(),
                depth(zmp, placed.support), (zmp - projected).norm());
    EXPECT_GE(depth(zmp, placed.support), margin - 1e-9);
    EXPECT_LT((zmp - projected).norm(), 1e-8);
  }
}

TEST(TerrainFootsteps, PlanHoldsTheZmpOnEachSupport) {
  // The paper's walk placed on the rough ground by the rigid outline: in single support the ZMP
  // reference is the support sole's ZMP target R (zmp_x, zmp_y) + (x, y), and the plan's support
  // index names the placement each foot is on.
  const plantar::contact::RoughTerrain ground = rough_ground();
  const SolePoints outline = rigid_outline();
  WalkingParameters walk;
  place_walk_on_terrain(ground, outline, 0.03, walk);
  const FootstepPlan plan = make_footstep_plan(walk);
  std::vector<Footstep> placements = {walk.initial_right, walk.initial_left};
  placements.insert(placements.end(), walk.footsteps.begin(), walk.footsteps.end());
  ASSERT_EQ(plan.supports.size(), placements.size());
  double error = 0, largest_shift = 0;
  int single = 0;
  for (int k = 0; k < plan.n_samples; ++k) {
    for (int side = 0; side < 2; ++side) {
      // A supporting foot is on the placement the index names (a swing foot: its target).
      const bool swing =
          plan.phase[k] == (side == 0 ? SupportPhase::left_support : SupportPhase::right_support);
      const Footstep& on = placements[plan.support_index(k, side)];
      const Eigen::Vector3d sole = (side == 0 ? plan.right_sole : plan.left_sole).row(k);
      if (!swing)
        error = std::max(error, (sole - Eigen::Vector3d(on.x, on.y, on.z)).norm());
    }
    if (plan.phase[k] == SupportPhase::double_support)
      continue;
    ++single;
    const int side = plan.phase[k] == SupportPhase::right_support ? 0 : 1;
    const Footstep& on = placements[plan.support_index(k, side)];
    const Eigen::Vector3d target =
        Eigen::Vector3d(on.x, on.y, on.z) +
        footstep_rotation(on.yaw, on.pitch, on.roll) * Eigen::Vector3d(on.zmp_x, on.zmp_y, 0);
    error = std::max(error, (plan.zmp_reference.row(k).transpose() - target.head<2>()).norm());
    largest_shift = std::max(largest_shift, std::hypot(on.zmp_x, on.zmp_y));
  }
  std::printf("%d single-support samples: ZMP reference and soles against their placements "
              "%.1e m; largest ZMP target shift from a sole centre %.4f m\n",
              single, error, largest_shift);
  EXPECT_GT(single, 900);
  EXPECT_LT(error, 1e-15);
  EXPECT_GT(largest_shift, 0.01); // the rough ground moves the targets
}

TEST(TerrainFootsteps, CentreMarginIsTheInscribedRadiusAtTheIncentre) {
  // A triangle moved so that its incentre (a A + b B + c C) / (a + b + c), a the side opposite
  // A, is the origin: the centre's margin is the inscribed radius 2 area / perimeter; a square
  // of half side 0.04 around a point 0.01 off centre: 0.03; the origin outside by 0.02: < 0.
  Eigen::Matrix2Xd t(2, 3);
  t << -0.1, 0.12, 0.03, -0.05, -0.02, 0.07;
  const double a = (t.col(1) - t.col(2)).norm(), b = (t.col(2) - t.col(0)).norm(),
               c = (t.col(0) - t.col(1)).norm();
  const Eigen::Vector2d incentre = (a * t.col(0) + b * t.col(1) + c * t.col(2)) / (a + b + c);
  t.colwise() -= incentre;
  EXPECT_NEAR(centre_margin(t), inscribed_radius(t), 1e-15);
  Eigen::Matrix2Xd square(2, 4);
  square << -0.04, 0.04, 0.04, -0.04, -0.04, -0.04, 0.04, 0.04;
  square.row(0).array() += 0.01;
  EXPECT_NEAR(centre_margin(square), 0.03, 1e-15);
  square.row(0).array() += 0.05;
  EXPECT_LT(centre_margin(square), 0.0);
  EXPECT_EQ(centre_margin(square.leftCols(2)), -std::numeric_limits<double>::infinity());
}

TEST(TerrainFootsteps, FootholdSearchMovesASoleOffAStepEdge) {
  // A sole (the 9 x 9 grid: rows every kLength / 8 = 0.02715 m along x, one through the centre)
  // planned with its centre on the edge of a 2 cm step (upper side +x) rests level on the upper
  // side with the centre on its support's edge (margin 0). Candidates (radius 3 cm, spacing
  // 1 cm), with x_r the first grid row on the upper level (sole frame):
  //   dx >= 0: level on the upper rows, margin x_r + dx... = 0 for dx = 0.01, 0.02 (x_r = 0)
  //            and kLength / 8 for dx = 0.03 (x_r = -0.02715);
  //   dx < 0:  bridging the edge, on the back row (-kLength / 2, low ground) and the row x_r
  //            (upper level): margin min(x_r, kLength / 2) = kLength / 8 for dx = -0.01, -0.02,
  //            2 kLength / 8 for dx = -0.03.
  // The planned placement: of the planes through the centre's grid point (on the upper level),
  // all as low there, the level one (the least tilted). The bridging candidates are tilted by
  // asin(0.02 / (x_r + kLength / 2)) >= 0.12 rad, more than
  // max_tilt (0.05 rad): the best level one is dx = 0.03 (margin kLength / 8), dy = 0 the
  // nearest of its ties. With max_tilt 0.2 rad only dx = -0.03 reaches the 3 cm target: the sole
  // bridges the edge, centre height 0.02 (kLength / 2) / (kLength / 2 + 2 kLength / 8) =
  // 0.02 x 2 / 3 (the plane through the two rows). On flat ground every candidate holds the
  // centre 6.9 cm inside: the plan stays.
  const plantar::contact::StepTerrain step(0.02, 0.0, Eigen::Vector2d(0.3, 0.0), 0.0, 0.0);
  const Footstep planned{0.3, -0.105, 0.0};
  const FootholdSearch search{0.03, 0.01};
  const Footstep stay = place_on_terrain(step, planned, kGrid, 0.03);
  const Footstep moved =
      place_on_foothold(step, planned, kGrid, 0.03, search, Eigen::Vector2d(0.0, -0.105), 0.45);
  std::printf("on the edge: margin %.5f m; searched: x %.4f y %.4f z %.4f, margin %.5f m\n",
              centre_margin(stay.support), moved.x, moved.y, moved.z, centre_margin(moved.support));
  EXPECT_NEAR(centre_margin(stay.support), 0.0, 1e-12);
  EXPECT_NEAR(moved.x, 0.33, 1e-15);
  EXPECT_EQ(moved.y, planned.y);
  EXPECT_NEAR(moved.z, 0.02, 1e-15);
  EXPECT_EQ(footstep_tilt(moved), 0.0);
  EXPECT_NEAR(centre_margin(moved.support), kLength / 8, 1e-12);
  const FootholdSearch bridging{0.03, 0.01, 0.2};
  const Footstep bridged =
      place_on_foothold(step, planned, kGrid, 0.03, bridging, Eigen::Vector2d(0.0, -0.105), 0.45);
  std::printf("max tilt 0.2 rad: x %.4f y %.4f z %.5f, tilt %.4f rad, margin %.5f m\n", bridged.x,
              bridged.y, bridged.z, footstep_tilt(bridged), centre_margin(bridged.support));
  EXPECT_NEAR(bridged.x, 0.27, 1e-15);
  EXPECT_EQ(bridged.y, planned.y);
  EXPECT_NEAR(bridged.z, 0.02 * 2.0 / 3.0, 1e-12);
  // Tilted, the rows 3 kLength / 4 apart rise by 0.02: sin(tilt) = 0.02 / (3 kLength / 4).
  EXPECT_NEAR(footstep_tilt(bridged), std::asin(0.02 / (3 * kLength / 4)), 1e-12);
  EXPECT_NEAR(centre_margin(bridged.support), 2 * kLength / 8, 1e-12);
  // The longest step: a swing from x = 0.6 (a step back) of at most 0.3 m reaches the plan
  // (always allowed) and the candidates with dx >= 0 only: the best of those is dx = 0.03
  // (margin kLength / 8), not the bridging dx = -0.03.
  const Footstep back_step =
      place_on_foothold(step, planned, kGrid, 0.03, bridging, Eigen::Vector2d(0.6, -0.105), 0.3);
  EXPECT_NEAR(back_step.x, 0.33, 1e-15);
  EXPECT_NEAR(centre_margin(back_step.support), kLength / 8, 1e-12);
  const plantar::contact::FlatTerrain flat(0.0);
  const Footstep level =
      place_on_foothold(flat, planned, kGrid, 0.03, search, Eigen::Vector2d(0.0, -0.105), 0.45);
  EXPECT_EQ(level.x, planned.x);
  EXPECT_EQ(level.y, planned.y);
  EXPECT_THROW(place_on_foothold(flat, planned, kGrid, 0.03, {0.03, 0.01, 0.0},
                                 Eigen::Vector2d(0.0, -0.105), 0.45),
               std::invalid_argument);
  EXPECT_THROW(place_on_foothold(flat, planned, kGrid, 0.03, {-0.01, 0.01},
                                 Eigen::Vector2d(0.0, -0.105), 0.45),
               std::invalid_argument);
}

TEST(TerrainFootsteps, FootholdSearchHoldsTheCentresOnRoughGround) {
  // The paper's walk placed on the rough ground by the 9 x 9 grid (a rigid sole that touches
  // the ground anywhere): without a search most supports are thin triangles with the centre on
  // an edge; with a 3 cm search every footstep's centre margin is at least its plan's (the plan
  // is a candidate), each moves by at most 3 cm and every step stays within max_step_length.
  const plantar::contact::RoughTerrain ground = rough_ground();
  WalkingParameters planned, searched;
  place_walk_on_terrain(ground, kGrid, 0.03, planned);
  place_walk_on_terrain(ground, kGrid, 0.03, searched, {0.03, 0.01});
  ASSERT_EQ(planned.footsteps.size(), searched.footsteps.size());
  int held_before = 0, held_after = 0;
  double worst_before = 1e9, worst_after = 1e9, sum_before = 0, sum_after = 0;
  Eigen::Vector2d right(searched.initial_right.x, searched.initial_right.y),
      left(searched.initial_left.x, searched.initial_left.y);
  for (std::size_t i = 0; i < planned.footsteps.size(); ++i) {
    const Footstep &p = planned.footsteps[i], &s = searched.footsteps[i];
    const double before = centre_margin(p.support), after = centre_margin(s.support);
    std::printf("step %zu: margin %.4f -> %.4f m, moved (%.3f, %.3f) m\n", i, before, after,
                s.x - p.x, s.y - p.y);
    EXPECT_GE(std::min(after, 0.03), std::min(before, 0.03) - 1e-9);
    EXPECT_LE(std::hypot(s.x - p.x, s.y - p.y), 0.03 + 1e-12);
    Eigen::Vector2d& from = (i % 2 == 0) == searched.right_foot_first ? right : left;
    EXPECT_LE(std::hypot(s.x - from.x(), s.y - from.y()), searched.max_step_length + 1e-12);
    from << s.x, s.y;
    sum_before += std::clamp(before, 0.0, 0.03);
    sum_after += std::clamp(after, 0.0, 0.03);
    held_before += before >= 0.03 - 1e-9 ? 1 : 0;
    held_after += after >= 0.03 - 1e-9 ? 1 : 0;
    worst_before = std::min(worst_before, before);
    worst_after = std::min(worst_after, after);
  }
  std::printf("centre 3 cm inside the support: %d of %zu footsteps planned, %d searched; "
              "smallest margin %.4f -> %.4f m; sum of the margins (each clamped to [0, 3 cm]) "
              "%.4f -> %.4f m\n",
              held_before, planned.footsteps.size(), held_after, worst_before, worst_after,
              sum_before, sum_after);
  EXPECT_GT(held_after, held_before);
  EXPECT_GT(sum_after, 3 * sum_before);
  EXPECT_NO_THROW(check_walking_parameters(searched));
}

TEST(TerrainFootsteps, BadPointsAreReported) {
  const plantar::contact::SlopeTerrain slope(0.05, 0.0, Eigen::Vector3d::Zero());
  EXPECT_THROW(sole_grid(0.0, 0.1, 9), std::invalid_argument);
  EXPECT_THROW(sole_grid(0.2, 0.1, 1), std::invalid_argument);
  SolePoints two(2, 2);
  two << 0.1, -0.1, 0.0, 0.0;
  EXPECT_THROW(place_on_terrain(slope, {}, two, 0.0), std::invalid_argument);
  SolePoints off_centre(2, 3);
  off_centre << 0.1, 0.2, 0.1, 0.1, 0.1, 0.2;
  EXPECT_THROW(place_on_terrain(slope, {}, off_centre, 0.0), std::invalid_argument);
}

} // namespace

/// A wall of height 0.1 m over 0.19 < x < 0.21 on a level ground.
class WallTerrain : public plantar::contact::Terrain {
public:
  double height(double x, double) const override { return x > 0.19 && x < 0.21 ? 0.1 : 0.0; }
  Eigen::Vector2d gradient(double, double) const override { return Eigen::Vector2d::Zero(); }
};

/// The sample at the nearer end of the swing of @p foot holding sample @p k (planned height
/// above its ground > 0 between them).
int lift_side(const FootstepPlan& plan, int foot, int k) {
  const Eigen::MatrixX3d& sole = foot == 0 ? plan.right_sole : plan.left_sole;
  auto up = [&](int i) { return sole(i, 2) - plan.ground(i, foot) > 0.0; };
  int a = k, b = k;
  while (a > 0 && up(a - 1))
    --a;
  while (b + 1 < plan.n_samples && up(b + 1))
    ++b;
  return k - a <= b - k ? a - 1 : b + 1;
}

/// The worst (clearance - required) over the swings of @p walk's plan (only the swing onto
/// footstep @p step if >= 0) sampled every 1 ms, on a 4 mm grid of the whole sole (m; >= 0:
/// every point clears the ground by min(walk.swing_ground_margin, the sole's height above the
/// nearer of its two placements)).
double worst_swing_clearance(const plantar::contact::Terrain& terrain, WalkingParameters walk,
                             int step = -1) {
  walk.period = 0.001;
  const FootstepPlan plan = make_footstep_plan(walk);
  const double start = walk.standing_before + walk.initial_double_support_time +
                       step * (walk.single_support_time + walk.double_support_time);
  const int nx = 55, ny = 35; // 4 mm over 0.2172 x 0.138
  double worst = std::numeric_limits<double>::infinity();
  for (int k = 0; k < plan.n_samples; ++k)
    for (int foot = 0; foot < 2; ++foot) {
      if (step >= 0 && (plan.time(k) < start || plan.time(k) > start + walk.single_support_time))
        continue;
      const Eigen::MatrixX3d& sole = foot == 0 ? plan.right_sole : plan.left_sole;
      const double lift = sole(k, 2) - plan.ground(k, foot);
      if (lift <= 0.0)
        continue; // on its placement
      // The nearer placement's height: the ground at the swing's start or end.
      const int k_near = lift_side(plan, foot, k);
      const double near = plan.ground(k_near, foot);
      const Eigen::Vector2d tilt = (foot == 0 ? plan.right_tilt : plan.left_tilt).row(k);
      const Eigen::Matrix3d rotation =
          footstep_rotation((foot == 0 ? plan.right_yaw : plan.left_yaw)(k), tilt(1), tilt(0));
      const double required = std::min(walk.swing_ground_margin, sole(k, 2) - near);
      for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
          const Eigen::Vector3d p =
              sole.row(k).transpose() +
              rotation * Eigen::Vector3d(kLength * (double(i) / (nx - 1) - 0.5),
                                         kWidth * (double(j) / (ny - 1) - 0.5), 0.0);
          worst = std::min(worst, p.z() - terrain.height(p.x(), p.y()) - required);
        }
    }
  return worst;
}

TEST(SwingLiftFraction, TheSwingClearsAStepAndIsTheLeastThatDoes) {
  // The robustness matrix's 2 cm step (edge at x = 0.25 m, a 2 mm C1 ramp) planned on: the
  // right toe starts 6 mm behind the riser (0.135 + kLength / 2 = 0.2436 m). With the paper's
  // swing (f = 0) the toe meets the riser 7 mm up: the plan's swing runs into the step.
  const plantar::contact::StepTerrain step(0.02, 0.0, Eigen::Vector2d(0.25, 0.0), 0.0, 0.002);
  WalkingParameters walk;
  walk.touchdown_velocity = 0.1;
  WalkingParameters unlifted = walk;
  place_walk_on_terrain(step, kGrid, 0.03, walk);
  for (const Footstep& f : walk.footsteps)
    std::printf("footstep x %.3f y %.3f z %.4f: lift fraction %.3f\n", f.x, f.y, f.z,
                f.lift_fraction);
  unlifted.initial_right = walk.initial_right;
  unlifted.initial_left = walk.initial_left;
  unlifted.footsteps = walk.footsteps;
  for (Footstep& f : unlifted.footsteps)
    f.lift_fraction = 0.0;
  const double lifted = worst_swing_clearance(step, walk);
  const double paper = worst_swing_clearance(step, unlifted, 2);
  std::printf("worst clearance - required: %.5f m lifted, %.5f m with the paper's swing\n", lifted,
              paper);
  EXPECT_LT(paper, -0.01); // into the riser
  // The planner samples 201 instants on a 1 cm grid: between them the sole rises by under 1 mm.
  // (The third swing is the one that meets the riser with the paper's swing.)
  EXPECT_GT(lifted, -1e-3);
  // Only the third swing lifts (the right foot from x = 0.135 onto the step, its toe 6 mm behind
  // the riser): the left one from x = 0 reaches the edge near its apex; the others stay on one
  // level.
  for (std::size_t i = 0; i < walk.footsteps.size(); ++i)
    if (i == 2)
      EXPECT_GT(walk.footsteps[i].lift_fraction, 0.1);
    else
      EXPECT_EQ(walk.footsteps[i].lift_fraction, 0.0) << i;
  // The least: 0.01 less runs the right toe into the riser.
  WalkingParameters less = walk;
  less.footsteps[2].lift_fraction -= 0.01;
  const double worst = worst_swing_clearance(step, less, 2);
  std::printf("at f - 0.01: worst clearance - required %.6f m\n", worst);
  EXPECT_LT(worst, -1e-3);
}

TEST(SwingLiftFraction, ZeroOnFlatGroundAndAWallTooHighIsAnError) {
  const plantar::contact::FlatTerrain flat(0.0);
  WalkingParameters walk;
  place_walk_on_terrain(flat, kGrid, 0.03, walk);
  for (const Footstep& f : walk.footsteps)
    EXPECT_EQ(f.lift_fraction, 0.0);
  // A 10 cm wall between two placements, a 7 cm apex.
  const WallTerrain wall;
  const Footstep from{0.0, -0.105, 0.0}, to{0.4, -0.105, 0.0};
  try {
    swing_lift_fraction(wall, from, to, kGrid, walk);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("Step height (0.070000 m)"), std::string::npos)
        << e.what();
  }
  walk.step_height = 0.15; // the apex clears it
  const double f = swing_lift_fraction(wall, from, to, kGrid, walk);
  EXPECT_GT(f, 0.0);
  EXPECT_LT(f, 0.45);
}

TEST(SwingLiftFraction, TheFootOnlyRisesAndDescendsOverTheLiftFraction) {
  // make_footstep_plan with f = 0.25 on the first step: the right sole stays at its start
  // (x, y) for tau <= f, is at its target for tau >= 1 - f, and its height is the f = 0 plan's.
  WalkingParameters walk;
  walk.period = 0.001;
  walk.touchdown_velocity = 0.1;
  const FootstepPlan paper = make_footstep_plan(walk);
  walk.footsteps[0].lift_fraction = 0.25;
  const FootstepPlan lifted = make_footstep_plan(walk);
  const double start = walk.standing_before + walk.initial_double_support_time;
  int before = 0, after = 0, between = 0;
  for (int k = 0; k < lifted.n_samples; ++k) {
    EXPECT_EQ(lifted.right_sole(k, 2), paper.right_sole(k, 2)) << k;
    const double tau = (lifted.time(k) - start) / walk.single_support_time;
    if (tau < 0.0 || tau > 1.0)
      continue;
    const double x = lifted.right_sole(k, 0);
    if (tau <= 0.25) {
      EXPECT_EQ(x, walk.initial_right.x) << tau;
      ++before;
    } else if (tau >= 0.75) {
      EXPECT_NEAR(x, walk.footsteps[0].x, 1e-15) << tau;
      ++after;
    } else {
      EXPECT_GE(x, walk.initial_right.x);
      EXPECT_LE(x, walk.footsteps[0].x + 1e-15);
      between += x > walk.initial_right.x && x < walk.footsteps[0].x;
    }
  }
  EXPECT_GT(before, 150);
  EXPECT_GT(after, 150);
  EXPECT_GT(between, 350);
  walk.footsteps[0].lift_fraction = 0.5;
  EXPECT_THROW(make_footstep_plan(walk), std::invalid_argument);
}
