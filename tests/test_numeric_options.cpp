// Every numeric option of every command refuses nan, inf, -inf and values outside its range (exit 2,
// the option, the value and the range named). The options are found in each command's --help
// (CLI11 shows the type, and number_in's range after it: "--size INT:in [16, 16384]"), so an option
// added without the check fails here.
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using test_util::run_sdm;

namespace {

struct NumericOption {
  std::string command, name, type, range;  // range: "[lo, hi]" or "(lo, hi]", empty when the help shows none
  double lo = 0, hi = 0;
  bool open_low = false;
};

std::vector<std::string> commands() {
  const test_util::RunResult r = run_sdm("--help");
  REQUIRE(r.exit_code == 0);
  std::vector<std::string> out;
  std::istringstream in(r.output.substr(r.output.find("Subcommands:")));
  std::string line;
  const std::regex entry(R"(^  ([a-z]+)\s)");
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, entry)) out.push_back(m[1]);
  return out;
}

// The options of `command` whose type is a number (INT, UINT, FLOAT, NUMBER), with their range.
std::vector<NumericOption> numeric_options(const std::string& command) {
  const test_util::RunResult r = run_sdm(command + " --help");
  REQUIRE(r.exit_code == 0);
  std::vector<NumericOption> out;
  const std::regex option(R"(^\s+(?:-\w,)?(--[a-z0-9-]+) (INT|UINT|FLOAT|NUMBER)\b(?::in ([\[(])([^,\]]+), ([^\]]+)\])?)");
  std::istringstream in(r.output);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (!std::regex_search(line, m, option)) continue;
    NumericOption o;
    o.command = command, o.name = m[1], o.type = m[2];
    if (m[3].matched) {
      o.open_low = m[3] == "(";
      o.lo = std::stod(m[4]), o.hi = std::stod(m[5]);
      o.range = std::string(m[3]) + std::string(m[4]) + ", " + std::string(m[5]) + "]";
    }
    out.push_back(o);
  }
  return out;
}

// Values the option must refuse: not finite, and one beyond each end of its range.
std::vector<std::string> refused_values(const NumericOption& o) {
  std::vector<std::string> v = {"nan", "inf", "-inf"};
  std::ostringstream above, below;
  above << (o.hi > 0 ? 2 * o.hi + 1 : o.hi + 1);
  below << (o.open_low ? o.lo : o.lo < 0 ? 2 * o.lo - 1 : o.lo - 1);
  v.push_back(above.str());
  v.push_back(below.str());
  return v;
}

}  // namespace

TEST_CASE("every numeric option of every command refuses nan, inf and out-of-range values by name", "[cli][numeric_options]") {
  const std::vector<std::string> all = commands();
  REQUIRE(all.size() >= 16);
  int options = 0, runs = 0;
  for (const std::string& command : all) {
    for (const NumericOption& o : numeric_options(command)) {
      ++options;
      INFO("sdm " << command << " " << o.name << " " << o.type);
      CHECK_FALSE(o.range.empty());  // declared without number_in / number_above (apps/cli_common.h)
      if (o.range.empty()) continue;
      for (const std::string& value : refused_values(o)) {
        ++runs;
        const test_util::RunResult r = run_sdm(command + " " + o.name + "=" + value);
        INFO(value << " gave exit " << r.exit_code << ":\n" << r.output);
        CHECK(r.exit_code == 2);
        CHECK(r.output.find(o.name) != std::string::npos);
        CHECK(r.output.find(value) != std::string::npos);
        CHECK(r.output.find(o.range) != std::string::npos);
      }
    }
  }
  // Encode, decode, render, skeleton, ... have over forty between them; the walk must have found them.
  CHECK(options >= 40);
  CHECK(runs == 5 * options);
}

TEST_CASE("the options that hold a number in text refuse nan and inf", "[cli][numeric_options]") {
  for (const char* value : {"inf", "nan", "-1G", "infG"}) {
    const test_util::RunResult r = run_sdm(std::string("encode x.obj -o x.exr --max-memory ") + value);
    INFO(value << ":\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--max-memory") != std::string::npos);
  }
  // sdm batch (python/sdm_batch.py): --timeout and --workers.
  for (const char* args : {"--timeout nan", "--timeout inf", "--timeout 0", "--timeout -5", "--workers 0", "--workers 100000"}) {
    const test_util::RunResult r = run_sdm(std::string("batch x.obj -o out ") + args);
    INFO(args << ":\n" << r.output);
    CHECK(r.exit_code == 2);
    const std::string option = std::string(args).substr(0, std::string(args).find(' '));
    CHECK(r.output.find(option) != std::string::npos);
    CHECK(r.output.find("out of range") != std::string::npos);
  }
}

TEST_CASE("a numeric option in range still runs", "[cli][numeric_options]") {
  test_util::TempDir dir;
  const test_util::RunResult r = run_sdm("primitive cylinder --resolution 400 -o " + dir / "c.off");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  const test_util::RunResult n = run_sdm("remesh " + dir / "c.off" + " -o " + dir / "r.off" + " --factor 2 --iterations 2");
  INFO(n.output);
  CHECK(n.exit_code == 0);
}
