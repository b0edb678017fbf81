// The two programs of the command line (apps/hand_over.h): sdm runs the light commands itself and
// hands every other command line to sdm-full beside it; alone, it says what is missing.
#include <catch2/catch.hpp>

#include <filesystem>

#include "test_util.h"

namespace fs = std::filesystem;

TEST_CASE("sdm hands the commands it lacks to sdm-full and runs the light ones itself", "[cli]") {
  // --help comes from sdm-full: it lists the handed commands too.
  const auto help = test_util::run_sdm("--help");
  CHECK(help.exit_code == 0);
  CHECK(help.output.find("encode") != std::string::npos);
  CHECK(help.output.find("transfer") != std::string::npos);
  // A handed command runs (its own options reach it) and names itself "sdm" in its usage line.
  const auto encode_help = test_util::run_sdm("encode --help");
  CHECK(encode_help.exit_code == 0);
  CHECK(encode_help.output.find("OpenEXR") != std::string::npos);
  CHECK(encode_help.output.find("sdm-full") == std::string::npos);

  // sdm alone in a folder: the light commands work, a handed one exits 1 naming sdm-full and writes nothing.
  test_util::TempDir dir;
  const fs::path alone = dir.path / "sdm";
  fs::copy_file(SDM_BINARY, alone);
  const std::string mesh = dir / "capsule.ply", map = dir / "capsule.exr";
  auto run = [&](const std::string& args) { return test_util::run_program(alone.string(), args); };
  CHECK(run("--version").exit_code == 0);
  REQUIRE(run("primitive capsule -o " + mesh).exit_code == 0);
  const auto info = run("info " + mesh + " --json");
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.output);
  CHECK(j["genus_per_part"][0] == 0);
  CHECK(j["faces"].get<int>() == 2 * j["vertices"].get<int>() - 4);  // closed genus 0: V - E + F = 2
  const auto encode = run("encode " + mesh + " -o " + map + " --size 64");
  CHECK(encode.exit_code == 1);
  CHECK(encode.output.find("sdm-full") != std::string::npos);
  CHECK_FALSE(fs::exists(map));
}
