#include "apps/hand_over.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <unistd.h>
#include <vector>

// SDM_FULL_RELATIVE: libexec/sdm relative to bin, from CMake's install directories (CMakeLists.txt).

namespace sdm::cli {
namespace {

// This program's file: /proc/self/exe, or argv[0] where that cannot be read.
std::filesystem::path this_program(const char* argv0) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path(argv0) : self;
}

}  // namespace

bool runs_here(const std::vector<std::string>& commands, int argc, char** argv) {
  if (argc < 2) return false;
  const std::string first = argv[1];
  return first == "--version" || std::find(commands.begin(), commands.end(), first) != commands.end();
}

int hand_over(char** argv) {
  namespace fs = std::filesystem;
  const fs::path folder = this_program(argv[0]).parent_path();
  const fs::path places[] = {folder / "sdm-full", folder / SDM_FULL_RELATIVE / "sdm-full"};
  for (const fs::path& full : places) {
    if (::access(full.c_str(), X_OK) != 0) continue;
    const std::string name = full.string();
    ::execv(name.c_str(), argv);  // argv[0] stays the user's word, so usage lines say "sdm"
    std::cerr << "sdm: failed: cannot start " << name << ": " << std::strerror(errno) << std::endl;
    return 1;
  }
  std::cerr << "sdm: failed: this command needs sdm-full, which is neither at " << places[0].string() << " nor at "
            << places[1].lexically_normal().string() << ". Fix: build or install sdm again (both programs)." << std::endl;
  return 1;
}

std::filesystem::path front_program(const char* argv0) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path program = this_program(argv0);
  if (program.filename() != "sdm-full") return program;
  const fs::path folder = program.parent_path();
  for (const fs::path& front : {folder / "sdm", folder / SDM_FRONT_RELATIVE / "sdm"})
    if (fs::exists(front, ec)) return front.lexically_normal();
  return program;
}

int hand_over_to_batch(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path folder = this_program(argv[0]).parent_path();
  // The commands run by `sdm`, the front (it starts faster), also when sdm-full was asked.
  const fs::path front = front_program(argv[0]);
  const fs::path places[] = {folder / "python" / "sdm_batch.py", folder / SDM_BATCH_RELATIVE / "sdm_batch.py"};
  for (const fs::path& script : places) {
    if (!fs::exists(script, ec)) continue;
    const std::string python = ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
    std::vector<std::string> args = {python, script.string(), "--sdm", front.string()};
    for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
    std::vector<char*> c;
    for (auto& a : args) c.push_back(a.data());
    c.push_back(nullptr);
    ::execvp(python.c_str(), c.data());
    std::cerr << "sdm: failed: cannot start " << python << " for sdm batch: " << std::strerror(errno)
              << ". Fix: install python3 and python3-distributed (scripts/install-deps.sh)" << std::endl;
    return 1;
  }
  std::cerr << "sdm: failed: sdm batch needs sdm_batch.py, which is neither at " << places[0].string() << " nor at "
            << places[1].lexically_normal().string() << ". Fix: build or install sdm again." << std::endl;
  return 1;
}

}  // namespace sdm::cli
