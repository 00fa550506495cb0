#pragma once
// Loading a humanoid scene of scenes/ with overrides, for the tests of tests/apps.

#include "apps/humanoid_simulation.h"
#include "apps/scene.h"

#include <deal.II/base/parameter_handler.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace plantar::app::testing {

/// scenes/<name>.prm with each ("Subsection/Entry", value) of @p overrides set afterwards.
inline Scene
load_humanoid_scene(const std::string& name,
                    const std::vector<std::pair<std::string, std::string>>& overrides) {
  dealii::ParameterHandler prm;
  const std::filesystem::path file =
      std::filesystem::path(PLANTAR_SOURCE_DIR) / "scenes" / (name + ".prm");
  load_scene(file, prm);
  for (const auto& [path, value] : overrides) {
    const auto slash = path.find('/');
    if (slash == std::string::npos) {
      prm.set(path, value);
    } else {
      prm.enter_subsection(path.substr(0, slash));
      prm.set(path.substr(slash + 1), value);
      prm.leave_subsection();
    }
  }
  Scene scene;
  scene.parse(prm, file.parent_path());
  return scene;
}

/// Runs @p simulation to its end; returns the message of the std::runtime_error that stopped it
/// (a fall, a numerical failure), empty when it completed.
inline std::string run_to_stop(HumanoidSimulation& simulation) {
  try {
    simulation.run();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return {};
}

inline const char* const foot_forms[] = {"rigid", "compliant ankle", "fem sole"};

/// GoogleTest name of a foot-form parameter: "compliant ankle" -> "compliant_ankle".
template <class Info> std::string foot_form_name(const Info& info) {
  std::string name = info.param;
  for (auto& c : name)
    if (c == ' ')
      c = '_';
  return name;
}

} // namespace plantar::app::testing
