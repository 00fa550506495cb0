#include "coupling/deformable_pad.h"

#include "coupling/contact_frame_compliance.h"
#include "fem/material_table.h"
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"
#include "fem/sole_parameters.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace plantar::coupling {
namespace {

std::string number_text(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "(" + number_text(v.x()) + ", " + number_text(v.y()) + ", " + number_text(v.z()) + ")";
}

[[noreturn]] void fail(const std::string& pad, const std::string& message) {
  throw std::invalid_argument("DeformablePad '" + pad + "': " + message);
}

/// The mesh generated, imported and condensed, and its extent along pad z.
struct Built {
  CondensedSole condensed;
  double thickness;
};

Built build(const PadDescription& description) {
  dealii::Triangulation<3> tria;
  double thickness = 0;
  const fem::PhysicalGroups groups = mesh_pad(description, tria, thickness);
  const std::string parameter = "pad '" + description.name + "' materials";
  const fem::MaterialTable materials(fem::parse_material_specs(description.materials, parameter),
                                     groups);
  CondensationParameters parameters;
  parameters.attached_boundary = groups.surface("top");
  parameters.contact_boundary = groups.surface("bottom");
  parameters.degree = description.degree;
  return {CondensedSole(tria, materials, parameters), thickness};
}

} // namespace

fem::PhysicalGroups mesh_pad(const PadDescription& description, dealii::Triangulation<3>& tria,
                             double& thickness) {
  fem::MeshRequest request;
  request.geo_file = fem::resolve_path(description.geometry_file, std::filesystem::current_path());
  request.numbers = description.mesh_numbers;
  request.cache_directory =
      description.cache_directory.empty() ? fem::default_mesh_cache() : description.cache_directory;
  request.gmsh_executable = description.gmsh_executable;
  fem::PhysicalGroups groups =
      fem::import_mesh(fem::generate_mesh(request), {"top", "bottom"}, tria);
  double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
  for (const auto& vertex : tria.get_vertices()) {
    z_min = std::min(z_min, vertex[2]);
    z_max = std::max(z_max, vertex[2]);
  }
  thickness = z_max - z_min;
  return groups;
}

void PadDescription::validate() const {
  if (name.empty())
    fail(name, "name is empty (give the pad a name, e.g. \"left_knee\")");
  if (geometry_file.empty())
    fail(name, "geometry_file is empty (a gmsh .geo file, e.g. meshes/pad_knee.geo)");
  const auto geo = fem::resolve_path(geometry_file, std::filesystem::current_path());
  if (!std::filesystem::is_regular_file(geo))
    fail(name, "geometry_file = '" + geometry_file.string() +
                   "': no such file (looked in the working directory and the Plantar source "
                   "tree)");
  for (const auto& [key, value] : mesh_numbers) {
    if (key.empty())
      fail(name, "mesh_numbers: an empty gmsh parameter name");
    if (!std::isfinite(value))
      fail(name, "mesh_numbers[" + key + "] = " + number_text(value) + ": must be finite");
  }
  if (gmsh_executable.empty())
    fail(name, "gmsh_executable is empty");
  if (materials.find_first_not_of(" \t\n;") == std::string::npos)
    fail(name, "materials = '" + materials +
                   "': no region (expected 'region: E=..., nu=...; ...', e.g. 'pad: E=1e6, "
                   "nu=0.3')");
  if (degree != 1 && degree != 2)
    fail(name, "degree = " + std::to_string(degree) + ": must be 1 or 2");
  if (link.empty())
    fail(name, "link is empty (the name of the link carrying the pad)");
  if (!translation.allFinite())
    fail(name, "translation = " + vector_text(translation) + " m: must be finite");
  if (!rpy.allFinite())
    fail(name, "rpy = " + vector_text(rpy) + " rad: must be finite");
  if (!std::isfinite(friction) || friction < 0 || friction > 100)
    fail(name, "friction = " + number_text(friction) + ": must be in [0, 100]");
}

Eigen::Matrix3d PadDescription::rotation() const {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

DeformablePad::DeformablePad(const PadDescription& description)
    : description_((description.validate(), description)), rotation_(description.rotation()),
      condensed_([&] {
        Built built = build(description);
        thickness_ = built.thickness;
        return std::move(built.condensed);
      }()) {
  const int n = condensed_.n_contacts();
  const Eigen::MatrixXd& c = condensed_.compliance();
  link_positions_ =
      (rotation_ * condensed_.contact_positions().transpose()).colwise() + description_.translation;
  // R C R^T blockwise: the contact-frame rotation with every contact frame the identity.
  link_compliance_.resize(3 * n, 3 * n);
  const Eigen::MatrixXd frames = Eigen::Matrix3d::Identity().replicate(1, n);
  rotate_compliance_to_contact_frames(c, rotation_, frames, link_compliance_);

  // k_z = 1^T C_zz^-1 1, pad frame.
  Eigen::MatrixXd czz(n, n);
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l)
      czz(k, l) = c(3 * k + 2, 3 * l + 2);
  const Eigen::LLT<Eigen::MatrixXd> factor(czz);
  if (factor.info() != Eigen::Success)
    throw std::runtime_error("DeformablePad '" + description_.name +
                             "': the normal block of the compliance is not positive definite");
  vertical_stiffness_ = factor.solve(Eigen::VectorXd::Ones(n)).sum();
}

} // namespace plantar::coupling
