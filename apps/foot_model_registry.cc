#include "apps/foot_model_registry.h"

#include "apps/compliant_ankle_foot.h"
#include "apps/condensed_sole_foot.h"
#include "apps/hyperelastic_sole_foot.h"
#include "apps/rigid_foot.h"
#include "apps/scene.h"
#include "apps/viscoelastic_sole_foot.h"

#include <stdexcept>

namespace plantar::app {
namespace {

template <class Model> std::unique_ptr<FootModel> make(const Scene& scene) {
  return std::make_unique<Model>(scene);
}

/// Sole/Model picks the FEM sole's implementation.
std::unique_ptr<FootModel> make_fem_sole(const Scene& scene) {
  if (sole_model(scene.sole) == SoleModel::hyperelastic)
    return make<HyperelasticSoleFoot>(scene);
  if (has_viscoelastic_material(scene.sole.materials))
    return make<ViscoelasticSoleFoot>(scene);
  return make<CondensedSoleFoot>(scene);
}

} // namespace

const std::vector<FootFormEntry>& foot_form_table() {
  static const std::vector<FootFormEntry> table{
      {FootForm::rigid, "rigid", "8 contact points on each sole outline (Sole/Length x Sole/Width)",
       make<RigidFoot>},
      {FootForm::compliant_ankle, "compliant ankle",
       "the same points plus a passive 3-DoF spring-damper between ankle and foot (paper eq. "
       "13)",
       make<CompliantAnkleFoot>},
      {FootForm::fem_sole, "fem sole",
       "the FEM sole of subsection Sole condensed on its bottom nodes under each foot (eq. "
       "11-12), the robot's reference raised by Sole/Thickness",
       make_fem_sole},
  };
  return table;
}

namespace {
const FootFormEntry& entry(FootForm form) {
  for (const FootFormEntry& e : foot_form_table())
    if (e.form == form)
      return e;
  throw std::logic_error("foot form without a row in foot_model_registry.cc");
}
} // namespace

const char* to_string(FootForm form) {
  return entry(form).name;
}

std::string foot_form_names() {
  std::string names;
  for (const FootFormEntry& e : foot_form_table())
    names += (names.empty() ? "" : "|") + std::string(e.name);
  return names;
}

std::string foot_form_help() {
  std::string help;
  for (const FootFormEntry& e : foot_form_table())
    help += (help.empty() ? "" : "; ") + std::string(e.name) + ": " + e.help;
  return help + ".";
}

FootForm parse_foot_form(const std::string& name, const std::string& parameter) {
  for (const FootFormEntry& e : foot_form_table())
    if (name == e.name)
      return e.form;
  throw std::invalid_argument(parameter + " = '" + name + "': allowed " + foot_form_names());
}

std::unique_ptr<FootModel> make_foot_model(const Scene& scene) {
  return entry(scene.robot.foot_form).make(scene);
}

} // namespace plantar::app
