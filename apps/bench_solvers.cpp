// sdm bench --solvers: the contraction's sparse Cholesky, supernodal against Eigen and CHOLMOD.
#include "apps/bench.h"
#include "apps/commands.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/contract_mesh.h"
#include "libstm/skeleton/contraction_proxy.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace sdm::cli {
namespace {

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
    add("Spot", sdm::load_mesh(o.spot).mesh);
  else
    progress("bench: Spot skipped, " + o.spot + " not found (--spot PATH)");
  if (std::filesystem::exists(o.bunny)) {
    auto proxy = contraction_proxy(sdm::load_mesh(o.bunny).mesh);
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

}  // namespace

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

}  // namespace sdm::cli
