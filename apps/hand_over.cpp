#include "apps/hand_over.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <unistd.h>

// SDM_FULL_RELATIVE: libexec/sdm relative to bin, from CMake's install directories (CMakeLists.txt).

namespace sdm::cli {

bool runs_here(const std::vector<std::string>& commands, int argc, char** argv) {
  if (argc < 2) return false;
  const std::string first = argv[1];
  return first == "--version" || std::find(commands.begin(), commands.end(), first) != commands.end();
}

int hand_over(char** argv) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path folder = ec ? fs::path(argv[0]).parent_path() : self.parent_path();
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

}  // namespace sdm::cli
