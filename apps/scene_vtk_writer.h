#pragma once
// The ParaView series of a humanoid run: one frame per call of write(), in the world frame.
//
// <directory>/vtk/links_NNNNNN.vtp        the robot's links (scene_vtk_links.h)
// <directory>/vtk/sole_{right,left}_NNNNNN.vtu   (foot models with fields: FootModel::
//     write_fields; the FEM soles of apps/sole_patch_foot.h) each sole, its points
//     at their undeformed positions x = R_s X + p_s (X: mesh coordinates, R_s, p_s: the
//     r_sole/l_sole frame in the world), with point data
//       displacement          u = R_s u_sole (m, world), u_sole recovered from the contact
//                             nodes: u_n = -K_nn^-1 K_nc u_c (coupling/condensed_sole.h)
//       contact_displacement  the stepper's patch displacement u_c (m, world) on the bottom
//                             nodes, 0 elsewhere (equals displacement there)
//       contact_force         f_k = p_k / dt (N, world, ground on sole) on the bottom nodes
//       contact_pressure      f_z,k / a_k (Pa), a_k = int_bottom N_k ds the node's consistent
//                             area (0 where a_k <= 0, e.g. vertices of P2 triangles)
//       contact_node          1 on the bottom (contact) nodes, 0 elsewhere
//       strain, stress (sole frame, Pa), von_mises (Pa)        (fem/field_output.h)
//     and cell data material_id. "Warp By Vector" with displacement shows the deformed sole.
//     Sole/Model = hyperelastic (coupling/nonlinear_condensed_sole.h): the same arrays, with
//     displacement the sole's full field at its last Newton check (the forces of the last
//     update() that moved more than Sole/Check tolerance; the writer solves nothing, so output
//     does not change the run), strain the Green-Lagrange strain and stress, von_mises the
//     Cauchy stress of the hyperelastic law (sole frame).
// <directory>/vtk/pad_<name>_NNNNNN.vtu   each deformable pad (Pad 1 ... Pad 6, apps/pad_set.h):
//     the same arrays as a linear sole, the pad frame at its place on its link
// <directory>/terrain.vts   the ground (subsection Terrain, contact/terrain.h) unless it is the
//     default plane z = 0, written once: a
//     structured grid of the terrain surface z = h(x, y) over the feet's initial and planned
//     final positions +- 0.5 m (spacing 5 mm, or l/4 of a rough surface if smaller), with point
//     data height (m) and normal (the unit normal n)
// <directory>/{links,sole_right,sole_left,pad_<name>}.pvd   one time series each
// <directory>/scene.pvd      all parts (0 links, then right and left sole, then the pads, then
//     the terrain: the same file at every time)
// The .pvd files are rewritten (atomically) every collection_every frames and by finish() (and
// the destructor): a run that fails keeps a readable series of the frames written so far.
// Frames allocate (output steps only).

#include "apps/humanoid_simulation.h"
#include "apps/scene_vtk_links.h"
#include "multibody/data.h"

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace plantar::app {

class SceneVtkWriter {
public:
  /// Prepares the link shapes (@p urdf_file: the model's URDF; @p stick_radius, m, > 0) and
  /// asks @p simulation's foot model whether it has sole fields; creates <directory>/vtk.
  /// @p collection_every (>= 1): the .pvd files are rewritten every this many frames.
  SceneVtkWriter(const HumanoidSimulation& simulation, const std::filesystem::path& urdf_file,
                 double stick_radius, const std::filesystem::path& directory,
                 int collection_every = 1);
  /// Calls finish(), ignoring its errors (a run being unwound by an exception).
  ~SceneVtkWriter();

  /// Writes the frame of @p simulation's current state (time simulation.time()).
  void write(const HumanoidSimulation& simulation);
  /// Rewrites the .pvd files if frames were written since their last rewrite.
  void finish();
  /// The terrain surface's grid file, relative to the directory.
  static constexpr const char* terrain_file = "terrain.vts";
  int n_frames() const { return static_cast<int>(times_.size()); }

private:
  void write_pvd();
  /// terrain.vts (atomically) over the feet of @p simulation at t = 0 and planned at the end.
  void write_terrain(const HumanoidSimulation& simulation) const;

  std::filesystem::path directory_;
  std::vector<LinkShape> shapes_;
  multibody::Data data_;
  bool has_soles_ = false;        ///< the foot model writes sole fields
  bool has_terrain_ = false;      ///< terrain.vts written (not the default ground z = 0)
  std::vector<std::string> pads_; ///< "pad_<name>" per pad
  std::vector<double> times_;
  int collection_every_ = 1;
  int collection_frames_ = 0; ///< frames in the .pvd files on disk
};

} // namespace plantar::app
