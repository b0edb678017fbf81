// Every command prints one summary: its --json object, or the text read from that object. The text
// and the JSON of the same run carry the same numbers (counts, genus, distances).
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "tests/synthetic_shapes.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <regex>
#include <string>

namespace {

// The text after `label` on the line that starts with it (two spaces, the label, spaces).
std::string field(const std::string& text, const std::string& label) {
  std::smatch m;
  const std::regex line("(^|\n)  " + label + " +([^\n]*)");
  if (!std::regex_search(text, m, line)) return "";
  return m[2].str();
}

// The first number after `before` in `text`; NaN when there is none.
double number_after(const std::string& text, const std::string& before) {
  const size_t at = text.find(before);
  if (at == std::string::npos) return NAN;
  return std::stod(text.substr(at + before.size()));
}

}  // namespace

TEST_CASE("sdm info prints the counts, genus and repair of its --json object as text", "[cli][summaries]") {
  test_util::TempDir dir;
  const std::string torus = std::string(SDM_TEST_DATA) + "/double-torus-example.off";
  // A tetrahedron with one face twice: repair drops the copy, the text names the repaired counts.
  const std::string tetra = dir / "tetra.off";
  test_util::write_file(tetra, "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 1 2 3\n");
  for (const std::string& in : {torus, tetra}) {
    const test_util::RunResult text = test_util::run_sdm("info " + in), json = test_util::run_sdm("info --json " + in);
    INFO(text.output << json.output);
    REQUIRE(text.exit_code == 0);
    REQUIRE(json.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(json.output);
    const sdm::Mesh mesh = sdm::load_mesh(in).mesh;
    CHECK(std::stol(field(text.output, "vertices")) == j.at("vertices").get<long>());
    CHECK(std::stol(field(text.output, "faces")) == j.at("faces").get<long>());
    CHECK(std::stol(field(text.output, "edges")) == j.at("edges").get<long>());
    CHECK(std::stol(field(text.output, "boundary loops")) == j.at("boundary_loops").get<long>());
    CHECK(field(text.output, "pipeline") == (j.at("repair").at("changed").get<bool>() ? "ok after repair" : "ok"));
    if (in == torus) {
      // Genus 2 (the CGAL set's README); nothing to repair, so the file's counts are the mesh's.
      CHECK(field(text.output, "genus per part") == "2");
      CHECK(j.at("genus_per_part") == nlohmann::json::array({2}));
      CHECK(j.at("vertices").get<size_t>() == mesh.n_vertices());
      CHECK(j.at("faces").get<size_t>() == mesh.n_faces());
      const std::string box = field(text.output, "bounding box");
      CHECK(std::stod(box.substr(1)) == Approx(j.at("bbox_min")[0].get<double>()).epsilon(1e-5));
    } else {
      // Five faces as read, four repaired: V - E + F = 2 for the closed tetrahedron.
      CHECK(j.at("faces").get<long>() == 5);
      const nlohmann::json& fixed = j.at("repaired");
      CHECK(fixed.at("faces").get<long>() == 4);
      CHECK(fixed.at("vertices").get<long>() - fixed.at("edges").get<long>() + fixed.at("faces").get<long>() == 2);
      const std::string repaired = field(text.output, "repaired");
      CHECK(repaired == std::to_string(fixed.at("vertices").get<long>()) + " vertices, 4 faces, 1 parts, 0 boundary loops");
      CHECK(mesh.n_faces() == 4);
    }
  }
}

TEST_CASE("sdm compare prints the RMS and Hausdorff distance of its --json object as text", "[cli][summaries]") {
  test_util::TempDir dir;
  // Two tori around z of the same tessellation, the minor radius 0.5 and 0.55: the surfaces lie
  // 0.05 apart everywhere, the reference's diagonal is sqrt(5^2 + 5^2 + 1^2).
  const double gap = 0.05, diagonal = std::sqrt(51.0);
  sdm::write_mesh(synth::torus(2, 0.5, 8).mesh, dir / "thin.off");
  sdm::write_mesh(synth::torus(2, 0.5 + gap, 8).mesh, dir / "thick.off");
  const std::string args = "compare " + (dir / "thin.off") + " " + (dir / "thick.off") + " --samples 20000";
  const test_util::RunResult text = test_util::run_sdm(args), json = test_util::run_sdm(args + " --json");
  INFO(text.output << json.output);
  REQUIRE(text.exit_code == 0);
  REQUIRE(json.exit_code == 0);
  const nlohmann::json j = nlohmann::json::parse(json.output);
  const double rms = j.at("rms").get<double>(), hausdorff = j.at("hausdorff").get<double>();
  CHECK(rms == Approx(gap / diagonal).epsilon(0.03));
  CHECK(hausdorff == Approx(gap / diagonal).epsilon(0.03));
  CHECK(j.at("samples").get<int>() == 20000);
  // The text gives both in percent of the diagonal, 6 significant digits.
  CHECK(number_after(text.output, ": RMS ") == Approx(100 * rms).epsilon(1e-5));
  CHECK(number_after(text.output, ", Hausdorff ") == Approx(100 * hausdorff).epsilon(1e-5));
}

TEST_CASE("sdm primitive prints the counts and genus of its --json object as text", "[cli][summaries]") {
  test_util::TempDir dir;
  const test_util::RunResult text = test_util::run_sdm("primitive donut -o " + (dir / "a.off")),
                             json = test_util::run_sdm("primitive donut --json -o " + (dir / "b.off"));
  INFO(text.output << json.output);
  REQUIRE(text.exit_code == 0);
  REQUIRE(json.exit_code == 0);
  const nlohmann::json j = nlohmann::json::parse(json.output);
  const sdm::Mesh mesh = sdm::load_mesh(dir / "a.off").mesh;
  CHECK(j.at("genus").get<int>() == 1);
  CHECK(std::stol(field(text.output, "vertices")) == j.at("vertices").get<long>());
  CHECK(j.at("vertices").get<size_t>() == mesh.n_vertices());
  CHECK(std::stol(field(text.output, "faces")) == j.at("faces").get<long>());
  CHECK(std::stol(field(text.output, "genus")) == 1);
  CHECK(number_after(text.output, "min angle") == Approx(j.at("min_angle_degrees").get<double>()).epsilon(1e-5));
}
