#pragma once
// sdm bench (apps/cmd_bench.cpp declares its options): each apps/bench_NAME.cpp measures one thing
// and prints a table, or one JSON object with --json. Figures, not pass/fail: speed is measured here
// and written to docs/BENCHMARKS.md, never asserted by tests.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm::cli {

struct BenchOptions {
  std::string humans = "../shared/models/humans";
  std::vector<std::string> pose;
  std::string bunny = "../shared/models/cgal/bunny00.off";
  std::string spot = "examples/data/spot/spot_triangulated.obj";
  int repeat = 3, size = 1024;
  bool json = false, no_sdm = false, no_gl = false, solvers = false, transfer = false;
  bool turned_scaled = false, no_refine = false;  // --transfer: the FAUST targets turned and scaled; without the refinement
  std::vector<std::string> load;      // --load: meshes whose reading stages are timed
  std::vector<std::string> pipeline;  // --pipeline: meshes taken through every stage
  std::vector<std::string> commands;  // --commands: meshes taken through the four commands as processes
};

struct PaperRow {
  const char* name;
  int vertices;
  double total;     // Table I, seconds (AMD Phenom II X4 3.41 GHz, one thread)
  int segments;     // Table II
  double coverage;  // Table II
};
inline constexpr PaperRow kPaper[] = {{"ypsilon", 480, 2.6, 7, 0.837},
                                      {"bottle", 1530, 6.4, 5, 0.894},
                                      {"donut", 1728, 12.6, 24, 0.997},
                                      {"triple-torus", 2256, 24.1, 24, 0.91},
                                      {"crossed-cylinders", 3660, 84.7, 12, 0.743}};

// The CPU's model and its threads, for every table's heading.
std::string machine_line();

// The process's peak resident memory (getrusage's ru_maxrss, kilobytes on Linux), in bytes.
size_t peak_rss_bytes();

// Keeps the fastest of the runs: `slot` holds the best time so far.
inline void keep_fastest(double& slot, double seconds) { slot = std::min(slot, seconds); }

// One row per file of `paths`, in order: `row(path)`, its figures as a JSON object, each file named
// on stderr ("bench: WHAT PATH") once measured (bench --load, --pipeline).
nlohmann::json rows_per_file(const std::vector<std::string>& paths, const std::string& what,
                             const std::function<nlohmann::json(const std::string&)>& row);

// Table I, Table II and the SDM timings on the paper's five shapes (and bunny00): bench_stages.cpp.
int run_stages(const BenchOptions& o);
// --solvers: the contraction's sparse Cholesky solvers against each other: bench_solvers.cpp.
int run_solvers(const BenchOptions& o);
// --transfer: texture transfer between bodies and the FAUST correspondence error: bench_transfer.cpp.
int run_transfer_bench(const BenchOptions& o);
// --load: the loading stages of large meshes: bench_load.cpp.
int run_load_bench(const BenchOptions& o);
// --pipeline: meshes through every stage: bench_pipeline.cpp.
int run_pipeline_bench(const BenchOptions& o);
// One mesh through the stages in this process (load, skeleton, layout at `size`, encode, decode at
// level 3), the fastest of `repeat` runs of each, in seconds: bench_pipeline.cpp.
struct PipelineTimes {
  double load = INFINITY, skeleton = INFINITY, layout = INFINITY, encode = INFINITY, decode3 = INFINITY;
  size_t vertices = 0, decode3_faces = 0;
};
PipelineTimes time_pipeline(const std::string& path, int size, int repeat);
// --commands: meshes through skeleton, stm, encode and decode as processes, beside the stages in
// this process: bench_commands.cpp.
int run_commands_bench(const BenchOptions& o);

}  // namespace sdm::cli
