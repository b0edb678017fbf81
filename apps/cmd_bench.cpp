#include "apps/commands.h"
#include "libstm/extract_skeleton.h"
#include "libstm/mesh.h"
#include "libstm/primitives.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace sdm_cli {

Command add_bench_command(CLI::App& parent) {
  struct Opts {
    std::string bunny = "../shared/models/cgal/bunny00.off";
    int runs = 3;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "bench", "Time skeleton extraction per stage on the paper's test shapes (Table I) and bunny00;\n"
               "each timing is the minimum over the runs.");
  app->add_option("--bunny", o->bunny, "Path of bunny00.off (skipped with a note when missing)");
  app->add_option("--runs", o->runs, "Runs per model; the minimum is reported")->check(CLI::Range(1, 100));
  app->add_flag("--json", o->json, "Print one JSON object");
  return {app, [o]() {
            // Total seconds of the paper's Table I.
            const std::vector<std::pair<std::string, double>> shapes = {
                {"ypsilon", 2.6}, {"bottle", 6.4}, {"donut", 12.6}, {"triple-torus", 24.1}, {"crossed-cylinders", 84.7}};
            nlohmann::json rows = nlohmann::json::array();
            auto run = [&](const std::string& name, const stm::Mesh& mesh, double paper) {
              double best[4] = {1e300, 1e300, 1e300, 1e300};
              stm::Skeleton sk;
              for (int r = 0; r < o->runs; ++r) {
                stm::SkeletonStats st;
                const auto t0 = std::chrono::steady_clock::now();
                sk = stm::extract_skeleton(mesh, {}, nullptr, &st);
                const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                best[0] = std::min(best[0], st.contraction_seconds);
                best[1] = std::min(best[1], st.surgery_seconds);
                best[2] = std::min(best[2], st.refinement_seconds);
                best[3] = std::min(best[3], total);
              }
              nlohmann::json j = {{"model", name},          {"vertices", mesh.n_vertices()}, {"contraction", best[0]},
                                  {"surgery", best[1]},      {"refinement", best[2]},         {"total", best[3]},
                                  {"nodes", sk.nodes.size()}, {"ends", sk.end_nodes()},       {"branches", sk.branch_nodes()},
                                  {"cycles", sk.cycles()}};
              if (paper > 0) j["paper_total"] = paper, j["speedup"] = paper / best[3];
              rows.push_back(j);
              progress("bench: " + name + " done");
            };
            for (const auto& [name, paper] : shapes) run(name, stm::make_primitive(name), paper);
            std::string note;
            if (std::filesystem::exists(o->bunny)) run("bunny00", stm::load_mesh(o->bunny), 0);
            else note = "bunny00 skipped: " + o->bunny + " not found";
            if (o->json) {
              nlohmann::json j = {{"runs", o->runs}, {"models", rows}};
              if (!note.empty()) j["note"] = note;
              print_json(j);
              return 0;
            }
            std::printf("%-18s %7s %9s %9s %9s %9s %8s %9s  %s\n", "model", "verts", "contract", "surgery", "refine",
                        "total", "paper", "speed-up", "nodes/ends/branches/cycles");
            for (const auto& r : rows) {
              const bool p = r.contains("paper_total");
              std::printf("%-18s %7d %9.3f %9.3f %9.3f %9.3f %8s %9s  %d/%d/%d/%d\n", r["model"].get<std::string>().c_str(),
                          r["vertices"].get<int>(), r["contraction"].get<double>(), r["surgery"].get<double>(),
                          r["refinement"].get<double>(), r["total"].get<double>(),
                          p ? (std::to_string(r["paper_total"].get<double>()).substr(0, 4) + " s").c_str() : "-",
                          p ? (std::to_string(int(r["speedup"].get<double>())) + "x").c_str() : "-", r["nodes"].get<int>(),
                          r["ends"].get<int>(), r["branches"].get<int>(), r["cycles"].get<int>());
            }
            if (!note.empty()) std::printf("%s\n", note.c_str());
            return 0;
          }};
}

}  // namespace sdm_cli
