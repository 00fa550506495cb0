#pragma once
// A scene: every physical and numerical parameter of a run, read from a .prm
// file with deal.II's ParameterHandler. Each subsection is one struct with
// declare() and parse().

#include "apps/humanoid_parameters.h"
#include "apps/pad_parameters.h"
#include "apps/static_contact_parameters.h"
#include "apps/sweep_parameters.h"
#include "apps/terrain_parameters.h"
#include "fem/sole_parameters.h"

#include <deal.II/base/parameter_handler.h>

#include <filesystem>
#include <string>

namespace plantar::app {

/// Subsection "Static load": a uniform ground reaction on the sole's bottom face.
struct StaticLoadParameters {
  double normal_force = 600; ///< N, total, pushing the bottom face up (+z)
  double tangential_x = 0;   ///< N, total, along x
  double tangential_y = 0;   ///< N, total, along y
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Subsection "Output".
struct OutputParameters {
  bool write_vtu = true; ///< static sole: sole.vtu; humanoid scenes: the ParaView series
  bool write_csv = true; ///< humanoid scenes: CSV time series
  int output_every = 1;  ///< humanoid scenes: one CSV row every this many steps, >= 1
  int vtk_every = 40;    ///< humanoid scenes: one ParaView frame every this many steps, >= 1
  /// Humanoid scenes: rewrite the .pvd collections every this many frames (and after the last
  /// frame, also of a failed run), >= 1.
  int vtk_collection_every = 1;
  double vtk_stick_radius = 0.02; ///< m, radius of the links drawn as sticks
  /// Hz, [0, 1e4]: cut-off of the waist accelerometer's second-order Butterworth low-pass
  /// (apps/butterworth_low_pass.h); 0, or at or above the Nyquist frequency 1 / (2 dt): raw
  /// (the samples hold no higher frequency). 100 Hz: below the Nyquist frequency of every time
  /// step of the convergence study (250 Hz at dt = 2 ms), within the range of a MEMS IMU's
  /// digital low-pass (docs/walking.md).
  double accelerometer_bandwidth = 100;
  /// Landings (apps/landing_detector.h): touchdown when a foot's F_z rises through this
  /// fraction of the robot's weight, (0, 1).
  double landing_threshold = 0.01;
  double landing_window = 0.05; ///< s, (0, 1]: the landing figures cover this after touchdown
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Scene type: what a run does.
enum class SceneType {
  static_sole,    ///< the sole alone under a uniform load (static_sole_job.h)
  static_contact, ///< the sole on the ground under a rigid foot, distributed (static_contact_job.h)
  stand,          ///< humanoid scenes (humanoid_simulation.h): standing still,
  drop,           ///< released above the ground,
  lean,           ///< waist roll ramp,
  walk,           ///< the walk of subsection Walking
};
/// The scene-file name of @p type ("static sole", "stand", ...).
const char* to_string(SceneType type);

struct Scene {
  SceneType type = SceneType::static_sole;
  fem::SoleParameters sole;
  SoleReductionParameters sole_reduction; ///< subsection Sole, humanoid scenes (fem sole)
  SoleValidityParameters sole_validity;   ///< subsection Sole, humanoid scenes (fem sole)
  StaticLoadParameters static_load;
  StaticContactParameters static_contact; ///< subsection Static contact
  RobotParameters robot;
  ContactParameters contact;
  ControlParameters control;
  WalkingSceneParameters walking;
  LeanSceneParameters lean;
  SimulationParameters simulation;
  PadParameters pads;             ///< subsections Pad 1 ... Pad 6, humanoid scenes
  TerrainSceneParameters terrain; ///< subsection Terrain, humanoid scenes
  OutputParameters output;
  SweepParameters sweep; ///< plantar sweep only

  /// Declares every subsection in @p prm.
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory);
};

/// Declares every entry in @p prm and reads @p file into it. A line 'include PATH' reads PATH
/// there (resolved like the scene's other paths: the scene's directory, then the Plantar tree).
/// Throws std::runtime_error naming the file (and, for syntax or pattern errors, the line, the
/// parameter, its value and the allowed pattern).
void read_scene_file(const std::filesystem::path& file, dealii::ParameterHandler& prm);

/// Declares, reads @p file (read_scene_file) and parses it. Throws std::runtime_error with one
/// clear message naming the file (and, for syntax or pattern errors, the line,
/// the parameter, its value and the allowed pattern).
Scene load_scene(const std::filesystem::path& file, dealii::ParameterHandler& prm);

} // namespace plantar::app
