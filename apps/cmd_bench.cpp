// sdm bench: per-stage timings beside the paper's Table I, coverage beside its Table II, SDM
// encode/decode times, and a large real mesh; with --solvers, the contraction's sparse Cholesky
// solvers against each other. Figures, not pass/fail: speed is measured here and written to
// docs/BENCHMARKS.md, never asserted by tests.
#include "apps/bench_pose.h"
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/transfer_setup.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/registration/correspondence_error.h"
#include "libstm/render/gl_context.h"
#include "libstm/render/render_atlas.h"
#include "libstm/skeleton/contract_mesh.h"
#include "libstm/skeleton/contraction_proxy.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/transfer/transfer_texture.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <numeric>
#include <sstream>
#include <thread>

#include <sys/resource.h>

namespace sdm::cli {
namespace {

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
};

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

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string machine_line() {
  return cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
}

// ---- Table I, Table II, SDM: every stage of the pipeline ----

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

// Keeps the fastest of the runs: `slot` holds the best time so far.
void keep_fastest(double& slot, double seconds) { slot = std::min(slot, seconds); }

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
    bunny = std::make_unique<Row>(measure("bunny00", sdm::load_mesh(o.bunny), o.repeat, o.size, false, nullptr));
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

// ---- --solvers: the contraction's sparse Cholesky, supernodal against Eigen and CHOLMOD ----

struct SolverCase {
  std::string name;
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
};

struct SolverRun {
  sdm::SparseSolver solver;
  double seconds = INFINITY, factor_seconds = INFINITY;  // fastest of the runs
  int iterations = 0;
  double max_difference = 0;  // largest vertex distance to the supernodal result, / bounding-box diagonal
};

struct SolverRow {
  std::string name;
  long vertices = 0;
  std::vector<SolverRun> runs;  // supernodal first
};

const char* solver_key(sdm::SparseSolver s) {
  return s == sdm::SparseSolver::supernodal ? "supernodal" : s == sdm::SparseSolver::eigen ? "eigen" : "cholmod";
}

const char* solver_title(sdm::SparseSolver s) {
  return s == sdm::SparseSolver::supernodal ? "supernodal LL^T"
         : s == sdm::SparseSolver::eigen    ? "Eigen LDL^T"
                                            : "CHOLMOD supernodal";
}

std::vector<sdm::SparseSolver> available_solvers() {
  std::vector<sdm::SparseSolver> out;
  for (auto s : {sdm::SparseSolver::supernodal, sdm::SparseSolver::eigen, sdm::SparseSolver::cholmod})
    if (sdm::sparse_solver_available(s)) out.push_back(s);
  return out;
}

// The contraction proxy of a large mesh, as extract_skeleton makes it (make_proxy).
std::pair<Eigen::MatrixX3d, Eigen::MatrixX3i> contraction_proxy(const sdm::Mesh& mesh) {
  std::pair<Eigen::MatrixX3d, Eigen::MatrixX3i> proxy;
  sdm::make_proxy(sdm::vertex_matrix(mesh), sdm::face_matrix(mesh), sdm::SkeletonOptions{}.proxy_max_vertices,
                  proxy.first, proxy.second);
  return proxy;
}

// The paper's shapes, Spot and bunny00's contraction proxy (the meshes that are found).
std::vector<SolverCase> solver_cases(const BenchOptions& o) {
  std::vector<SolverCase> cases;
  auto add = [&](const std::string& name, const sdm::Mesh& m) {
    cases.push_back({name, sdm::vertex_matrix(m), sdm::face_matrix(m)});
  };
  for (const auto& p : kPaper) add(p.name, sdm::make_primitive(p.name));
  if (std::filesystem::exists(o.spot))
    add("Spot", sdm::load_mesh(o.spot));
  else
    progress("bench: Spot skipped, " + o.spot + " not found (--spot PATH)");
  if (std::filesystem::exists(o.bunny)) {
    auto proxy = contraction_proxy(sdm::load_mesh(o.bunny));
    cases.push_back({"bunny00 remeshed", std::move(proxy.first), std::move(proxy.second)});
  } else {
    progress("bench: bunny00 skipped, " + o.bunny + " not found (--bunny PATH)");
  }
  return cases;
}

// The same contraction (uniform weights, the raw options of extract_skeleton) with every
// available solver, fastest of `repeat` runs each.
SolverRow measure_solvers(const SolverCase& c, int repeat) {
  SolverRow row;
  row.name = c.name;
  row.vertices = long(c.V.rows());
  const double diagonal = (c.V.colwise().maxCoeff() - c.V.colwise().minCoeff()).norm();
  Eigen::MatrixX3d reference;
  for (auto solver : available_solvers()) {
    sdm::ContractOptions opt = sdm::uniform_contraction();
    opt.solver = solver;
    SolverRun run;
    run.solver = solver;
    for (int k = 0; k < repeat; ++k) {
      const sdm::Stopwatch clock;
      const sdm::ContractResult res = sdm::contract_mesh(c.V, c.F, opt);
      keep_fastest(run.seconds, clock.seconds());
      keep_fastest(run.factor_seconds, res.factor_seconds);
      run.iterations = res.iterations;
      if (reference.size() == 0) reference = res.positions;
      run.max_difference = (res.positions - reference).rowwise().norm().maxCoeff() / diagonal;
    }
    row.runs.push_back(run);
  }
  return row;
}

nlohmann::json solvers_json(const std::vector<SolverRow>& rows) {
  nlohmann::json j;
  j["machine"] = machine_line();
  j["meshes"] = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json rj{{"name", r.name}, {"vertices", r.vertices}};
    for (const auto& run : r.runs)
      rj[solver_key(run.solver)] = {{"seconds", run.seconds},
                                    {"factor_seconds", run.factor_seconds},
                                    {"iterations", run.iterations},
                                    {"max_difference", run.max_difference}};
    j["meshes"].push_back(rj);
  }
  return j;
}

// A Markdown table, the form of docs/BENCHMARKS.md: each solver's total seconds with the
// factorisations' share in parentheses, then each other solver's largest difference to the
// supernodal result. Iterations are the supernodal contraction's; a solver that took a different
// number is marked with its own.
void print_solver_table(std::ostream& s, const std::vector<SolverRow>& rows, int repeat) {
  const auto solvers = available_solvers();
  s << "Machine: " << machine_line() << "\n"
    << "Contraction seconds (factorisations in parentheses), fastest of " << repeat
    << "; max difference: largest vertex distance to the supernodal result / bounding-box diagonal.\n\n";
  s << "| mesh | vertices |";
  for (auto solver : solvers) s << " " << solver_title(solver) << " |";
  for (size_t k = 1; k < solvers.size(); ++k) s << " max difference, " << solver_key(solvers[k]) << " |";
  s << " iterations |\n|---|---|";
  for (size_t k = 0; k < 2 * solvers.size(); ++k) s << "---|";
  s << "\n";
  for (const auto& r : rows) {
    s << "| " << r.name << " | " << r.vertices << " |";
    for (const auto& run : r.runs) {
      s << std::fixed << std::setprecision(3) << " " << run.seconds << " (" << run.factor_seconds << ")";
      if (run.iterations != r.runs[0].iterations) s << ", " << run.iterations << " iterations";
      s << " |";
    }
    for (size_t k = 1; k < r.runs.size(); ++k) s << std::scientific << std::setprecision(1) << " " << r.runs[k].max_difference << " |";
    s << " " << r.runs[0].iterations << " |\n";
  }
}

int run_solvers(const BenchOptions& o) {
  std::vector<SolverRow> rows;
  for (const auto& c : solver_cases(o)) {
    progress("bench --solvers: " + c.name);
    rows.push_back(measure_solvers(c, o.repeat));
  }
  if (o.json) {
    print_json(solvers_json(rows));
    return 0;
  }
  std::ostringstream s;
  print_solver_table(s, rows, o.repeat);
  std::cout << s.str();
  return 0;
}

// ---- Texture transfer between different bodies ----

struct TransferRow {
  std::string pair;
  int vertices = 0;
  double extract = INFINITY, transfer = INFINITY;  // seconds, fastest of the runs
  std::string kind;
  double rms = 0;
};

// The texture the bench's sources show (their uv a planar projection: with_planar_uv).
Image checker_texture() {
  Image checker(64, 64, 4, 255);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) checker.pixels[4 * (64 * y + x)] = ((x / 8 + y / 8) % 2) ? 200 : 40;
  return checker;
}

// How the transfer found the target's skeleton, as `sdm transfer --json` names it.
std::string target_kind(const TextureTransfer& t) {
  return t.carried ? "carried" : t.fitted ? "bent" : t.registered ? "registered" : "extracted";
}

std::string pair_name(const std::string& a_path, const std::string& b_path) {
  return std::filesystem::path(a_path).stem().string() + " -> " + std::filesystem::path(b_path).stem().string();
}

// Both extractions, then transfer_texture (recognition, registration, layout, atlas, coordinates)
// with a 1024 atlas, as `sdm transfer` runs them; the fastest of `repeat` runs.
TransferRow time_transfer(GlContext& gl, const std::string& a_path, const std::string& b_path, int repeat) {
  const Mesh a = with_planar_uv(load_mesh(a_path)), b = load_mesh(b_path);
  const Image checker = checker_texture();
  TransferRow row;
  row.pair = pair_name(a_path, b_path);
  row.vertices = int(a.n_vertices());
  TransferOptions to;
  to.size = 1024;
  for (int r = 0; r < repeat; ++r) {
    Stopwatch sw;
    Skeleton sa, sb;
    run_concurrently([&] { sb = extract_skeleton(b, transfer_skeleton_options()); }, [&] { sa = extract_skeleton(a, transfer_skeleton_options()); });
    const double e = sw.lap();
    const TextureTransfer t = transfer_texture(gl, a, checker, sa, b, sb, to);
    row.extract = std::min(row.extract, e), row.transfer = std::min(row.transfer, sw.lap());
    row.kind = target_kind(t);
    row.rms = t.fit_rms;
  }
  return row;
}

// ---- Correspondence error on FAUST (docs/BENCHMARKS.md) ----

// The FAUST registrations compared: one connectivity, so target vertex i truly shows source vertex
// i; 001 and 007 are one person in two poses.
const char* const kFaust[] = {"tr_reg_001.off", "tr_reg_007.off", "tr_reg_010.off", "tr_reg_024.off"};

// Mean geodesic errors on FAUST as published (x100 of sqrt(area), Kim et al. 2011's unit; the
// remeshed FAUST test pairs), beside ours.
struct PublishedError {
  const char* method;
  double mean;
};
const PublishedError kPublished[] = {{"BCICP", 6.1}, {"ZoomOut", 6.1}, {"Smooth Shells", 2.5}, {"Deep Shells", 1.7}, {"ULRSSM", 1.6}};

struct CorrespondenceRow {
  std::string pair, kind;
  std::string failure;  // why there is no correspondence (the transfer refused the pair), or empty
  double fit_rms = INFINITY, seconds = 0, measure_seconds = 0;
  double geodesic_mean = 0, geodesic_p90 = 0, euclidean_mean = 0, euclidean_p90 = 0;
};

// The ordered pair a -> b through what `sdm transfer` runs with its defaults (the meshes loaded as
// it loads them, both skeletons as it obtains them, its TransferOptions: 2048 atlas, the other
// extraction candidates), the source given a planar uv and a checker texture (neither reaches the
// correspondence), then every target vertex's error against the ground truth (correspondence_error).
// `seconds`: loading, both skeletons and the transfer, once; `measure_seconds`: the error.
// With `turned_scaled` the target is turned 180 degrees about its vertical (y) axis and scaled by 1.7
// once loaded; with `no_refine` the transfer keeps the registration's closest points (--no-refine).
CorrespondenceRow transfer_correspondence(GlContext& gl, const std::string& a_path, const std::string& b_path, bool turned_scaled,
                                          bool no_refine) {
  CorrespondenceRow row;
  row.pair = pair_name(a_path, b_path);
  Stopwatch sw;
  try {
    const Mesh a = with_planar_uv(load_mesh_min_part(a_path));
    Mesh b = load_mesh_min_part(b_path);
    if (turned_scaled)
      for (auto v : b.vertices()) {
        const Mesh::Point p = b.point(v);
        b.set_point(v, 1.7 * Mesh::Point(-p[0], p[1], -p[2]));
      }
    Skeleton sa, sb;
    SkeletonStats stats_a, stats_b;
    obtain_both_skeletons(
        a.n_vertices() + b.n_vertices(), [&] { sa = skeleton_for(a, "", "source", &stats_a, nullptr); },
        [&] { sb = skeleton_for(b, "", "target", &stats_b, nullptr); });
    TransferSettings settings;
    settings.no_refine = no_refine;
    const TransferOptions to = transfer_command_options(settings, a, b, stats_a, stats_b, nullptr);
    const TextureTransfer t = transfer_texture(gl, a, checker_texture(), sa, b, sb, to);
    row.seconds = sw.lap();
    row.kind = target_kind(t), row.fit_rms = t.fit_rms;
    if (a.n_vertices() != b.n_vertices() || t.correspondence.size() != b.n_vertices()) {
      row.failure = "no point correspondence of every target vertex";
      return row;
    }
    std::vector<int> truth(b.n_vertices());
    std::iota(truth.begin(), truth.end(), 0);
    const CorrespondenceError e = correspondence_error(a, t.correspondence, truth);
    row.measure_seconds = sw.lap();
    row.geodesic_mean = e.geodesic_mean, row.geodesic_p90 = e.geodesic_p90;
    row.euclidean_mean = e.euclidean_mean, row.euclidean_p90 = e.euclidean_p90;
  } catch (const InputError& e) {
    row.seconds = sw.lap();
    row.failure = e.what();
  }
  return row;
}

// Every ordered pair of kFaust found in `humans` (none, with a note, when one is missing).
std::vector<CorrespondenceRow> faust_correspondences(GlContext& gl, const std::string& humans, bool turned_scaled, bool no_refine) {
  std::vector<CorrespondenceRow> rows;
  for (const char* name : kFaust)
    if (!std::filesystem::exists(humans + "/" + name)) {
      std::cerr << "bench: " << humans << "/" << name << " missing: the FAUST correspondence error skipped\n";
      return rows;
    }
  const int n = int(std::size(kFaust));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      std::cerr << "bench: correspondence " << kFaust[i] << " -> " << kFaust[j] << " (" << rows.size() + 1 << " of " << n * (n - 1) << ")\n";
      rows.push_back(transfer_correspondence(gl, humans + "/" + kFaust[i], humans + "/" + kFaust[j], turned_scaled, no_refine));
      const CorrespondenceRow& r = rows.back();
      if (!r.failure.empty()) std::cerr << "  refused: " << r.failure << "\n";
      else std::cerr << "  geodesic error mean " << r.geodesic_mean << ", p90 " << r.geodesic_p90 << " (" << r.seconds << " s)\n";
    }
  return rows;
}

// Over the pairs with a correspondence: the mean of their means, the worst mean and the worst p90.
struct CorrespondenceSummary {
  int measured = 0, refused = 0;
  double mean = 0, euclidean_mean = 0, worst_mean = 0, worst_p90 = 0;
  std::string worst_mean_pair, worst_p90_pair;
};

CorrespondenceSummary summarise(const std::vector<CorrespondenceRow>& rows) {
  CorrespondenceSummary s;
  for (const auto& r : rows) {
    if (!r.failure.empty()) {
      ++s.refused;
      continue;
    }
    ++s.measured;
    s.mean += r.geodesic_mean, s.euclidean_mean += r.euclidean_mean;
    if (r.geodesic_mean > s.worst_mean) s.worst_mean = r.geodesic_mean, s.worst_mean_pair = r.pair;
    if (r.geodesic_p90 > s.worst_p90) s.worst_p90 = r.geodesic_p90, s.worst_p90_pair = r.pair;
  }
  if (s.measured) s.mean /= s.measured, s.euclidean_mean /= s.measured;
  return s;
}

nlohmann::json correspondence_json(const std::vector<CorrespondenceRow>& rows) {
  nlohmann::json pairs = nlohmann::json::array(), published = nlohmann::json::object();
  for (const auto& r : rows) {
    nlohmann::json j = {{"pair", r.pair}, {"transfer_s", r.seconds}};
    if (!r.failure.empty()) {
      j["refused"] = r.failure;
    } else {
      j.update({{"target_skeleton", r.kind}, {"fit_rms", r.fit_rms}, {"geodesic_mean", r.geodesic_mean}, {"geodesic_p90", r.geodesic_p90},
                {"euclidean_mean_percent", r.euclidean_mean}, {"euclidean_p90_percent", r.euclidean_p90}, {"error_s", r.measure_seconds}});
    }
    pairs.push_back(j);
  }
  for (const auto& p : kPublished) published[p.method] = p.mean;
  const CorrespondenceSummary s = summarise(rows);
  return {{"unit", "geodesic distance on the source / sqrt(source area) x 100 (shortest paths through 5 points per edge and straight across faces: an upper bound, about 1 % over the exact geodesic on FAUST); euclidean in % of the "
                   "source's bounding-box diagonal"},
          {"pairs", pairs},
          {"measured", s.measured},
          {"refused", s.refused},
          {"geodesic_mean", s.mean},
          {"euclidean_mean_percent", s.euclidean_mean},
          {"worst_mean", s.worst_mean},
          {"worst_mean_pair", s.worst_mean_pair},
          {"worst_p90", s.worst_p90},
          {"worst_p90_pair", s.worst_p90_pair},
          {"published_faust_means", published}};
}

void print_correspondence_table(const std::vector<CorrespondenceRow>& rows, bool turned_scaled, bool no_refine) {
  std::cout << "\nCorrespondence error on FAUST (every ordered pair; `sdm transfer`'s defaults"
            << (no_refine ? " with --no-refine" : "") << (turned_scaled ? "; each target turned 180 degrees about y and scaled 1.7" : "")
            << "; geodesic on the source / sqrt(area) x 100,\n"
               "shortest paths through 5 points per edge (an upper bound), every target vertex; euclidean % of the diagonal; "
            << machine_line() << ")\n"
            << "| pair | target | fit RMS | geodesic mean | geodesic p90 | euclidean mean | euclidean p90 | transfer (s) | error (s) |\n"
            << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    std::cout << "| " << r.pair << " | ";
    if (!r.failure.empty()) {
      std::cout << "refused: " << r.failure << " | | | | | | " << std::fixed << std::setprecision(2) << r.seconds << " | |\n";
      continue;
    }
    std::cout << r.kind << " | " << std::fixed << std::setprecision(3) << 100 * r.fit_rms << " % | " << std::setprecision(2)
              << r.geodesic_mean << " | " << r.geodesic_p90 << " | " << r.euclidean_mean << " % | " << r.euclidean_p90 << " % | "
              << r.seconds << " | " << std::setprecision(3) << r.measure_seconds << " |\n";
  }
  const CorrespondenceSummary s = summarise(rows);
  std::cout << "Over the " << s.measured << " pairs measured (" << s.refused << " refused): geodesic mean " << std::setprecision(2) << s.mean
            << " (euclidean " << s.euclidean_mean << " %), worst mean " << s.worst_mean << " (" << s.worst_mean_pair << "), worst p90 "
            << s.worst_p90 << " (" << s.worst_p90_pair << ")\n"
            << "Published mean geodesic errors on FAUST (remeshed test pairs, the same unit):" << std::setprecision(1);
  const char* separator = " ";
  for (const auto& p : kPublished) std::cout << separator << p.method << " " << p.mean, separator = ", ";
  std::cout << "\n";
}

int run_transfer_bench(const BenchOptions& o) {
  const std::vector<std::pair<std::string, std::string>> pairs{
      {"tr_reg_007.off", "tr_reg_024.off"}, {"tr_reg_024.off", "tr_reg_007.off"}, {"8_gorilla_01.off", "8_man_02.off"}};
  GlContext gl;
  std::vector<TransferRow> rows;
  for (const auto& [a, b] : pairs) {
    const std::string pa = o.humans + "/" + a, pb = o.humans + "/" + b;
    if (!std::filesystem::exists(pa) || !std::filesystem::exists(pb)) {
      std::cerr << "bench: " << pa << " or " << pb << " missing: skipped\n";
      continue;
    }
    std::cerr << "bench: transfer " << a << " -> " << b << "\n";
    rows.push_back(time_transfer(gl, pa, pb, o.repeat));
  }
  const std::vector<CorrespondenceRow> faust = faust_correspondences(gl, o.humans, o.turned_scaled, o.no_refine);
  if (o.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows)
      j.push_back({{"pair", r.pair}, {"vertices", r.vertices}, {"extract_s", r.extract}, {"transfer_s", r.transfer},
                   {"total_s", r.extract + r.transfer}, {"target_skeleton", r.kind}, {"fit_rms", r.rms}});
    print_json({{"machine", machine_line()}, {"transfers", j}, {"faust_correspondence", correspondence_json(faust)},
                {"targets_turned_scaled", o.turned_scaled}, {"refined", !o.no_refine}});
    return 0;
  }
  std::cout << "Texture transfer between different bodies (1024 atlas; fastest of " << o.repeat << "; " << machine_line() << ")\n"
            << "| pair | vertices | both skeletons (s) | transfer (s) | total (s) | target | fit RMS |\n|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    std::cout << "| " << r.pair << " | " << r.vertices << " | " << std::fixed << std::setprecision(2) << r.extract << " | " << r.transfer
              << " | " << r.extract + r.transfer << " | " << r.kind << " | " << std::setprecision(3) << 100 * r.rms << " % |\n";
  if (!faust.empty()) print_correspondence_table(faust, o.turned_scaled, o.no_refine);
  return 0;
}

}  // namespace

// ---- Loading large meshes (docs/BENCHMARKS.md, "Loading large meshes") ----

// The process's peak resident memory (getrusage's ru_maxrss, kilobytes on Linux), in bytes.
size_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return size_t(u.ru_maxrss) * 1024;
}

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

// ---- A mesh through the whole pipeline (docs/BENCHMARKS.md, "Pipeline stages by mesh size") ----

// Per file: load, skeleton, layout (--size atlas), encode (same size) and decode at level 3, the
// fastest of `repeat` runs each (in-memory, as the commands run them without their checks), the
// decode's rate in faces per second, and the process's peak memory after them.
int run_pipeline_bench(const BenchOptions& o) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string& path : o.pipeline) {
    double load = INFINITY, skeleton = INFINITY, layout = INFINITY, encode = INFINITY, decode = INFINITY;
    size_t vertices = 0, faces = 0;
    for (int i = 0; i < o.repeat; ++i) {
      Stopwatch sw;
      const Mesh mesh = load_mesh(path);
      load = std::min(load, sw.lap());
      const Skeleton sk = extract_skeleton(mesh);
      skeleton = std::min(skeleton, sw.lap());
      LayoutOptions lo;
      lo.size = o.size;
      const Layout L = compute_layout(mesh, sk, lo);
      layout = std::min(layout, sw.lap());
      EncodeOptions eo;
      eo.fill_unread = false;  // as `sdm encode` writes a file
      const SdmImage im = encode_sdm(mesh, L, eo);
      encode = std::min(encode, sw.lap());
      DecodeOptions d;
      d.level = 3;
      faces = decode_sdm(im, d).n_faces();
      decode = std::min(decode, sw.lap());
      vertices = mesh.n_vertices();
    }
    std::cerr << "bench: pipeline " << path << "\n";
    rows.push_back({{"file", path}, {"vertices", vertices}, {"load_s", load}, {"skeleton_s", skeleton}, {"layout_s", layout},
                    {"encode_s", encode}, {"decode3_s", decode}, {"decode3_faces", faces}, {"decode3_faces_per_s", double(faces) / decode},
                    {"skeleton_to_decode_s", skeleton + layout + encode + decode}});
  }
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

Command add_bench_command(CLI::App& parent) {
  auto o = std::make_shared<BenchOptions>();
  auto* app = parent.add_subcommand(
      "bench", "Time every stage on the paper's five test shapes (beside its Table I and Table II), the SDM\n"
               "encoder and decoder (1024 map; levels 3 and 5), and a large real mesh. Fastest of --repeat runs.\n"
               "With --solvers: the contraction with each sparse Cholesky (supernodal, Eigen, and CHOLMOD in a build\n"
               "configured with -DSDM_WITH_CHOLMOD=ON) on the five shapes, Spot and bunny00's contraction proxy, and how far their results differ.");
  app->add_option("--bunny", o->bunny, "Large mesh for the skeleton timing (skipped with a note when missing)")->capture_default_str();
  app->add_option("--spot", o->spot, "Spot mesh for --solvers (skipped with a note when missing)")->capture_default_str();
  app->add_option("--repeat", o->repeat, "Runs per measurement; the fastest is kept")->capture_default_str()->check(number_in(1, 20));
  app->add_option("--size", o->size, "Atlas size for packing and composing")->capture_default_str()->check(number_in(64, 8192));
  app->add_flag("--no-sdm", o->no_sdm, "Skip the SDM encode/decode timings");
  app->add_flag("--no-gl", o->no_gl, "Skip the GL atlas composing timing");
  app->add_flag("--solvers", o->solvers, "Compare the contraction's sparse Cholesky solvers instead (docs/BENCHMARKS.md)");
  app->add_flag("--transfer", o->transfer,
                "Time texture transfer between different bodies instead (FAUST 007 <-> 024, TOSCA gorilla -> man, from --humans),\n"
                "and measure its correspondence error on every ordered pair of FAUST 001, 007, 010 and 024 against their ground truth");
  app->add_option("--humans", o->humans, "Folder of the human meshes for --transfer (skipped with a note when missing)")->capture_default_str();
  app->add_flag("--turned-scaled", o->turned_scaled,
                "With --transfer: measure the FAUST correspondence with each target turned 180 degrees about its vertical axis and scaled by 1.7");
  app->add_flag("--no-refine", o->no_refine, "With --transfer: transfer as 'sdm transfer --no-refine' (no spectral refinement)");
  app->add_option("--load", o->load, "Time the loading stages (read, validate, build) of these meshes instead");
  app->add_option("--pipeline", o->pipeline,
                  "Take these meshes through every stage instead (load, skeleton, layout and encode at --size, decode at level 3)");
  app->add_option("--pose", o->pose,
                  "Pose SOURCE like TARGET instead (pairs of meshes with the same connectivity, e.g. FAUST 001 007): per node of "
                  "SOURCE's SDM skeleton the Kabsch motion of its vertices, the map decoded and posed, against linear blend skinning");
  app->add_flag("--json", o->json, "Print one JSON object instead of tables");
  return {app, [o]() {
            if (!o->pose.empty()) return run_pose_bench(o->pose, o->size, o->json, machine_line());
            if (!o->pipeline.empty()) return run_pipeline_bench(*o);
            return o->solvers ? run_solvers(*o) : o->transfer ? run_transfer_bench(*o) : !o->load.empty() ? run_load_bench(*o) : run_stages(*o);
          }};
}

}  // namespace sdm::cli
