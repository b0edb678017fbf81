#include "apps/memory_budget.h"

#include "libstm/core/errors.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace sdm::cli {

void add_max_memory_option(CLI::App* app, std::string& value) {
  app->add_option("--max-memory", value,
                  "Refuse up front when the estimated peak memory exceeds this (e.g. 8G, 512M; default: 3/4 of the\n"
                  "machine's memory)");
}

double memory_budget(const std::string& value) {
  if (value.empty()) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? 0.75 * double(pages) * double(page) : 8e9;
  }
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  std::string unit(end);
  for (auto& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (!unit.empty() && unit.back() == 'B') unit.pop_back();
  const double scale = unit.empty() ? 1 : unit == "K" ? 1024.0 : unit == "M" ? 1048576.0 : unit == "G" ? 1073741824.0 : unit == "T" ? 1099511627776.0 : -1;
  if (end == value.c_str() || scale < 0 || !(x > 0) || !std::isfinite(x * scale))
    throw InputError("--max-memory " + value + " is not a size (write e.g. 8G, 512M or a number of bytes)");
  return x * scale;
}

std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= 1073741824.0) std::snprintf(buf, sizeof buf, "%.1f GB", bytes / 1073741824.0);
  else std::snprintf(buf, sizeof buf, "%.0f MB", bytes / 1048576.0);
  return buf;
}

void check_memory(double estimate, const std::string& max_memory, const std::string& what, const std::string& fix) {
  const double budget = memory_budget(max_memory);
  if (estimate <= budget) return;
  throw InputError(what + " needs about " + format_bytes(estimate) + " of memory, more than the budget of " + format_bytes(budget) +
                   (max_memory.empty() ? " (3/4 of this machine's memory)" : " (--max-memory)") + ": " + fix +
                   ", or raise --max-memory");
}

sdm::ImageBudget image_budget(const std::string& max_memory, const std::string& path) {
  return [max_memory, path](double bytes, int width, int height) {
    check_memory(bytes, max_memory, "decoding image " + path + " (" + std::to_string(width) + " x " + std::to_string(height) + " pixels)",
                 "use a smaller image");
  };
}

sdm::ReadBudget json_budget(const std::string& max_memory, const std::string& path) {
  return [max_memory, path](double bytes) { check_memory(bytes, max_memory, "reading " + path, "use a smaller file"); };
}

void check_atlas_memory(int size, double bytes_per_texel, const std::string& max_memory) {
  check_memory(bytes_per_texel * double(size) * double(size), max_memory, "an atlas of " + std::to_string(size) + "^2 texels",
               "use a smaller --size");
}

}  // namespace sdm::cli
