// sdm bench: per-stage timings beside the paper's Table I, coverage beside its Table II, SDM
// encode/decode times, and a large real mesh. Figures, not pass/fail: speed is measured here and
// written to docs/BENCHMARKS.md, never asserted by tests.
#include "apps/commands.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/render/render_atlas.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <thread>

namespace sdm::cli {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct PaperRow {
  const char* name;
  int vertices;
  double total;     // Table I, seconds (AMD Phenom II X4 3.41 GHz, one thread)
  int segments;     // Table II
  double coverage;  // Table II
};
const PaperRow kPaper[] = {{"ypsilon", 480, 2.6, 7, 0.837},
                           {"bottle", 1530, 6.4, 5, 0.894},
                           {"donut", 1728, 12.6, 24, 0.997},
                           {"triple-torus", 2256, 24.1, 24, 0.91},
                           {"crossed-cylinders", 3660, 84.7, 12, 0.743}};

struct Row {
  std::string name;
  long vertices = 0;
  double contraction = INFINITY, surgery = INFINITY, refinement = INFINITY, packing = INFINITY, composing = INFINITY;
  double skeleton_wall = INFINITY;  // the two skeleton candidates run on two threads
  double encode = INFINITY, decode3 = INFINITY, decode5 = INFINITY;
  int segments = 0;
  double coverage = 0, stretch = 0;
  double skeleton_total() const { return skeleton_wall; }
  double stm_total() const { return skeleton_total() + packing + composing; }
};

// Times every stage, keeping the fastest of `repeat` runs (the machine may be shared).
Row measure(const std::string& name, const sdm::Mesh& mesh, int repeat, int size, bool sdm, sdm::GlContext* gl) {
  Row r;
  r.name = name;
  r.vertices = long(mesh.n_vertices());
  for (int k = 0; k < repeat; ++k) {
    sdm::SkeletonStats st;
    const sdm::Skeleton sk = sdm::extract_skeleton(mesh, {}, nullptr, &st);
    r.contraction = std::min(r.contraction, st.contraction_seconds);
    r.surgery = std::min(r.surgery, st.surgery_seconds);
    r.refinement = std::min(r.refinement, st.refinement_seconds);
    r.skeleton_wall = std::min(r.skeleton_wall, st.seconds);
    sdm::LayoutOptions lo;
    lo.size = size;
    auto t = Clock::now();
    const sdm::Layout layout = sdm::compute_layout(mesh, sk, lo);
    r.packing = std::min(r.packing, since(t));
    r.segments = int(layout.segments.size());
    r.coverage = layout.coverage;
    if (gl) {
      // Texture composing (paper t4): the surface drawn into the atlas, here its positions as values.
      std::vector<Eigen::Vector4f> values;
      for (auto f : mesh.faces())
        for (auto v : mesh.fv_range(f)) {
          const auto& p = mesh.point(v);
          values.emplace_back(float(p[0]), float(p[1]), float(p[2]), 1.0f);
        }
      t = Clock::now();
      sdm::render_atlas_values(*gl, mesh, layout, values);
      r.composing = std::min(r.composing, since(t));
    }
    if (sdm) {
      sdm::LayoutOptions l1024;
      l1024.size = 1024;
      const sdm::Layout layout1024 = sdm::compute_layout(mesh, sk, l1024);
      t = Clock::now();
      const sdm::SdmImage im = sdm::encode_sdm(mesh, layout1024);
      r.encode = std::min(r.encode, since(t));
      for (int level : {3, 5}) {
        sdm::DecodeOptions d;
        d.level = level;
        t = Clock::now();
        sdm::decode_sdm(im, d);
        double& slot = level == 3 ? r.decode3 : r.decode5;
        slot = std::min(slot, since(t));
      }
    }
  }
  if (!gl) r.composing = 0;
  return r;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace

Command add_bench_command(CLI::App& parent) {
  struct Opts {
    std::string bunny = "../shared/models/cgal/bunny00.off";
    int repeat = 3, size = 1024;
    bool json = false, no_sdm = false, no_gl = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "bench", "Time every stage on the paper's five test shapes (beside its Table I and Table II), the SDM\n"
               "encoder and decoder (1024 map; levels 3 and 5), and a large real mesh. Fastest of --repeat runs.");
  app->add_option("--bunny", o->bunny, "Large mesh for the skeleton timing (skipped with a note when missing)")->capture_default_str();
  app->add_option("--repeat", o->repeat, "Runs per measurement; the fastest is kept")->capture_default_str()->check(CLI::Range(1, 20));
  app->add_option("--size", o->size, "Atlas size for packing and composing")->capture_default_str()->check(CLI::Range(64, 8192));
  app->add_flag("--no-sdm", o->no_sdm, "Skip the SDM encode/decode timings");
  app->add_flag("--no-gl", o->no_gl, "Skip the GL atlas composing timing");
  app->add_flag("--json", o->json, "Print one JSON object instead of tables");
  return {app, [o]() {
            std::unique_ptr<sdm::GlContext> gl;
            if (!o->no_gl) gl = std::make_unique<sdm::GlContext>();
            std::vector<Row> rows;
            for (const auto& p : kPaper) {
              progress("bench: " + std::string(p.name));
              rows.push_back(measure(p.name, sdm::make_primitive(p.name), o->repeat, o->size, !o->no_sdm, gl.get()));
            }
            Row bunny;
            bool have_bunny = std::filesystem::exists(o->bunny);
            if (have_bunny) {
              progress("bench: " + o->bunny);
              bunny = measure("bunny00", sdm::load_mesh(o->bunny), o->repeat, o->size, false, nullptr);
            }
            const std::string machine = cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
            if (o->json) {
              nlohmann::json j;
              j["machine"] = machine;
              j["renderer"] = gl ? gl->renderer() : "";
              auto row_json = [](const Row& r) {
                return nlohmann::json{{"name", r.name}, {"vertices", r.vertices}, {"contraction", r.contraction},
                                      {"surgery", r.surgery}, {"refinement", r.refinement}, {"packing", r.packing},
                                      {"composing", r.composing}, {"skeleton_total", r.skeleton_total()},
                                      {"stm_total", r.stm_total()}, {"segments", r.segments}, {"coverage", r.coverage},
                                      {"encode_1024", r.encode}, {"decode_level3", r.decode3}, {"decode_level5", r.decode5}};
              };
              for (size_t i = 0; i < rows.size(); ++i) {
                auto rj = row_json(rows[i]);
                rj["paper_total"] = kPaper[i].total;
                rj["paper_coverage"] = kPaper[i].coverage;
                rj["speedup"] = kPaper[i].total / rows[i].stm_total();
                rj["speedup_skeleton"] = kPaper[i].total / rows[i].skeleton_total();
                j["shapes"].push_back(rj);
              }
              if (have_bunny) j["bunny"] = row_json(bunny);
              print_json(j);
              return 0;
            }
            std::ostringstream s;
            s << std::fixed;
            s << "Machine: " << machine << (gl ? "; GL: " + gl->renderer() : "") << "\n\n";
            s << "Table I (seconds): t1 contraction (and medial poles), t2 skeleton construction (surgery +\n"
              << "refinement), each summed over the two skeleton candidates, which run on two threads; t3 packing,\n"
              << "t4 composing (surface drawn into the " << o->size << "^2 atlas). total: wall clock of the skeleton\n"
              << "+ t3 + t4. Speed-up: the paper's total over ours, for the whole pipeline and for the skeleton\n"
              << "alone (wall clock).\n";
            s << std::left << std::setw(19) << "shape" << std::right << std::setw(7) << "verts" << std::setw(9) << "t1"
              << std::setw(9) << "t2" << std::setw(9) << "t3" << std::setw(9) << "t4" << std::setw(9) << "total"
              << std::setw(9) << "paper" << std::setw(10) << "speed-up" << std::setw(11) << "skeleton\n";
            for (size_t i = 0; i < rows.size(); ++i) {
              const Row& r = rows[i];
              s << std::left << std::setw(19) << r.name << std::right << std::setw(7) << r.vertices << std::setprecision(4)
                << std::setw(9) << r.contraction << std::setw(9) << r.surgery + r.refinement << std::setw(9) << r.packing
                << std::setw(9) << r.composing << std::setw(9) << r.stm_total() << std::setprecision(1) << std::setw(9)
                << kPaper[i].total << std::setprecision(0) << std::setw(9) << kPaper[i].total / r.stm_total() << "x"
                << std::setw(10) << kPaper[i].total / r.skeleton_total() << "x\n";
            }
            if (have_bunny)
              s << std::left << std::setw(19) << "bunny00" << std::right << std::setw(7) << bunny.vertices << std::setprecision(4)
                << std::setw(9) << bunny.contraction << std::setw(9) << bunny.surgery + bunny.refinement << std::setw(9)
                << bunny.packing << std::setw(9) << "-" << std::setw(9) << bunny.skeleton_total() + bunny.packing << "\n";
            else
              s << "bunny00: skipped, " << o->bunny << " not found (--bunny PATH)\n";
            s << "\nTable II: coverage of the atlas\n";
            s << std::left << std::setw(19) << "shape" << std::right << std::setw(10) << "segments" << std::setw(10)
              << "coverage" << std::setw(16) << "paper segments" << std::setw(16) << "paper coverage\n";
            for (size_t i = 0; i < rows.size(); ++i)
              s << std::left << std::setw(19) << rows[i].name << std::right << std::setw(10) << rows[i].segments
                << std::setprecision(1) << std::setw(9) << 100 * rows[i].coverage << "%" << std::setw(16) << kPaper[i].segments
                << std::setw(15) << 100 * kPaper[i].coverage << "%\n";
            if (!o->no_sdm) {
              s << "\nSDM (1024 map): encode, decode at level 3 and 5, seconds\n";
              for (const auto& r : rows)
                s << std::left << std::setw(19) << r.name << std::right << std::setprecision(3) << std::setw(9) << r.encode
                  << std::setw(9) << r.decode3 << std::setw(9) << r.decode5 << "\n";
            }
            std::cout << s.str();
            return 0;
          }};
}

}  // namespace sdm::cli
