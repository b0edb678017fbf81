// sdm bench: per-stage timings beside the paper's Table I, coverage beside its Table II, SDM
// encode/decode times, and a large real mesh.
#include "apps/bench.h"
#include "apps/commands.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/render/gl_context.h"
#include "libstm/render/render_atlas.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

namespace sdm::cli {
namespace {

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

sdm::Skeleton time_skeleton(const sdm::Mesh& mesh, Row& r) {
  sdm::SkeletonStats st;
  sdm::Skeleton sk = sdm::extract_skeleton(mesh, {}, nullptr, &st);
  keep_fastest(r.contraction, st.contraction_seconds);
  keep_fastest(r.surgery, st.surgery_seconds);
  keep_fastest(r.refinement, st.refinement_seconds);
  keep_fastest(r.skeleton_wall, st.seconds);
  return sk;
}

// Texture composing (paper t4): the surface drawn into the atlas, here its positions as values.
void time_composing(const sdm::Mesh& mesh, const sdm::Layout& layout, sdm::GlContext& gl, Row& r) {
  std::vector<Eigen::Vector4f> values;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) {
      const auto& p = mesh.point(v);
      values.emplace_back(float(p[0]), float(p[1]), float(p[2]), 1.0f);
    }
  const sdm::Stopwatch clock;
  sdm::render_atlas_values(gl, mesh, layout, values);
  keep_fastest(r.composing, clock.seconds());
}

// The SDM encoder on a 1024 map and the decoder at levels 3 and 5.
void time_sdm(const sdm::Mesh& mesh, const sdm::Skeleton& sk, Row& r) {
  sdm::LayoutOptions l1024;
  l1024.size = 1024;
  const sdm::Layout layout1024 = sdm::compute_layout(mesh, sk, l1024);
  sdm::Stopwatch clock;
  const sdm::SdmImage im = sdm::encode_sdm(mesh, layout1024);
  keep_fastest(r.encode, clock.seconds());
  for (int level : {3, 5}) {
    sdm::DecodeOptions d;
    d.level = level;
    clock.restart();
    sdm::decode_sdm(im, d);
    keep_fastest(level == 3 ? r.decode3 : r.decode5, clock.seconds());
  }
}

// Times every stage, keeping the fastest of `repeat` runs (the machine may be shared).
Row measure(const std::string& name, const sdm::Mesh& mesh, int repeat, int size, bool with_sdm, sdm::GlContext* gl) {
  Row r;
  r.name = name;
  r.vertices = long(mesh.n_vertices());
  for (int k = 0; k < repeat; ++k) {
    const sdm::Skeleton sk = time_skeleton(mesh, r);
    sdm::LayoutOptions lo;
    lo.size = size;
    const sdm::Stopwatch clock;
    const sdm::Layout layout = sdm::compute_layout(mesh, sk, lo);
    keep_fastest(r.packing, clock.seconds());
    r.segments = int(layout.segments.size());
    r.coverage = layout.coverage;
    if (gl) time_composing(mesh, layout, *gl, r);
    if (with_sdm) time_sdm(mesh, sk, r);
  }
  if (!gl) r.composing = 0;
  return r;
}

nlohmann::json row_json(const Row& r) {
  return nlohmann::json{{"name", r.name},
                        {"vertices", r.vertices},
                        {"contraction", r.contraction},
                        {"surgery", r.surgery},
                        {"refinement", r.refinement},
                        {"packing", r.packing},
                        {"composing", r.composing},
                        {"skeleton_total", r.skeleton_total()},
                        {"stm_total", r.stm_total()},
                        {"segments", r.segments},
                        {"coverage", r.coverage},
                        {"encode_1024", r.encode},
                        {"decode_level3", r.decode3},
                        {"decode_level5", r.decode5}};
}

nlohmann::json stages_json(const std::vector<Row>& rows, const Row* bunny, const sdm::GlContext* gl) {
  nlohmann::json j;
  j["machine"] = machine_line();
  j["renderer"] = gl ? gl->renderer() : "";
  for (size_t i = 0; i < rows.size(); ++i) {
    auto rj = row_json(rows[i]);
    rj["paper_total"] = kPaper[i].total;
    rj["paper_coverage"] = kPaper[i].coverage;
    rj["speedup"] = kPaper[i].total / rows[i].stm_total();
    rj["speedup_skeleton"] = kPaper[i].total / rows[i].skeleton_total();
    j["shapes"].push_back(rj);
  }
  if (bunny) j["bunny"] = row_json(*bunny);
  return j;
}

void print_table_one(std::ostream& s, const std::vector<Row>& rows, const Row* bunny, const BenchOptions& o) {
  s << "Table I (seconds): t1 contraction (and medial poles), t2 skeleton construction (surgery +\n"
    << "refinement), each summed over the two skeleton candidates, which run on two threads; t3 packing,\n"
    << "t4 composing (surface drawn into the " << o.size << "^2 atlas). total: wall clock of the skeleton\n"
    << "+ t3 + t4. Speed-up: the paper's total over ours, for the whole pipeline and for the skeleton\n"
    << "alone (wall clock).\n";
  s << std::left << std::setw(19) << "shape" << std::right << std::setw(7) << "verts" << std::setw(9) << "t1"
    << std::setw(9) << "t2" << std::setw(9) << "t3" << std::setw(9) << "t4" << std::setw(9) << "total" << std::setw(9)
    << "paper" << std::setw(10) << "speed-up" << std::setw(11) << "skeleton\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    s << std::left << std::setw(19) << r.name << std::right << std::setw(7) << r.vertices << std::setprecision(4)
      << std::setw(9) << r.contraction << std::setw(9) << r.surgery + r.refinement << std::setw(9) << r.packing
      << std::setw(9) << r.composing << std::setw(9) << r.stm_total() << std::setprecision(1) << std::setw(9)
      << kPaper[i].total << std::setprecision(0) << std::setw(9) << kPaper[i].total / r.stm_total() << "x"
      << std::setw(10) << kPaper[i].total / r.skeleton_total() << "x\n";
  }
  if (bunny)
    s << std::left << std::setw(19) << "bunny00" << std::right << std::setw(7) << bunny->vertices << std::setprecision(4)
      << std::setw(9) << bunny->contraction << std::setw(9) << bunny->surgery + bunny->refinement << std::setw(9)
      << bunny->packing << std::setw(9) << "-" << std::setw(9) << bunny->skeleton_total() + bunny->packing << "\n";
  else
    s << "bunny00: skipped, " << o.bunny << " not found (--bunny PATH)\n";
}

void print_table_two(std::ostream& s, const std::vector<Row>& rows) {
  s << "\nTable II: coverage of the atlas\n";
  s << std::left << std::setw(19) << "shape" << std::right << std::setw(10) << "segments" << std::setw(10) << "coverage"
    << std::setw(16) << "paper segments" << std::setw(16) << "paper coverage\n";
  for (size_t i = 0; i < rows.size(); ++i)
    s << std::left << std::setw(19) << rows[i].name << std::right << std::setw(10) << rows[i].segments
      << std::setprecision(1) << std::setw(9) << 100 * rows[i].coverage << "%" << std::setw(16) << kPaper[i].segments
      << std::setw(15) << 100 * kPaper[i].coverage << "%\n";
}

void print_sdm_table(std::ostream& s, const std::vector<Row>& rows) {
  s << "\nSDM (1024 map): encode, decode at level 3 and 5, seconds\n";
  for (const auto& r : rows)
    s << std::left << std::setw(19) << r.name << std::right << std::setprecision(3) << std::setw(9) << r.encode
      << std::setw(9) << r.decode3 << std::setw(9) << r.decode5 << "\n";
}

}  // namespace

int run_stages(const BenchOptions& o) {
  std::unique_ptr<sdm::GlContext> gl;
  if (!o.no_gl) gl = std::make_unique<sdm::GlContext>();
  std::vector<Row> rows;
  for (const auto& p : kPaper) {
    progress("bench: " + std::string(p.name));
    rows.push_back(measure(p.name, sdm::make_primitive(p.name), o.repeat, o.size, !o.no_sdm, gl.get()));
  }
  std::unique_ptr<Row> bunny;
  if (std::filesystem::exists(o.bunny)) {
    progress("bench: " + o.bunny);
    bunny = std::make_unique<Row>(measure("bunny00", sdm::load_mesh(o.bunny).mesh, o.repeat, o.size, false, nullptr));
  }
  if (o.json) {
    print_json(stages_json(rows, bunny.get(), gl.get()));
    return 0;
  }
  std::ostringstream s;
  s << std::fixed;
  s << "Machine: " << machine_line() << (gl ? "; GL: " + gl->renderer() : "") << "\n\n";
  print_table_one(s, rows, bunny.get(), o);
  print_table_two(s, rows);
  if (!o.no_sdm) print_sdm_table(s, rows);
  std::cout << s.str();
  return 0;
}

}  // namespace sdm::cli
