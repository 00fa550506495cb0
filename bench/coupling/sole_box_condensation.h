#pragma once
// The HRP-2 sole of meshes/sole_box.geo (0.2172 x 0.138 x 0.02 m) meshed by gmsh with Q1
// hexahedra (or P1 tetrahedra) of size h, E = 4 MPa, nu = 0.3, top bonded, bottom in contact,
// condensed (bench programs of bench/coupling).

#include "coupling/condensed_sole.h"
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"

#include <filesystem>

namespace plantar::bench {

/// The condensed sole at mesh size @p mesh_size (m), the 3 n_c solves in blocks of
/// @p block_size right-hand sides, or (@p form = factorization) the factor of K kept instead
/// of C; linear tetrahedra instead of Q1 hexahedra if !@p hexahedra; meshes cached in
/// ./mesh-cache.
inline coupling::CondensedSole condense_sole_box(
    double mesh_size, int block_size = 64,
    coupling::CondensationParameters::Form form = coupling::CondensationParameters::Form::dense,
    bool hexahedra = true) {
  fem::MeshRequest request;
  request.geo_file = std::filesystem::path(PLANTAR_SOURCE_DIR) / "meshes" / "sole_box.geo";
  request.numbers = {{"SoleMeshSize", mesh_size}, {"SoleHex", hexahedra ? 1.0 : 0.0}};
  request.cache_directory = std::filesystem::current_path() / "mesh-cache";
  dealii::Triangulation<3> tria;
  const auto groups = fem::import_mesh(fem::generate_mesh(request), {"top", "bottom"}, tria);
  const fem::MaterialTable materials(fem::LinearElasticMaterial(4e6, 0.3, "rubber"));
  coupling::CondensationParameters parameters;
  parameters.attached_boundary = groups.surface("top");
  parameters.contact_boundary = groups.surface("bottom");
  parameters.block_size = block_size;
  parameters.form = form;
  return coupling::CondensedSole(tria, materials, parameters);
}

} // namespace plantar::bench
