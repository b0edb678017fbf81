#include "apps/convert_mesh.h"

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <utility>

namespace sdm::cli {

sdm::LoadReport convert(const std::string& in, const std::string& out, bool strict, double& rounding) {
  if (strict) input_settings().no_repair = true;
  sdm::LoadedMesh m = load_input(in);
  if (strict) check_strict(m.report.validation, in);
  for (const auto& f : m.report.validation.findings)
    progress("note: " + std::to_string(f.count) + " " + f.kind + ", e.g. " + f.example);
  sdm::write_mesh(m.mesh, out, m.texture);
  rounding = note_float32_rounding(m.mesh, out);
  progress("wrote " + out + " (" + std::to_string(m.mesh.n_vertices()) + " vertices, " + std::to_string(m.mesh.n_faces()) + " faces)");
  return std::move(m.report);
}

}  // namespace sdm::cli
