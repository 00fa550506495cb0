#include "apps/scene_vtk_writer.h"

#include "contact/rough_terrain.h"
#include "contact/terrain.h"
#include "fem/atomic_file.h"
#include "multibody/kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <optional>
#include <stdexcept>

namespace plantar::app {
namespace {

const char* const foot_names[2] = {"right", "left"};

/// vtk/<stem>_NNNNNN.vtp for the links, .vtu for the soles.
std::string frame_name(const std::string& stem, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "_%06d", frame);
  return "vtk/" + stem + number + (stem == "links" ? ".vtp" : ".vtu");
}

} // namespace

SceneVtkWriter::SceneVtkWriter(const HumanoidSimulation& simulation,
                               const std::filesystem::path& urdf_file, double stick_radius,
                               const std::filesystem::path& directory, int collection_every)
    : directory_(directory), data_(simulation.model()), collection_every_(collection_every) {
  if (collection_every < 1)
    throw std::invalid_argument(
        "Output/VTK collection every = " + std::to_string(collection_every) + ": must be >= 1");
  shapes_ = make_link_shapes(simulation.model(), urdf_file, stick_radius);
  has_soles_ = simulation.foot_model().has_fields();
  for (int i = 0; i < simulation.pads().size(); ++i)
    pads_.push_back("pad_" + simulation.pads().name(i));
  std::filesystem::create_directories(directory_ / "vtk");
  has_terrain_ = simulation.terrain().level_height() != std::optional<double>(0.0);
  if (has_terrain_)
    write_terrain(simulation);
}

void SceneVtkWriter::write_terrain(const HumanoidSimulation& simulation) const {
  // The extent: the soles at t = 0 and planned at the end, +- 0.5 m.
  multibody::Data data(simulation.model());
  multibody::forward_kinematics(simulation.model(), data, simulation.q());
  const FootModel& feet = simulation.foot_model();
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e300), high = -low;
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Vector3d start =
        multibody::frame_placement(simulation.model(), data, feet.sole_frame(foot)).translation;
    const Eigen::Vector3d end = foot == 0 ? simulation.summary().planned_right_sole
                                          : simulation.summary().planned_left_sole;
    low = low.cwiseMin(start.head<2>()).cwiseMin(end.head<2>());
    high = high.cwiseMax(start.head<2>()).cwiseMax(end.head<2>());
  }
  low.array() -= 0.5;
  high.array() += 0.5;
  const contact::Terrain& terrain = simulation.terrain();
  double spacing = 0.005;
  if (const auto* rough = dynamic_cast<const contact::RoughTerrain*>(&terrain))
    spacing = std::min(spacing, 2.0 * rough->spacing()); // l/4
  const int nx = static_cast<int>(std::ceil((high.x() - low.x()) / spacing)) + 1;
  const int ny = static_cast<int>(std::ceil((high.y() - low.y()) / spacing)) + 1;
  fem::write_file_atomically(directory_ / terrain_file, [&](std::ostream& out) {
    out << std::setprecision(9) << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"StructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "<StructuredGrid WholeExtent=\"0 " << nx - 1 << " 0 " << ny - 1 << " 0 0\">\n"
        << "<Piece Extent=\"0 " << nx - 1 << " 0 " << ny - 1 << " 0 0\">\n"
        << "<PointData Scalars=\"height\" Normals=\"normal\">\n"
        << "<DataArray type=\"Float64\" Name=\"height\" format=\"ascii\">\n";
    auto x_of = [&](int i) { return low.x() + i * spacing; };
    auto y_of = [&](int j) { return low.y() + j * spacing; };
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        out << terrain.height(x_of(i), y_of(j)) << "\n";
    out << "</DataArray>\n"
        << "<DataArray type=\"Float64\" Name=\"normal\" NumberOfComponents=\"3\" "
           "format=\"ascii\">\n";
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d n = contact::terrain_normal(terrain.gradient(x_of(i), y_of(j)));
        out << n.x() << " " << n.y() << " " << n.z() << "\n";
      }
    out << "</DataArray>\n</PointData>\n<Points>\n"
        << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        out << x_of(i) << " " << y_of(j) << " " << terrain.height(x_of(i), y_of(j)) << "\n";
    out << "</DataArray>\n</Points>\n</Piece>\n</StructuredGrid>\n</VTKFile>\n";
  });
}

SceneVtkWriter::~SceneVtkWriter() {
  try {
    finish();
  } catch (...) { // already unwinding or finished: the frames themselves are written
  }
}

void SceneVtkWriter::finish() {
  if (collection_frames_ != n_frames())
    write_pvd();
}

void SceneVtkWriter::write(const HumanoidSimulation& simulation) {
  const int frame = n_frames();
  multibody::forward_kinematics(simulation.model(), data_, simulation.q());
  write_links_vtp(simulation.model(), data_, shapes_, directory_ / frame_name("links", frame));
  if (has_soles_) {
    const FootModel& feet = simulation.foot_model();
    for (int foot = 0; foot < 2; ++foot)
      feet.write_fields(
          foot, multibody::frame_placement(simulation.model(), data_, feet.sole_frame(foot)),
          directory_ / frame_name(std::string("sole_") + foot_names[foot], frame));
  }
  for (int i = 0; i < static_cast<int>(pads_.size()); ++i)
    simulation.pads().write_fields(i, data_, directory_ / frame_name(pads_[i], frame));
  times_.push_back(simulation.time());
  if (n_frames() - collection_frames_ >= collection_every_)
    write_pvd();
}

void SceneVtkWriter::write_pvd() {
  collection_frames_ = n_frames();
  auto write = [&](const std::string& name, const std::vector<std::string>& stems,
                   bool with_terrain) {
    fem::write_file_atomically(directory_ / name, [&](std::ostream& out) {
      out << std::setprecision(10)
          << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
          << "<Collection>\n";
      for (std::size_t i = 0; i < times_.size(); ++i) {
        for (std::size_t part = 0; part < stems.size(); ++part)
          out << "<DataSet timestep=\"" << times_[i] << "\" part=\"" << part << "\" file=\""
              << frame_name(stems[part], static_cast<int>(i)) << "\"/>\n";
        if (with_terrain) // scene.pvd: the terrain, the same file at every time
          out << "<DataSet timestep=\"" << times_[i] << "\" part=\"" << stems.size() << "\" file=\""
              << terrain_file << "\"/>\n";
      }
      out << "</Collection>\n</VTKFile>\n";
    });
  };
  std::vector<std::string> all{"links"};
  if (has_soles_)
    for (const char* foot : foot_names)
      all.push_back(std::string("sole_") + foot);
  all.insert(all.end(), pads_.begin(), pads_.end());
  for (const std::string& part : all)
    write(part + ".pvd", {part}, false);
  write("scene.pvd", all, has_terrain_);
}

} // namespace plantar::app
