#include "apps/cli_common.h"
#include "apps/cloud_input.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/mesh/validate_mesh.h"

#include <iomanip>
#include <memory>

namespace sdm::cli {
namespace {

// The findings of a report (MeshReport::to_json's "findings") as text.
void print_findings(const nlohmann::json& findings) {
  if (findings.empty()) std::cout << "  findings        none\n";
  for (const auto& f : findings) {
    const bool fatal = f["fatal"].get<bool>();
    std::cout << "  " << (fatal ? "ERROR " : "note  ") << f["count"] << " " << f["kind"].get<std::string>() << ", e.g. "
              << f["example"].get<std::string>() << (fatal ? "\n        fix: " + f["fix"].get<std::string>() : "") << "\n";
  }
}

Eigen::Vector3d vector_of(const nlohmann::json& x) { return {x[0].get<double>(), x[1].get<double>(), x[2].get<double>()}; }

// Info's summary (its --json object) as text.
void print_info_text(const nlohmann::json& j) {
  std::cout << j["file"].get<std::string>() << "\n";
  std::cout << "  vertices        " << j["vertices"] << "\n";
  std::cout << "  faces           " << j["faces"] << "\n";
  std::cout << "  edges           " << j["edges"] << "\n";
  std::cout << "  parts           " << j["parts"] << "\n";
  std::cout << "  genus per part ";
  for (const auto& g : j["genus_per_part"]) std::cout << ' ' << (g.get<int>() < 0 ? std::string("open") : std::to_string(g.get<int>()));
  std::cout << "\n  boundary loops  " << j["boundary_loops"] << "\n";
  std::cout << std::setprecision(6) << "  bounding box    [" << vector_of(j["bbox_min"]).transpose() << "] - ["
            << vector_of(j["bbox_max"]).transpose() << "]\n";
  std::cout << "  uv              " << (j["uv"].get<bool>() ? "yes" : "no") << "\n";
  if (!j["texture"].get<std::string>().empty()) std::cout << "  texture         " << j["texture"].get<std::string>() << "\n";
  print_findings(j["findings"]);
  const bool changed = j["repair"]["changed"].get<bool>();
  if (changed) {
    std::cout << "  repair (what every command does before it works on the mesh)\n";
    for (const auto& s : j["repair"]["steps"]) {
      const std::string example = s["example"].get<std::string>();
      std::cout << "        " << s["count"] << " " << s["kind"].get<std::string>() << (example.empty() ? "" : ", e.g. " + example) << "\n";
    }
    const nlohmann::json& fixed = j["repaired"];
    std::cout << "  repaired        " << fixed["vertices"] << " vertices, " << fixed["faces"] << " faces, " << fixed["parts"] << " parts, "
              << fixed["boundary_loops"] << " boundary loops\n";
    bool fatal = false;
    for (const auto& f : fixed["findings"]) fatal |= f["fatal"].get<bool>();
    if (fatal) print_findings(fixed["findings"]);
  }
  std::cout << "  pipeline        " << (j["usable"].get<bool>() ? (changed ? "ok after repair" : "ok") : "refused") << "\n";
}

}  // namespace

Command add_info_command(CLI::App& parent) {
  struct Opts {
    std::string mesh;
    bool json = false;
    bool strict = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "info", "Describe a mesh: counts, parts, genus, boundary loops, bounding box, validation findings and what repair\n"
              "would do. Exits 2 when the mesh cannot go through the pipeline even repaired, so scripts can use it as a check.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf) or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  app->add_flag("--strict", o->strict,
                "Judge the mesh as it is, without repair, and exit 2 also for tolerated findings (degenerate faces, isolated\n"
                "vertices, holes)");
  add_repair_options(app);
  return {app, [o]() {
            if (sdm::is_point_cloud_file(o->mesh)) return cloud_info(o->mesh, o->json);
            sdm::MeshSoup soup = sdm::read_mesh_soup(o->mesh);
            sdm::LoadOptions options = load_options();
            if (o->strict) options.repair = false;
            options.report_as_read = true;  // the file as it is, in full, before its repair
            sdm::LoadReport lr = sdm::repair_and_validate(soup, options);
            sdm::MeshReport& final_report = lr.validation;
            if (final_report.usable()) sdm::orient_outward(soup, final_report);  // names a part that was inside out
            const sdm::RepairReport& repair = lr.repair;
            // The file as it is: the report the pipeline goes on with when nothing was repaired.
            const sdm::MeshReport& r = repair.changed() ? lr.as_read : final_report;
            // One summary: --json prints it, the text reads it.
            nlohmann::json j = r.to_json();
            j["file"] = o->mesh;
            j["uv"] = !soup.uv.empty();
            j["texture"] = soup.texture;
            j["repair"] = repair.to_json();
            if (repair.changed()) j["repaired"] = final_report.to_json();
            j["usable"] = final_report.usable();
            if (o->json) print_json(j);
            else print_info_text(j);
            if (!final_report.usable()) {
              if (!o->json) std::cerr << final_report.refusal(o->mesh) << std::endl;
              return 2;
            }
            if (o->strict) check_strict(r, o->mesh);
            return 0;
          }};
}

}  // namespace sdm::cli
