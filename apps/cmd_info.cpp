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

void print_findings(const sdm::MeshReport& r) {
  if (r.findings.empty()) std::cout << "  findings        none\n";
  for (const auto& f : r.findings)
    std::cout << "  " << (f.fatal ? "ERROR " : "note  ") << f.count << " " << f.kind << ", e.g. " << f.example
              << (f.fatal ? "\n        fix: " + f.fix : "") << "\n";
}

void print_text(const std::string& path, const sdm::MeshSoup& soup, const sdm::MeshReport& r, const sdm::RepairReport& repair,
                const sdm::MeshReport& final_report) {
  std::cout << path << "\n";
  std::cout << "  vertices        " << r.vertices << "\n";
  std::cout << "  faces           " << r.faces << "\n";
  std::cout << "  edges           " << r.edges << "\n";
  std::cout << "  parts           " << r.parts << "\n";
  std::cout << "  genus per part ";
  for (int g : r.genus_per_part) std::cout << ' ' << (g < 0 ? std::string("open") : std::to_string(g));
  std::cout << "\n  boundary loops  " << r.boundary_loops << "\n";
  std::cout << std::setprecision(6) << "  bounding box    [" << r.bbox_min.transpose() << "] - [" << r.bbox_max.transpose() << "]\n";
  std::cout << "  uv              " << (soup.uv.empty() ? "no" : "yes") << "\n";
  if (!soup.texture.empty()) std::cout << "  texture         " << soup.texture << "\n";
  print_findings(r);
  if (repair.changed()) {
    std::cout << "  repair (what every command does before it works on the mesh)\n";
    for (const auto& s : repair.steps)
      std::cout << "        " << s.count << " " << s.kind << (s.example.empty() ? "" : ", e.g. " + s.example) << "\n";
    std::cout << "  repaired        " << final_report.vertices << " vertices, " << final_report.faces << " faces, "
              << final_report.parts << " parts, " << final_report.boundary_loops << " boundary loops\n";
    bool fatal = false;
    for (const auto& f : final_report.findings) fatal |= f.fatal;
    if (fatal) print_findings(final_report);
  }
  std::cout << "  pipeline        " << (final_report.usable() ? (repair.changed() ? "ok after repair" : "ok") : "refused") << "\n";
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
            if (o->json) {
              auto j = r.to_json();
              j["file"] = o->mesh;
              j["uv"] = !soup.uv.empty();
              j["texture"] = soup.texture;
              j["repair"] = repair.to_json();
              if (repair.changed()) j["repaired"] = final_report.to_json();
              j["usable"] = final_report.usable();
              print_json(j);
            } else {
              print_text(o->mesh, soup, r, repair, final_report);
            }
            if (!final_report.usable()) {
              if (!o->json) std::cerr << final_report.refusal(o->mesh) << std::endl;
              return 2;
            }
            if (o->strict) check_strict(r, o->mesh);
            return 0;
          }};
}

}  // namespace sdm::cli
