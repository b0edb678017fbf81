#pragma once
// Helpers shared by the tests: temporary folders and running the sdm binary.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace test_util {

// A fresh folder under the system temp directory, removed when the object goes out of scope.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("sdm-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// The closed meshes of ../shared/models (what the round trips and layouts are measured on), with their genus (the CGAL
// meshes' README); only those this checkout has (the tests skip, with a warning, when none).
struct SharedMesh {
  std::string name, path;
  int genus = 0;
};
inline std::vector<SharedMesh> closed_shared_meshes() {
  const std::string models = std::string(SDM_TEST_DATA) + "/../../../shared/models/";
  const std::vector<std::pair<std::string, int>> all = {
      {"humans/tr_reg_007.off", 0},  {"humans/tr_reg_024.off", 0},   {"humans/tr_reg_085.off", 0},
      {"humans/8_gorilla_01.off", 0}, {"humans/8_man_02.off", 0},     {"cgal/bunny00.off", 0},
      {"cgal/blobby.off", 0},         {"cgal/retinal.off", 0},        {"cgal/double-torus-example.off", 2},
      {"cgal/rotor.off", 1},          {"cgal/anchor_dense.off", 4},   {"spot/spot_triangulated.obj", 0}};
  std::vector<SharedMesh> present;
  for (const auto& [name, genus] : all)
    if (std::ifstream(models + name).good()) present.push_back({name, models + name, genus});
  return present;
}

// A shell command capping the address space at 1 GB, to put before a command under test: a reader
// that trusted a hostile header fails with bad_alloc (exit 1) instead of taking the machine. The
// sanitizers reserve terabytes of shadow memory up front, so under them the cap is left out.
inline std::string memory_cap() {
#if defined(__SANITIZE_ADDRESS__)
  return "true";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return "true";
#else
  return "ulimit -v 1048576";
#endif
#else
  return "ulimit -v 1048576";
#endif
}

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `PROGRAM ARGS` and captures its output and exit code.
inline RunResult run_program(const std::string& program, const std::string& args) {
  RunResult r;
  std::string cmd = program + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs `sdm ARGS` (the binary built with the tests) and captures its output and exit code.
inline RunResult run_sdm(const std::string& args) { return run_program(SDM_BINARY, args); }

// The JSON object a command printed last (`--json`), after its progress lines: the object that
// starts a line of its own. Throws (the test fails) when there is none.
inline nlohmann::json last_json(const RunResult& r) {
  const size_t at = r.output.rfind("\n{\n");
  if (at == std::string::npos) throw std::runtime_error("no JSON object in the output:\n" + r.output);
  return nlohmann::json::parse(r.output.substr(at + 1));
}

inline void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace test_util
