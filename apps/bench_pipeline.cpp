// sdm bench --pipeline: a mesh through the whole pipeline (docs/BENCHMARKS.md, "Pipeline stages by mesh size").
#include "apps/bench.h"
#include "apps/commands.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <cmath>
#include <iomanip>
#include <iostream>

namespace sdm::cli {

PipelineTimes time_pipeline(const std::string& path, int size, int repeat) {
  PipelineTimes t;
  for (int i = 0; i < repeat; ++i) {
    Stopwatch sw;
    const Mesh mesh = load_mesh(path).mesh;
    keep_fastest(t.load, sw.lap());
    const Skeleton sk = extract_skeleton(mesh);
    keep_fastest(t.skeleton, sw.lap());
    LayoutOptions lo;
    lo.size = size;
    const Layout L = compute_layout(mesh, sk, lo);
    keep_fastest(t.layout, sw.lap());
    EncodeOptions eo;
    eo.fill_unread = false;  // as `sdm encode` writes a file
    const SdmImage im = encode_sdm(mesh, L, eo);
    keep_fastest(t.encode, sw.lap());
    DecodeOptions d;
    d.level = 3;
    t.decode3_faces = decode_sdm(im, d).n_faces();
    keep_fastest(t.decode3, sw.lap());
    t.vertices = mesh.n_vertices();
  }
  return t;
}

namespace {

// One file through every stage, the fastest of `repeat` runs of each.
nlohmann::json pipeline_row(const std::string& path, int repeat, int size) {
  const PipelineTimes t = time_pipeline(path, size, repeat);
  return {{"file", path}, {"vertices", t.vertices}, {"load_s", t.load}, {"skeleton_s", t.skeleton}, {"layout_s", t.layout},
          {"encode_s", t.encode}, {"decode3_s", t.decode3}, {"decode3_faces", t.decode3_faces},
          {"decode3_faces_per_s", double(t.decode3_faces) / t.decode3},
          {"skeleton_to_decode_s", t.skeleton + t.layout + t.encode + t.decode3}};
}

}  // namespace

// Per file: load, skeleton, layout (--size atlas), encode (same size) and decode at level 3, the
// fastest of `repeat` runs each (in-memory, as the commands run them without their checks), the
// decode's rate in faces per second, and the process's peak memory after them.
int run_pipeline_bench(const BenchOptions& o) {
  const nlohmann::json rows =
      rows_per_file(o.pipeline, "pipeline", [&](const std::string& path) { return pipeline_row(path, o.repeat, o.size); });
  if (o.json) {
    print_json({{"machine", machine_line()}, {"size", o.size}, {"pipelines", rows}, {"peak_rss_mb", double(peak_rss_bytes()) / 1e6}});
    return 0;
  }
  std::cout << "Pipeline (atlas " << o.size << ", decode level 3; fastest of " << o.repeat << "; " << machine_line() << ")\n"
            << "| file | vertices | load (s) | skeleton (s) | layout (s) | encode (s) | decode 3 (s) | decoded faces/s | skeleton to decode (s) |\n"
            << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    std::cout << "| " << r["file"].get<std::string>() << " | " << r["vertices"] << " | " << std::fixed << std::setprecision(2)
              << r["load_s"].get<double>() << " | " << r["skeleton_s"].get<double>() << " | " << r["layout_s"].get<double>() << " | "
              << r["encode_s"].get<double>() << " | " << r["decode3_s"].get<double>() << " | " << std::setprecision(0)
              << r["decode3_faces_per_s"].get<double>() << " | " << std::setprecision(2) << r["skeleton_to_decode_s"].get<double>()
              << " |\n";
  std::cout << "Peak memory of the process: " << std::setprecision(0) << double(peak_rss_bytes()) / 1e6 << " MB\n";
  return 0;
}

}  // namespace sdm::cli
