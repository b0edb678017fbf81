#include "apps/bench.h"

#include <fstream>
#include <iostream>
#include <thread>

#include <sys/resource.h>

namespace sdm::cli {
namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace

std::string machine_line() {
  return cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
}

size_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return size_t(u.ru_maxrss) * 1024;
}

nlohmann::json rows_per_file(const std::vector<std::string>& paths, const std::string& what,
                             const std::function<nlohmann::json(const std::string&)>& row) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string& path : paths) {
    rows.push_back(row(path));
    std::cerr << "bench: " << what << " " << path << "\n";
  }
  return rows;
}

}  // namespace sdm::cli
