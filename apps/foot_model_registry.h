#pragma once
// The foot forms of the humanoid scenes: one table (foot_model_registry.cc) maps each form to
// its scene-file name (Robot/Foot form), its help and the factory of its FootModel. Adding a
// form: a FootForm value, one FootModel file, one row of the table (docs/user_guide.md).

#include <memory>
#include <string>
#include <vector>

namespace plantar::app {

struct Scene;
class FootModel;

/// How the feet touch the ground.
enum class FootForm {
  rigid,           ///< rigid soles: 8 contact points on the sole outline (corners + edge midpoints)
  compliant_ankle, ///< rigid points + the passive 3-DoF ankle spring-damper (paper eq. 13)
  fem_sole,        ///< a condensed FEM sole under each foot (paper eq. 11-12)
};

/// One row of the table.
struct FootFormEntry {
  FootForm form;
  const char* name; ///< value of Robot/Foot form
  const char* help; ///< one sentence for the parameter's help
  std::unique_ptr<FootModel> (*make)(const Scene& scene);
};

/// Every foot form, in the order of the parameter's help.
const std::vector<FootFormEntry>& foot_form_table();
/// The scene-file name of @p form.
const char* to_string(FootForm form);
/// The names joined by '|' (a deal.II Selection pattern).
std::string foot_form_names();
/// "name: help; name: help ..." for the parameter's help.
std::string foot_form_help();
/// The form named @p name. Throws std::invalid_argument naming @p parameter, the value and the
/// allowed names.
FootForm parse_foot_form(const std::string& name, const std::string& parameter);
/// The foot model of @p scene's Robot/Foot form (meshes and condenses a sole: the long part).
std::unique_ptr<FootModel> make_foot_model(const Scene& scene);

} // namespace plantar::app
