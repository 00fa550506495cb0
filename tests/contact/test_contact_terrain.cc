// The terrains (contact/terrain.h and its implementations): heights against their closed forms,
// gradients against central finite differences of the heights, the frame (orthonormal,
// continuous, the flat ground's (z, x, y) on flat ground), the first-order gap (exact for
// planes), the rough surface's measured RMS height and correlation length against the
// requested ones, the CSV grid's bilinear exactness on a plane and its errors.
#include "contact/bump_terrain.h"
#include "contact/cylinder_terrain.h"
#include "contact/flat_terrain.h"
#include "contact/grid_terrain.h"
#include "contact/ground_frame.h"
#include "contact/rough_terrain.h"
#include "contact/slope_terrain.h"
#include "contact/step_terrain.h"
#include "contact/terrain_factory.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <random>
#include <string>

namespace pc = plantar::contact;

namespace {

// Max over random points in [-1, 1]^2 (scaled by @p extent) of |grad h - central FD|, step
// @p step. The FD error is step^2 |h'''| / 6; the points within @p step of a kink are skipped
// by @p skip.
template <class Skip>
double gradient_error(const pc::Terrain& terrain, double extent, double step, Skip skip,
                      unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0;
  for (int i = 0; i < 2000; ++i) {
    const double x = extent * unit(rng), y = extent * unit(rng);
    if (skip(x, y))
      continue;
    const Eigen::Vector2d fd(
        (terrain.height(x + step, y) - terrain.height(x - step, y)) / (2 * step),
        (terrain.height(x, y + step) - terrain.height(x, y - step)) / (2 * step));
    worst = std::max(worst, (terrain.gradient(x, y) - fd).cwiseAbs().maxCoeff());
  }
  return worst;
}
auto no_skip = [](double, double) { return false; };

std::filesystem::path temporary_file(const std::string& name, const std::string& text) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

} // namespace

TEST(ContactTerrain, FrameIsOrthonormalContinuousAndFlatGroundsPermutation) {
  // Flat: exactly ground_frame.h's R_c.
  EXPECT_EQ(pc::terrain_frame(Eigen::Vector2d::Zero()), pc::ground_frame());
  EXPECT_EQ(pc::ground_frame().transpose(), pc::ground_frame_transpose());
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst_orthonormal = 0, worst_normal = 0, worst_lipschitz = 0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d g(3 * unit(rng), 3 * unit(rng));
    const Eigen::Matrix3d r = pc::terrain_frame(g);
    worst_orthonormal =
        std::max({worst_orthonormal, (r.transpose() * r - Eigen::Matrix3d::Identity()).norm(),
                  std::abs(r.determinant() - 1.0)});
    // n is the normalised (-h_x, -h_y, 1); t1, t2 are tangent (orthogonal to the normal).
    const Eigen::Vector3d n = Eigen::Vector3d(-g.x(), -g.y(), 1).normalized();
    worst_normal = std::max(worst_normal, (r.col(0) - n).norm());
    // Continuity: |R(g + d) - R(g)| / |d| bounded for small d.
    const Eigen::Vector2d d(1e-7 * unit(rng), 1e-7 * unit(rng));
    worst_lipschitz = std::max(worst_lipschitz, (pc::terrain_frame(g + d) - r).norm() / d.norm());
  }
  std::printf("frames: max |R^T R - I|, |det - 1| %.1e, |n - n_exact| %.1e, max |dR|/|dg| %.2f\n",
              worst_orthonormal, worst_normal, worst_lipschitz);
  EXPECT_LE(worst_orthonormal, 1e-14);
  EXPECT_LE(worst_normal, 1e-15);
  EXPECT_LE(worst_lipschitz, 10.0); // |dn/dg| <= 1, |dt1/dg| <= a few for |g| <= 3
}

TEST(ContactTerrain, FlatAndSlopeAgainstClosedForms) {
  const pc::FlatTerrain flat(0.3);
  EXPECT_EQ(flat.height(5, -2), 0.3);
  EXPECT_EQ(flat.level_height().value(), 0.3);
  EXPECT_EQ(pc::terrain_gap(flat, Eigen::Vector3d(1, 2, 0.5)), 0.5 - 0.3);
  EXPECT_EQ(pc::terrain_gap(pc::flat_ground(), Eigen::Vector3d(1, 2, -0.01)), -0.01);

  // The slope's normal is the axis rotation of e_z (Eigen's AngleAxis, independent) and the
  // first-order gap of any point is its exact distance n . (p - p0) to the plane.
  const double alpha = 0.3, psi = 0.7;
  const Eigen::Vector3d p0(0.2, -0.4, 0.1);
  const pc::SlopeTerrain slope(alpha, psi, p0);
  const Eigen::Vector3d axis(std::cos(psi), std::sin(psi), 0);
  const Eigen::Vector3d normal = Eigen::AngleAxisd(alpha, axis) * Eigen::Vector3d::UnitZ();
  EXPECT_FALSE(slope.level_height().has_value());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst_gap = 0, worst_normal = 0, worst_height = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(unit(rng), unit(rng), unit(rng));
    const pc::TerrainContact c = pc::terrain_contact(slope, p);
    worst_gap = std::max(worst_gap, std::abs(c.gap - normal.dot(p - p0)));
    worst_normal = std::max(worst_normal, (c.frame.col(0) - normal).norm());
    // The surface point above (x, y) lies in the plane.
    const Eigen::Vector3d s(p.x(), p.y(), slope.height(p.x(), p.y()));
    worst_height = std::max(worst_height, std::abs(normal.dot(s - p0)));
  }
  std::printf("slope: gap vs distance to the plane %.1e, normal %.1e, surface in plane %.1e\n",
              worst_gap, worst_normal, worst_height);
  EXPECT_LE(worst_gap, 1e-15 * 10);
  EXPECT_LE(worst_normal, 1e-15 * 10);
  EXPECT_LE(worst_height, 1e-15 * 10);
  EXPECT_THROW(pc::SlopeTerrain(2.0, 0, p0), std::invalid_argument);
}

TEST(ContactTerrain, StepsBumpsAndCylinderAgainstClosedFormsAndFiniteDifferences) {
  // Step: H = 0.02 along heading 30 deg through (0.1, 0.2), ramp width 4 mm.
  const double rise = 0.02, heading = M_PI / 6, width = 0.004;
  const Eigen::Vector2d edge(0.1, 0.2), d(std::cos(heading), std::sin(heading));
  const pc::StepTerrain step(rise, heading, edge, -0.01, width);
  auto at = [&](double s) { // the point at signed distance s from the edge
    const Eigen::Vector2d x = edge + s * d + 0.3 * Eigen::Vector2d(-d.y(), d.x());
    return x;
  };
  EXPECT_EQ(step.height(at(-0.01).x(), at(-0.01).y()), -0.01);
  EXPECT_NEAR(step.height(at(0.01).x(), at(0.01).y()), -0.01 + rise, 1e-17);
  EXPECT_NEAR(step.height(at(0).x(), at(0).y()), -0.01 + 0.5 * rise, 1e-15);
  EXPECT_NEAR(step.gradient(at(0).x(), at(0).y()).norm(), 1.5 * rise / width, 1e-12);
  const double e_step = gradient_error(step, 0.5, 1e-7, [&](double x, double y) {
    const double s = d.dot(Eigen::Vector2d(x, y) - edge);
    return std::abs(std::abs(s) - 0.5 * width) < 1e-6; // the C1 joints (S'' jumps)
  });
  const pc::StepTerrain sharp(rise, heading, edge, 0.0, 0.0);
  EXPECT_EQ(sharp.height(at(0).x(), at(0).y()), rise); // on the edge: the upper level
  EXPECT_EQ(sharp.height(at(-1e-9).x(), at(-1e-9).y()), 0.0);
  EXPECT_EQ(sharp.gradient(at(0).x(), at(0).y()), Eigen::Vector2d::Zero());

  // Bumps: A cos(2 pi x / Lx) cos(2 pi y / Ly); Ly = 0: a corrugation along x.
  const pc::BumpTerrain bumps(0.01, 0.4, 0.3, 0.05);
  EXPECT_NEAR(bumps.height(0.1, 0.075), 0.05 + 0.01 * std::cos(M_PI / 2) * std::cos(M_PI / 2),
              1e-17);
  EXPECT_NEAR(bumps.height(0.4, 0.3), 0.06, 1e-16);
  const double e_bumps = gradient_error(bumps, 1.0, 1e-6, no_skip);
  const pc::BumpTerrain ridges(0.01, 0.4, 0.0, 0.0);
  EXPECT_NEAR(ridges.height(0.1, 7.3), 0.01 * std::cos(2 * M_PI * 0.1 / 0.4), 1e-17);

  // Cylinder: radius 0.1 m, rise 0.01 m, axis along y through x = 0.05: the surface points
  // lie on the circle centred R - b below the top; the top at z0 + b; flat off the bump.
  const double radius = 0.1, bump = 0.01;
  const pc::CylinderTerrain cylinder(radius, bump, M_PI / 2, Eigen::Vector2d(0.05, 0.0), 0.0);
  EXPECT_NEAR(cylinder.height(0.05, 3.0), bump, 1e-15);
  EXPECT_EQ(cylinder.height(0.05 + 0.05, 0.0), 0.0);
  EXPECT_NEAR(cylinder.half_width(), std::sqrt(radius * radius - 0.09 * 0.09), 1e-15);
  double worst_circle = 0;
  for (int i = -20; i <= 20; ++i) {
    const double dx = 0.99 * cylinder.half_width() * i / 20.0;
    const double z = cylinder.height(0.05 + dx, 1.0);
    worst_circle = std::max(worst_circle, std::abs(std::hypot(dx, z - (bump - radius)) - radius));
  }
  const double e_cylinder = gradient_error(cylinder, 0.2, 1e-7, [&](double x, double) {
    return std::abs(std::abs(x - 0.05) - cylinder.half_width()) < 1e-6; // the kink
  });
  std::printf("gradient vs central FD: step %.1e, bumps %.1e, cylinder %.1e; cylinder surface "
              "off its circle %.1e m\n",
              e_step, e_bumps, e_cylinder, worst_circle);
  // FD error: step^2 |h'''| / 6 + 2 eps |h| / step: step 1e-7 with h''' ~ 12 H / w^3 (step:
  // 2e-7 bound), step 1e-6 for the bumps (|h'''| ~ A (2 pi / L)^3 ~ 5e1: 1e-11).
  EXPECT_LE(e_step, 1e-6);
  EXPECT_LE(e_bumps, 1e-8);
  EXPECT_LE(e_cylinder, 1e-6);
  EXPECT_LE(worst_circle, 1e-15);
  EXPECT_THROW(pc::CylinderTerrain(0.1, 0.2, 0, Eigen::Vector2d::Zero(), 0), std::invalid_argument);
  EXPECT_THROW(pc::StepTerrain(0.02, 0, Eigen::Vector2d::Zero(), 0, -1e-3), std::invalid_argument);
  EXPECT_THROW(pc::BumpTerrain(0.01, -1, 0.3, 0), std::invalid_argument);
}

TEST(ContactTerrain, RoughSurfaceHasTheRequestedStatistics) {
  // sigma = 5 mm, l = 5 cm, 2048 modes; the grid (spacing l/8) over 1 m x 1 m.
  pc::RoughTerrainParameters p;
  p.rms = 0.005;
  p.correlation_length = 0.05;
  p.seed = 7;
  p.modes = 2048;
  p.size_x = p.size_y = 1.0;
  const pc::RoughTerrain rough(p);
  // The grid's interpolation against the mode sum, and its gradients against FD (C1 surface).
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(-0.49, 0.49);
  double worst_interpolation = 0;
  for (int i = 0; i < 300; ++i) {
    const double x = unit(rng), y = unit(rng);
    worst_interpolation =
        std::max(worst_interpolation, std::abs(rough.height(x, y) - rough.mode_height(x, y)));
  }
  const double e_gradient = gradient_error(rough, 0.49, 1e-7, no_skip, 5);
  // The statistics of the field (the mode sum the grid interpolates) over 6 m x 6 m, sampled at
  // spacing l/2.
  const double step = 0.5 * p.correlation_length;
  const int n = static_cast<int>(6.0 / step);
  Eigen::MatrixXd h(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      h(i, j) = rough.mode_height(-3.0 + i * step, -3.0 + j * step);
  const double rms = std::sqrt(h.squaredNorm() / h.size());
  // Autocorrelation along x and y at lags of step: the lag where it falls to 1/e (linear
  // interpolation between the samples around it).
  auto correlation = [&](int lag) {
    const double along_x = (h.topRows(n - lag).array() * h.bottomRows(n - lag).array()).mean();
    const double along_y = (h.leftCols(n - lag).array() * h.rightCols(n - lag).array()).mean();
    return 0.5 * (along_x + along_y) / (rms * rms);
  };
  double measured_length = 0;
  for (int lag = 1; lag < n / 4; ++lag) {
    const double c0 = correlation(lag - 1), c1 = correlation(lag);
    if (c1 <= std::exp(-1.0)) {
      measured_length = step * (lag - 1 + (c0 - std::exp(-1.0)) / (c0 - c1));
      break;
    }
  }
  // Tolerances: the sample holds N_ind = (6 / l)^2 = 14400 correlation areas, so the RMS has a
  // relative standard error of about 1 / sqrt(2 N_ind) = 0.6 %: allowed 4 of them, 2.5 %. The
  // correlation at lag l of one realisation with N modes scatters by about
  // sqrt((1 - e^-2)^2 / (2 N)) = 0.013 around e^-1, the sample adds ~ 1/sqrt(N_ind) = 0.008,
  // and the correlation's slope there is 2/(e l): an error in l of ~ 0.0155 / 0.74 = 2.1 %;
  // allowed 4 of them, 8.5 %. (The interpolation: O((l/8)^4) terms, allowed 1e-3 sigma.)
  std::printf("rough: RMS %.4f mm (requested %.4f), correlation length %.4f m (requested %.4f), "
              "grid interpolation vs mode sum %.2e m, gradient vs FD %.2e\n",
              rms * 1e3, p.rms * 1e3, measured_length, p.correlation_length, worst_interpolation,
              e_gradient);
  EXPECT_NEAR(rms / p.rms, 1.0, 0.025);
  EXPECT_NEAR(measured_length / p.correlation_length, 1.0, 0.085);
  EXPECT_LE(worst_interpolation, 1e-3 * p.rms);
  EXPECT_LE(e_gradient, 1e-5);
  // Reproducible from the seed, different with another.
  const pc::RoughTerrain again(p);
  EXPECT_EQ(again.height(0.123, -0.456), rough.height(0.123, -0.456));
  p.seed = 8;
  p.modes = 64;
  EXPECT_NE(pc::RoughTerrain(p).mode_height(0.123, -0.456), rough.mode_height(0.123, -0.456));
  // Outside the grid: clamped onto its border, gradient 0.
  EXPECT_EQ(rough.height(10.0, 0.3), rough.height(0.5 + rough.spacing(), 0.3));
  EXPECT_EQ(rough.gradient(10.0, 0.3), Eigen::Vector2d::Zero());
  p.correlation_length = 1e-4;
  EXPECT_THROW(pc::RoughTerrain{p}, std::invalid_argument); // too many grid nodes
}

TEST(ContactTerrain, CsvGridIsBilinearAndExactOnAPlane) {
  // A plane h = 0.01 + 0.02 x - 0.03 y sampled on a 5 x 4 grid (spacing 0.1, origin (-0.2,
  // -0.1)): heights and gradients exact inside.
  const double spacing = 0.1;
  const Eigen::Vector2d origin(-0.2, -0.1);
  auto plane = [](double x, double y) { return 0.01 + 0.02 * x - 0.03 * y; };
  std::string text = "# plane\n\n";
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 5; ++c) {
      char value[64];
      std::snprintf(value, sizeof value, "%s%.17g", c ? ", " : "",
                    plane(origin.x() + c * spacing, origin.y() + r * spacing));
      text += value;
    }
    text += "\n";
  }
  const auto path = temporary_file("plantar_terrain_plane.csv", text);
  const pc::GridTerrain grid(path.string(), spacing, origin, 0.5);
  EXPECT_EQ(grid.n_rows(), 4);
  EXPECT_EQ(grid.n_columns(), 5);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> ux(-0.2, 0.2), uy(-0.1, 0.2);
  double worst_height = 0, worst_gradient = 0;
  for (int i = 0; i < 500; ++i) {
    const double x = ux(rng), y = uy(rng);
    worst_height = std::max(worst_height, std::abs(grid.height(x, y) - 0.5 - plane(x, y)));
    worst_gradient = std::max(
        worst_gradient, (grid.gradient(x, y) - Eigen::Vector2d(0.02, -0.03)).cwiseAbs().maxCoeff());
  }
  std::printf("grid on a plane: height error %.1e m, gradient error %.1e\n", worst_height,
              worst_gradient);
  EXPECT_LE(worst_height, 1e-16 * 10);
  EXPECT_LE(worst_gradient, 1e-14);
  // Outside: clamped onto the border, gradient zero.
  EXPECT_NEAR(grid.height(5.0, 0.0), 0.5 + plane(0.2, 0.0), 1e-16 * 10);
  EXPECT_EQ(grid.gradient(5.0, 0.0), Eigen::Vector2d::Zero());
  // A non-plane cell: bilinear between its four corners, the centre is their mean.
  Eigen::MatrixXd corners(2, 2);
  corners << 0.0, 1.0, 2.0, 7.0;
  const pc::GridTerrain cell(corners, 1.0, Eigen::Vector2d::Zero(), 0.0);
  EXPECT_DOUBLE_EQ(cell.height(0.5, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(cell.gradient(0.5, 0.5).x(), 0.5 * (1.0 + 5.0));

  // Errors name the file, the line and the column.
  auto message = [](const std::string& name, const std::string& body) {
    try {
      pc::GridTerrain(temporary_file(name, body).string(), 0.1, Eigen::Vector2d::Zero(), 0.0);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string bad_value = message("plantar_terrain_bad.csv", "0, 1\n0, x2\n");
  EXPECT_NE(bad_value.find("plantar_terrain_bad.csv line 2 column 2: 'x2'"), std::string::npos)
      << bad_value;
  const std::string ragged = message("plantar_terrain_ragged.csv", "0, 1, 2\n# c\n0, 1\n");
  EXPECT_NE(ragged.find("line 3 has 2 values, expected 3"), std::string::npos) << ragged;
  const std::string small = message("plantar_terrain_small.csv", "0, 1\n");
  EXPECT_NE(small.find("allowed >= 2 rows"), std::string::npos) << small;
  EXPECT_THROW(pc::GridTerrain("/nonexistent/terrain.csv", 0.1, Eigen::Vector2d::Zero(), 0.0),
               std::invalid_argument);
}

TEST(ContactTerrain, FactoryBuildsEveryType) {
  pc::TerrainParameters p;
  p.rough.correlation_length = 0.2;
  p.rough.size_x = p.rough.size_y = 1.0;
  p.rough.modes = 16;
  p.grid_file = temporary_file("plantar_terrain_zero.csv", "0, 0\n0, 0\n").string();
  for (const auto& [type, name] : pc::terrain_type_names()) {
    p.type = type;
    const auto terrain = pc::make_terrain(p);
    ASSERT_NE(terrain, nullptr) << name;
    EXPECT_TRUE(std::isfinite(terrain->height(0.01, 0.02))) << name;
    EXPECT_EQ(terrain->level_height().has_value(), type == pc::TerrainType::flat) << name;
  }
  // The slope of the factory: degrees, pivot at the origin and level.
  p.type = pc::TerrainType::slope;
  p.slope_angle = 10;
  p.slope_axis_heading = 90;
  p.level = 0.1;
  EXPECT_NEAR(pc::make_terrain(p)->height(1.0, 0.0), 0.1 - std::tan(10 * M_PI / 180), 1e-15);
  p.slope_angle = 95;
  EXPECT_THROW(pc::make_terrain(p), std::invalid_argument);
}
