// sdm bench --commands: a mesh through skeleton, stm, encode and decode as a user runs them, each a
// process of the `sdm` beside this program, beside the same stages in this process
// (docs/BENCHMARKS.md, "The pipeline as commands").
#include "apps/bench.h"
#include "apps/commands.h"
#include "apps/hand_over.h"
#include "libstm/core/errors.h"

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <spawn.h>
#include <stdexcept>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace sdm::cli {
namespace {

struct ProcessTime {
  double wall = INFINITY, cpu = INFINITY;  // seconds; the fastest run's wall time and its CPU (user + system)
};

// Runs `args` (args[0]: the program) with stdout and stderr into `log`; its wall and CPU seconds.
// A command that fails is an error naming it and its log.
ProcessTime run_process(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (spawned != 0) throw std::runtime_error("bench: cannot start " + args[0] + ": " + std::strerror(spawned));
  int status = 0;
  rusage use{};
  while (wait4(pid, &status, 0, &use) < 0)
    if (errno != EINTR) throw std::runtime_error("bench: lost " + args[0] + ": " + std::strerror(errno));
  ProcessTime t;
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  t.cpu = double(use.ru_utime.tv_sec + use.ru_stime.tv_sec) + 1e-6 * double(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::string line;
    for (const std::string& a : args) line += (line.empty() ? "" : " ") + a;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const std::string what = "'" + line + "' failed (exit " + std::to_string(code) + "); its output: " + log.string();
    if (code == 2) throw sdm::InputError(what);  // the mesh: the command's own message says why
    throw std::runtime_error("bench: " + what);
  }
  return t;
}

// A fresh folder for one mesh's files, removed when done (kept with its logs when a command fails).
std::filesystem::path make_work_folder() {
  std::string pattern = (std::filesystem::temp_directory_path() / "sdm-bench-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("bench: cannot make a folder in " + std::filesystem::temp_directory_path().string());
  return pattern;
}

constexpr const char* kCommandNames[] = {"skeleton", "stm", "encode", "decode"};

// The four commands on `mesh` as README's pipeline runs them, the fastest of `repeat` each.
std::array<ProcessTime, 4> time_commands(const std::string& sdm, const std::string& mesh, int size, int repeat) {
  const std::filesystem::path dir = make_work_folder();
  const std::string S = (dir / "S.json").string(), L = (dir / "L.json").string(), map = (dir / "map.exr").string(),
                    out = (dir / "out.obj").string();
  const std::vector<std::string> lines[] = {
      {sdm, "skeleton", mesh, "-o", S},
      {sdm, "stm", mesh, "-o", L, "--skeleton", S, "--size", std::to_string(size)},
      {sdm, "encode", mesh, "-o", map, "--layout", L},
      {sdm, "decode", map, "-o", out, "--lod", "3"}};
  std::array<ProcessTime, 4> best;
  for (int i = 0; i < repeat; ++i)
    for (size_t c = 0; c < 4; ++c) {
      const ProcessTime t = run_process(lines[c], dir / (std::string(kCommandNames[c]) + ".log"));
      if (t.wall < best[c].wall) best[c] = t;
    }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return best;
}

void print_commands_table(const nlohmann::json& rows, int size, int repeat) {
  std::cout << "Commands as processes (atlas " << size << ", decode level 3; fastest of " << repeat << "; " << machine_line() << ")\n"
            << "| file | vertices | skeleton (s) | stm (s) | encode (s) | decode (s) | commands (s) | stages in one process (s) |\n"
            << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    std::cout << "| " << r["file"].get<std::string>() << " | " << r["vertices"] << std::fixed << std::setprecision(2);
    for (const char* c : kCommandNames) std::cout << " | " << r["commands"][c]["wall_s"].get<double>();
    std::cout << " | " << r["commands_s"].get<double>() << " | " << r["stages_s"].get<double>() << " |\n";
  }
  std::cout << "In-process stages (load, skeleton, layout, encode, decode 3):\n";
  for (const auto& r : rows) {
    const auto& s = r["stages"];
    std::cout << "  " << r["file"].get<std::string>() << ": " << s["load_s"].get<double>() << ", " << s["skeleton_s"].get<double>()
              << ", " << s["layout_s"].get<double>() << ", " << s["encode_s"].get<double>() << ", " << s["decode3_s"].get<double>()
              << "\n";
  }
}

}  // namespace

// Per file: the four commands as processes (wall and CPU seconds, the fastest of --repeat), and the
// stages of the same mesh in this process (time_pipeline), the gap between them being what the
// commands add: process starts, loading and repairing the mesh in each, files, encode's check.
int run_commands_bench(const BenchOptions& o) {
  const std::string sdm = front_program("/proc/self/exe").string();
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string& path : o.commands) {
    const std::string mesh = std::filesystem::absolute(path).string();
    const std::array<ProcessTime, 4> t = time_commands(sdm, mesh, o.size, o.repeat);
    const PipelineTimes p = time_pipeline(mesh, o.size, o.repeat);
    nlohmann::json commands = nlohmann::json::object();
    double all = 0;
    for (size_t c = 0; c < 4; ++c) {
      commands[kCommandNames[c]] = {{"wall_s", t[c].wall}, {"cpu_s", t[c].cpu}};
      all += t[c].wall;
    }
    std::cerr << "bench: commands " << path << "\n";
    rows.push_back({{"file", path}, {"vertices", p.vertices}, {"commands", commands}, {"commands_s", all},
                    {"stages", {{"load_s", p.load}, {"skeleton_s", p.skeleton}, {"layout_s", p.layout}, {"encode_s", p.encode},
                                {"decode3_s", p.decode3}}},
                    {"stages_s", p.load + p.skeleton + p.layout + p.encode + p.decode3}});
  }
  if (o.json) print_json({{"machine", machine_line()}, {"program", sdm}, {"size", o.size}, {"repeat", o.repeat}, {"meshes", rows}});
  else print_commands_table(rows, o.size, o.repeat);
  return 0;
}

}  // namespace sdm::cli
