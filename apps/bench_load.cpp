// sdm bench --load: loading large meshes (docs/BENCHMARKS.md, "Loading large meshes").
#include "apps/bench.h"
#include "apps/commands.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"

#include <cmath>
#include <iomanip>
#include <iostream>

namespace sdm::cli {

// Per file: reading the soup, validating it (and repairing it where validation says repair may
// help, as load_mesh does), building the halfedge mesh (the stages of load_mesh), the fastest of
// `repeat` runs each, and the process's peak memory after them. Beside them, the repair's share of
// the load, and the validation of the repaired soup: what the load of the same mesh, clean, spends
// on validation (the difference is what a defect costs).
int run_load_bench(const BenchOptions& o) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string& path : o.load) {
    double read = INFINITY, validate = INFINITY, build = INFINITY, repair = INFINITY, clean = INFINITY;
    size_t vertices = 0, faces = 0;
    long repairs = 0;
    for (int i = 0; i < o.repeat; ++i) {
      Stopwatch sw;
      MeshSoup soup = read_mesh_soup(path);
      const double r = sw.lap();
      EdgeTable table;
      const LoadReport lr = prepare_soup(soup, path, LoadOptions{}, &table);
      const double v = sw.lap();
      const Mesh mesh = build_mesh(soup, table.edges() ? &table : nullptr);
      const double b = sw.lap();
      validate_mesh(soup);
      clean = std::min(clean, sw.lap());
      read = std::min(read, r), validate = std::min(validate, v), build = std::min(build, b), repair = std::min(repair, lr.repair_seconds);
      vertices = mesh.n_vertices(), faces = mesh.n_faces(), repairs = long(lr.repair.steps.size());
    }
    std::cerr << "bench: loaded " << path << "\n";
    const double total = read + validate + build;
    rows.push_back({{"file", path}, {"vertices", vertices}, {"faces", faces}, {"read_s", read}, {"validate_s", validate},
                    {"build_s", build}, {"total_s", total}, {"repair_s", repair}, {"repair_share", repair / total},
                    {"repair_steps", repairs}, {"validate_repaired_s", clean}, {"defect_share", (validate - clean) / total}});
  }
  if (o.json) {
    print_json({{"machine", machine_line()}, {"loads", rows}, {"peak_rss_mb", double(peak_rss_bytes()) / 1e6}});
    return 0;
  }
  std::cout << "Loading (fastest of " << o.repeat << "; " << machine_line() << ")\n"
            << "| file | vertices | faces | read (s) | validate, repair (s) | build (s) | total (s) | repair (s) | of the load | "
               "validate repaired (s) | defects' share |\n"
            << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    std::cout << "| " << r["file"].get<std::string>() << " | " << r["vertices"] << " | " << r["faces"] << " | " << std::fixed
              << std::setprecision(3) << r["read_s"].get<double>() << " | " << r["validate_s"].get<double>() << " | "
              << r["build_s"].get<double>() << " | " << r["total_s"].get<double>() << " | " << r["repair_s"].get<double>() << " | "
              << std::setprecision(1) << 100 * r["repair_share"].get<double>() << " % | " << std::setprecision(3)
              << r["validate_repaired_s"].get<double>() << " | " << std::setprecision(1) << 100 * r["defect_share"].get<double>() << " % |\n";
  std::cout << "Peak memory of the process: " << std::setprecision(0) << double(peak_rss_bytes()) / 1e6 << " MB\n";
  return 0;
}

}  // namespace sdm::cli
