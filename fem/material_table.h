#pragma once
// Materials per region of a sole, written in a scene as
//   "rubber: E=4e6, nu=0.3; heel_pad: law=linear, E=1e6, nu=0.45"
// and resolved against the mesh's physical volume names.

#include "fem/linear_elastic_material.h"
#include "fem/mesh_import.h"

#include <map>
#include <string>

namespace plantar::fem {

/// One region's law and its named parameters, as written in the scene.
struct MaterialSpec {
  std::string region;
  std::string law = "linear";
  std::map<std::string, double> values; ///< e.g. {"E": 4e6, "nu": 0.3}
};

/// Parses a materials string (see above). Throws std::invalid_argument naming
/// @p parameter_name and the offending text on malformed input.
std::map<std::string, MaterialSpec> parse_material_specs(const std::string& text,
                                                         const std::string& parameter_name);

/// Linear-elastic materials indexed by deal.II material id.
class MaterialTable {
public:
  /// Resolves @p specs against the mesh's physical volumes: every volume of
  /// the mesh that holds cells must have a spec, and every spec must name a
  /// volume of the mesh. Throws std::invalid_argument naming the region, the
  /// mesh file and the parameter otherwise, or if a law is not "linear".
  MaterialTable(const std::map<std::string, MaterialSpec>& specs, const PhysicalGroups& groups);
  /// One material for every cell whatever its id (tests, single-region meshes).
  explicit MaterialTable(const LinearElasticMaterial& material);

  /// The material of cells with material id @p id (throws if none).
  const LinearElasticMaterial& operator[](dealii::types::material_id id) const;

private:
  std::map<dealii::types::material_id, LinearElasticMaterial> by_id_;
  bool uniform_ = false;
};

} // namespace plantar::fem
