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

namespace {

// The fastest of the runs of each loading stage of one file, and what the load found.
struct LoadTimes {
  double read = INFINITY, validate = INFINITY, build = INFINITY, repair = INFINITY, clean = INFINITY;
  size_t vertices = 0, faces = 0;
  long repairs = 0;
};

// One run of load_mesh's stages on `path`, each stage's time kept in `t` where it is the fastest.
void time_load_once(const std::string& path, LoadTimes& t) {
  Stopwatch sw;
  MeshSoup soup = read_mesh_soup(path);
  keep_fastest(t.read, sw.lap());
  EdgeTable table;
  const LoadReport lr = prepare_soup(soup, path, LoadOptions{}, &table);
  keep_fastest(t.validate, sw.lap());
  const Mesh mesh = build_mesh(soup, table.edges() ? &table : nullptr);
  keep_fastest(t.build, sw.lap());
  validate_mesh(soup);
  keep_fastest(t.clean, sw.lap());
  keep_fastest(t.repair, lr.repair_seconds);
  t.vertices = mesh.n_vertices(), t.faces = mesh.n_faces(), t.repairs = long(lr.repair.steps.size());
}

nlohmann::json load_row(const std::string& path, int repeat) {
  LoadTimes t;
  for (int i = 0; i < repeat; ++i) time_load_once(path, t);
  const double total = t.read + t.validate + t.build;
  return {{"file", path}, {"vertices", t.vertices}, {"faces", t.faces}, {"read_s", t.read}, {"validate_s", t.validate},
          {"build_s", t.build}, {"total_s", total}, {"repair_s", t.repair}, {"repair_share", t.repair / total},
          {"repair_steps", t.repairs}, {"validate_repaired_s", t.clean}, {"defect_share", (t.validate - t.clean) / total}};
}

}  // namespace

// Per file: reading the soup, validating it (and repairing it where validation says repair may
// help, as load_mesh does), building the halfedge mesh (the stages of load_mesh), the fastest of
// `repeat` runs each, and the process's peak memory after them. Beside them, the repair's share of
// the load, and the validation of the repaired soup: what the load of the same mesh, clean, spends
// on validation (the difference is what a defect costs).
int run_load_bench(const BenchOptions& o) {
  const nlohmann::json rows = rows_per_file(o.load, "loaded", [&](const std::string& path) { return load_row(path, o.repeat); });
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
