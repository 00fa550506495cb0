#include "apps/scene_vtk_links.h"

#include "fem/atomic_file.h"

#include <urdf_model/model.h>

#include <Eigen/Geometry>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace plantar::app {
namespace {

constexpr int n_sides = 16;        // cylinder sides
constexpr double min_stick = 1e-3; // m: shorter segments are not drawn

multibody::SE3 to_se3(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  const Eigen::Quaterniond q(w, x, y, z);
  return multibody::SE3(q.normalized().toRotationMatrix(),
                        Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
}

/// Appends the shape of @p geometry at @p origin (link frame) of a link on @p frame's body.
bool add_geometry(const urdf::Geometry& geometry, const urdf::Pose& origin,
                  const multibody::Frame& frame, std::vector<LinkShape>& shapes) {
  LinkShape shape;
  shape.body = frame.body;
  shape.placement = frame.placement * to_se3(origin);
  switch (geometry.type) {
  case urdf::Geometry::BOX: {
    const auto& box = static_cast<const urdf::Box&>(geometry);
    shape.kind = LinkShape::Kind::box;
    shape.size << box.dim.x, box.dim.y, box.dim.z;
    break;
  }
  case urdf::Geometry::CYLINDER: {
    const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
    shape.kind = LinkShape::Kind::cylinder;
    shape.size << cylinder.radius, cylinder.radius, cylinder.length;
    break;
  }
  case urdf::Geometry::SPHERE: {
    const double d = 2 * static_cast<const urdf::Sphere&>(geometry).radius;
    shape.kind = LinkShape::Kind::box;
    shape.size << d, d, d;
    break;
  }
  default:
    return false; // meshes are not drawn
  }
  shapes.push_back(shape);
  return true;
}

/// A cylinder of radius @p radius on body @p body from @p a to @p b (body coordinates).
void add_stick(int body, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
               std::vector<LinkShape>& shapes) {
  const Eigen::Vector3d axis = b - a;
  const double length = axis.norm();
  if (length < min_stick)
    return;
  LinkShape shape;
  shape.kind = LinkShape::Kind::cylinder;
  shape.body = body;
  shape.placement = multibody::SE3(
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix(),
      0.5 * (a + b));
  shape.size << radius, radius, length;
  shapes.push_back(shape);
}

} // namespace

std::vector<LinkShape> make_link_shapes(const multibody::Model& model,
                                        const urdf::ModelInterface& urdf, double stick_radius) {
  if (!(stick_radius > 0)) {
    std::ostringstream msg;
    msg << "Output/VTK stick radius = " << stick_radius << ": must be > 0 (m)";
    throw std::invalid_argument(msg.str());
  }
  std::vector<LinkShape> shapes;
  std::vector<bool> has_geometry(model.n_bodies, false);
  for (const multibody::Frame& frame : model.frames) {
    const auto link = urdf.getLink(frame.name);
    if (!link)
      continue;
    bool drawn = false;
    for (const auto& visual : link->visual_array)
      if (visual && visual->geometry)
        drawn |= add_geometry(*visual->geometry, visual->origin, frame, shapes);
    if (!drawn)
      for (const auto& collision : link->collision_array)
        if (collision && collision->geometry)
          drawn |= add_geometry(*collision->geometry, collision->origin, frame, shapes);
    if (drawn)
      has_geometry[frame.body] = true;
  }
  // Sticks for bodies without geometry: to each child joint origin and each merged frame.
  for (int i = 2; i < model.n_bodies; ++i) {
    const int p = model.parent[i];
    if (p >= 1 && !has_geometry[p])
      add_stick(p, Eigen::Vector3d::Zero(), model.joint_placement[i].translation, stick_radius,
                shapes);
  }
  for (const multibody::Frame& frame : model.frames)
    if (frame.body >= 1 && !has_geometry[frame.body])
      add_stick(frame.body, Eigen::Vector3d::Zero(), frame.placement.translation, stick_radius,
                shapes);
  return shapes;
}

void write_links_vtu(const multibody::Model& model, const multibody::Data& data,
                     const std::vector<LinkShape>& shapes, const std::filesystem::path& path) {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> connectivity, offsets, types, bodies;
  auto add_cell = [&](std::initializer_list<int> ids, int type, int body) {
    connectivity.insert(connectivity.end(), ids);
    offsets.push_back(static_cast<int>(connectivity.size()));
    types.push_back(type);
    bodies.push_back(body);
  };
  constexpr int vtk_vertex = 1, vtk_polygon = 7, vtk_quad = 9, vtk_hexahedron = 12;
  for (const LinkShape& shape : shapes) {
    const multibody::SE3 world = data.oMi[shape.body] * shape.placement;
    const int first = static_cast<int>(points.size());
    if (shape.kind == LinkShape::Kind::box) {
      const Eigen::Vector3d h = 0.5 * shape.size;
      // VTK hexahedron order: bottom face counter-clockwise, then top face.
      const double corners[8][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1},
                                    {-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int k = 0; k < 8; ++k)
        points.push_back(world.act_point(Eigen::Vector3d(
            corners[k][0] * h.x(), corners[k][1] * h.y(), (k < 4 ? -1.0 : 1.0) * h.z())));
      add_cell({first, first + 1, first + 2, first + 3, first + 4, first + 5, first + 6, first + 7},
               vtk_hexahedron, shape.body);
    } else {
      const double r = shape.size.x(), half = 0.5 * shape.size.z();
      for (int end = 0; end < 2; ++end)
        for (int k = 0; k < n_sides; ++k) {
          const double a = 2 * M_PI * k / n_sides;
          points.push_back(world.act_point(
              Eigen::Vector3d(r * std::cos(a), r * std::sin(a), end ? half : -half)));
        }
      for (int k = 0; k < n_sides; ++k) {
        const int k1 = (k + 1) % n_sides;
        add_cell({first + k, first + k1, first + n_sides + k1, first + n_sides + k}, vtk_quad,
                 shape.body);
      }
      for (int end = 0; end < 2; ++end) {
        for (int k = 0; k < n_sides; ++k)
          connectivity.push_back(first + end * n_sides + (end ? k : n_sides - 1 - k));
        offsets.push_back(static_cast<int>(connectivity.size()));
        types.push_back(vtk_polygon);
        bodies.push_back(shape.body);
      }
    }
  }
  for (int i = 1; i < model.n_bodies; ++i) {
    points.push_back(data.oMi[i].translation);
    add_cell({static_cast<int>(points.size()) - 1}, vtk_vertex, i);
  }

  fem::write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(12); // 1e-11 m at 10 m
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "<UnstructuredGrid>\n"
        << "<Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\"" << types.size()
        << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
           "format=\"ascii\">\n";
    for (const auto& x : points)
      out << x.x() << ' ' << x.y() << ' ' << x.z() << '\n';
    out << "</DataArray>\n</Points>\n<Cells>\n"
        << "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int c : connectivity)
      out << c << ' ';
    out << "\n</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (int c : offsets)
      out << c << ' ';
    out << "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int c : types)
      out << c << ' ';
    out << "\n</DataArray>\n</Cells>\n<CellData Scalars=\"body\">\n"
        << "<DataArray type=\"Int32\" Name=\"body\" format=\"ascii\">\n";
    for (int c : bodies)
      out << c << ' ';
    out << "\n</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  });
}

} // namespace plantar::app
