#include "apps/convert_mesh.h"

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <utility>

namespace sdm::cli {

Converted convert(const std::string& in, const std::string& out, bool strict) {
  if (strict) input_settings().no_repair = true;
  sdm::LoadedMesh m = load_input(in);
  if (strict) check_strict(m.report.validation, in);
  for (const auto& f : m.report.validation.findings)
    progress("note: " + std::to_string(f.count) + " " + f.kind + ", e.g. " + f.example);
  sdm::write_mesh(m.mesh, out, m.texture);
  Converted c;
  c.rounding = note_float32_rounding(m.mesh, out);
  c.vertices = m.mesh.n_vertices();
  c.faces = m.mesh.n_faces();
  c.report = std::move(m.report);
  return c;
}

void print_written(const nlohmann::json& summary) {
  progress("wrote " + summary["output"].get<std::string>() + " (" + std::to_string(summary["vertices"].get<size_t>()) + " vertices, " +
           std::to_string(summary["faces"].get<size_t>()) + " faces)");
}

}  // namespace sdm::cli
