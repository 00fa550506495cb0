#pragma once
// The ground as a height field z = h(x, y) (m), and the contact frame and gap that every contact
// point and patch node takes from it.
//
// Normal and frame at (x, y), from the gradient (h_x, h_y):
//   n  = (-h_x, -h_y, 1) / sqrt(1 + h_x^2 + h_y^2)             (unit, n_z > 0)
//   t1 = (e_x - n_x n) / |e_x - n_x n|                          (e_x projected on the plane)
//   t2 = n x t1
//   R_c = [n t1 t2] (columns in world coordinates): world = R_c c, c = R_c^T world.
// R_c is continuous in (h_x, h_y) (|e_x - n_x n|^2 = 1 - n_x^2 >= n_z^2 > 0) and on flat ground
// equals the permutation (z, x, y) of contact/ground_frame.h.
//
// Gap of a point p (first order signed distance, m):
//   g(p) = (p_z - h(p_x, p_y)) n_z(p_x, p_y),
// the distance along the normal to the tangent plane at the point vertically below p; exact for
// planes, error O(g^2 |grad h|^2 kappa) on a surface of curvature kappa. The contact point is
// taken vertically below p (x and y unchanged), so the frame is the one at (p_x, p_y).

#include <Eigen/Core>
#include <optional>

namespace plantar::contact {

/// A ground height field. Implementations: flat_terrain.h, slope_terrain.h, step_terrain.h,
/// bump_terrain.h, cylinder_terrain.h, rough_terrain.h, grid_terrain.h; built from a scene by
/// make_terrain (terrain_factory.h).
class Terrain {
public:
  virtual ~Terrain() = default;
  /// h(x, y), m, for world x, y (m). Defined (finite) everywhere.
  virtual double height(double x, double y) const = 0;
  /// (dh/dx, dh/dy), dimensionless, at (x, y).
  virtual Eigen::Vector2d gradient(double x, double y) const = 0;
  /// The constant height z0 when the ground is the horizontal plane z = z0 (the contact frame
  /// is then ground_frame.h's everywhere: the stepper's fast path), else nothing.
  virtual std::optional<double> level_height() const { return std::nullopt; }
};

/// n = (-h_x, -h_y, 1) / |.| for the gradient @p slope (h_x, h_y).
Eigen::Vector3d terrain_normal(const Eigen::Vector2d& slope);

/// R_c = [n t1 t2] (3 x 3, orthonormal, det +1, world <- contact frame) for the gradient
/// @p slope: see the header comment. (0, 0) gives ground_frame.h's (z, x, y).
Eigen::Matrix3d terrain_frame(const Eigen::Vector2d& slope);

/// The gap and frame of a point on a terrain.
struct TerrainContact {
  double gap = 0;                                      ///< g(p), m (negative: penetration)
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity(); ///< R_c at (p_x, p_y)
};

/// g(p) = (p_z - h) n_z and R_c at (p_x, p_y) of @p terrain for the world point @p point (m).
TerrainContact terrain_contact(const Terrain& terrain, const Eigen::Vector3d& point);

/// The first-order gap (p_z - h(p_x, p_y)) n_z of @p point (m), without the frame.
double terrain_gap(const Terrain& terrain, const Eigen::Vector3d& point);

} // namespace plantar::contact
