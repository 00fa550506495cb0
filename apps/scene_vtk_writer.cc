#include "apps/scene_vtk_writer.h"

#include "fem/atomic_file.h"
#include "multibody/kinematics.h"

#include <cstdio>
#include <iomanip>

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
                               const std::filesystem::path& directory)
    : directory_(directory), data_(simulation.model()) {
  shapes_ = make_link_shapes(simulation.model(), urdf_file, stick_radius);
  has_soles_ = simulation.foot_model().has_fields();
  for (int i = 0; i < simulation.pads().size(); ++i)
    pads_.push_back("pad_" + simulation.pads().name(i));
  std::filesystem::create_directories(directory_ / "vtk");
}

SceneVtkWriter::~SceneVtkWriter() = default;

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
  write_pvd();
}

void SceneVtkWriter::write_pvd() const {
  auto write = [&](const std::string& name, const std::vector<std::string>& stems) {
    fem::write_file_atomically(directory_ / name, [&](std::ostream& out) {
      out << std::setprecision(10)
          << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
          << "<Collection>\n";
      for (std::size_t i = 0; i < times_.size(); ++i)
        for (std::size_t part = 0; part < stems.size(); ++part)
          out << "<DataSet timestep=\"" << times_[i] << "\" part=\"" << part << "\" file=\""
              << frame_name(stems[part], static_cast<int>(i)) << "\"/>\n";
      out << "</Collection>\n</VTKFile>\n";
    });
  };
  std::vector<std::string> all{"links"};
  if (has_soles_)
    for (const char* foot : foot_names)
      all.push_back(std::string("sole_") + foot);
  all.insert(all.end(), pads_.begin(), pads_.end());
  for (const std::string& part : all)
    write(part + ".pvd", {part});
  write("scene.pvd", all);
}

} // namespace plantar::app
