// Validation: every class of broken input is built here, reported with its count, refused with
// exit code 2 when the pipeline cannot take it, and nothing is written.
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>

using namespace sdm;
namespace fs = std::filesystem;

namespace {

const char* kTetraPoints = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const char* kTetraFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string off(int nv, int nf, const std::string& points, const std::string& faces) {
  std::ostringstream s;
  s << "OFF\n" << nv << ' ' << nf << " 0\n" << points << faces;
  return s.str();
}

const Finding* find(const MeshReport& r, const std::string& kind_part) {
  for (const auto& f : r.findings)
    if (f.kind.find(kind_part) != std::string::npos) return &f;
  return nullptr;
}

// How the pipeline takes a class: refused (even repaired), tolerated (reported, written; --strict
// refuses), repaired (refused as it is with --no-repair; by default repaired and written, the
// repair named), or repaired but still refused (the repair leaves another fatal finding).
enum class Outcome { refused, tolerated, repaired, refused_after_repair };

struct Case {
  std::string name, file_name, content, expect_message;
  Outcome outcome;
  std::string repaired_message = "";  // in the output of the default run, for the two repaired kinds
};

void check_refused(const test_util::RunResult& r, const std::string& message) {
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(message) != std::string::npos);
  const bool says_how = r.output.find("Fix") != std::string::npos || r.output.find("supported") != std::string::npos ||
                        r.output.find("cannot read") != std::string::npos;
  CHECK(says_how);
}

}  // namespace

TEST_CASE("A closed tetrahedron is valid with genus 0 and one part", "[validate]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "t.off", off(4, 4, kTetraPoints, kTetraFaces));
  MeshReport r = validate_mesh(read_mesh_soup(dir / "t.off"));
  CHECK(r.usable());
  CHECK(r.findings.empty());
  CHECK(r.parts == 1);
  CHECK(r.genus_per_part == std::vector<int>{0});
  CHECK(r.edges == 6);
  CHECK(r.boundary_loops == 0);
}

TEST_CASE("Each invalid input class is reported and refused with exit code 2 and leaves no output", "[validate]") {
  test_util::TempDir dir;
  // Two tetrahedra glued at one vertex: every edge is manifold, the shared vertex is not.
  const std::string two_tetra_points = std::string(kTetraPoints) + "-1 0 0\n0 -1 0\n0 0 -1\n";
  const std::string tetra_b = "3 0 5 4\n3 0 4 6\n3 0 6 5\n3 4 5 6\n";
  // Three triangles sharing edge (0,1) plus closing faces: the edge is used three times.
  const std::string fin_points = std::string(kTetraPoints) + "0 -1 -1\n";
  const std::vector<Case> cases = {
      {"empty file", "empty.off", "", "empty", Outcome::refused},
      {"unreadable", "garbage.off", "this is not a mesh\n", "cannot read", Outcome::refused},
      {"unknown format", "mesh.abc", "1 2 3\n", "unknown format", Outcome::refused},
      {"no faces", "points.off", off(4, 0, kTetraPoints, ""), "no face", Outcome::refused},
      {"NaN coordinates", "nan.off", off(4, 4, "0 0 0\n1 0 0\nnan 1 0\n0 0 1\n", kTetraFaces), "NaN", Outcome::refused},
      {"infinite coordinates (OBJ)", "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
       "NaN or infinite", Outcome::refused},
      // An open sheet capped over its hole still encloses nothing.
      {"flat open sheet", "sheet.off", off(4, 2, "0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 1 2\n3 0 2 3\n"), "enclosing no volume", Outcome::refused},
      // The fin peels off the tetrahedron as a flat sheet as large as the tetrahedron: still refused.
      {"non-manifold edge", "fin.off", off(5, 5, fin_points, std::string(kTetraFaces) + "3 0 1 4\n"), "non-manifold edges",
       Outcome::refused_after_repair, "enclosing no volume"},
      {"non-manifold vertex", "bowtie.off", off(7, 8, two_tetra_points, std::string(kTetraFaces) + tetra_b), "non-manifold vertices",
       Outcome::repaired, "repaired: 1 non-manifold vertices split"},
      {"duplicated face", "dup.off", off(4, 5, kTetraPoints, std::string(kTetraFaces) + "3 0 2 1\n"), "duplicated faces", Outcome::repaired,
       "repaired: 1 faces dropped: duplicates of another face"},
      {"inconsistent orientation", "flip.off", off(4, 4, kTetraPoints, "3 0 1 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"), "inconsistently oriented",
       Outcome::repaired, "repaired: 1 faces flipped to agree"},
      {"invalid face", "badidx.off", off(4, 4, kTetraPoints, "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 2\n"), "invalid faces", Outcome::repaired,
       "repaired: 1 faces dropped: a repeated corner"},
      // Tolerated: reported, written by default, refused by --strict.
      {"degenerate face", "flat.off", off(6, 8, "1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0.5 0.5 0\n0 0 -1\n",
                                           "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n"),
       "degenerate (zero-area) faces", Outcome::tolerated},
      // Open meshes go through (the skeleton fills the holes); --strict refuses them.
      {"open mesh", "open.off", off(4, 3, kTetraPoints, "3 0 2 1\n3 0 1 3\n3 0 3 2\n"), "boundary edges", Outcome::tolerated},
      {"isolated vertex", "iso.off", off(5, 4, std::string(kTetraPoints) + "5 5 5\n", kTetraFaces), "isolated vertices", Outcome::tolerated},
  };
  for (const auto& c : cases) {
    SECTION(c.name) {
      const std::string in = dir / c.file_name;
      const std::string out = dir / "out.obj";
      test_util::write_file(in, c.content);
      auto r = test_util::run_sdm("convert " + in + " -o " + out);
      INFO(r.output);
      if (c.outcome == Outcome::refused) {
        check_refused(r, c.expect_message);
        CHECK_FALSE(fs::exists(out));
        auto info = test_util::run_sdm("info " + in);
        CHECK(info.exit_code == 2);
      } else if (c.outcome == Outcome::tolerated) {
        CHECK(r.exit_code == 0);
        CHECK(r.output.find(c.expect_message) != std::string::npos);
        CHECK(fs::exists(out));
        fs::remove(out);
        auto strict = test_util::run_sdm("convert --strict " + in + " -o " + out);
        CHECK(strict.exit_code == 2);
        CHECK(strict.output.find(c.expect_message) != std::string::npos);
        CHECK_FALSE(fs::exists(out));
      } else {
        const bool written = c.outcome == Outcome::repaired;
        CHECK(r.exit_code == (written ? 0 : 2));
        CHECK(r.output.find(c.repaired_message) != std::string::npos);
        CHECK(fs::exists(out) == written);
        if (written) CHECK(validate_mesh(read_mesh_soup(out)).usable());  // as written, without a repair
        std::error_code ec;
        fs::remove(out, ec);
        auto info = test_util::run_sdm("info " + in);
        CHECK(info.exit_code == (written ? 0 : 2));
        for (const std::string flag : {"--no-repair", "--strict"}) {
          auto as_is = test_util::run_sdm("convert " + flag + " " + in + " -o " + out);
          INFO(flag << ": " << as_is.output);
          check_refused(as_is, c.expect_message);
          CHECK_FALSE(fs::exists(out));
        }
        CHECK(test_util::run_sdm("info --no-repair " + in).exit_code == 2);
      }
      // Nothing but the input is left in the folder: no temporary files either.
      const auto left = std::distance(fs::directory_iterator(dir.path), fs::directory_iterator());
      CHECK(left == 1);
      fs::remove(in);
    }
  }
}

TEST_CASE("Counts and examples are exact", "[validate]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "open.off", off(4, 2, kTetraPoints, "3 0 2 1\n3 0 1 3\n"));
  MeshReport r = validate_mesh(read_mesh_soup(dir / "open.off"));
  const Finding* b = find(r, "boundary");
  REQUIRE(b);
  CHECK(b->count == 4);  // two triangles sharing one edge: 4 boundary edges
  CHECK(r.boundary_loops == 1);
  CHECK(r.boundary_loops_per_part == std::vector<int>{1});
  CHECK(r.genus_per_part == std::vector<int>{0});  // a disc: a sphere once capped
  CHECK(r.usable());
}

TEST_CASE("Several parts are allowed and reported with their genus", "[validate]") {
  test_util::TempDir dir;
  // Two disjoint tetrahedra.
  const std::string pts = std::string(kTetraPoints) + "5 0 0\n6 0 0\n5 1 0\n5 0 1\n";
  const std::string faces = std::string(kTetraFaces) + "3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n";
  test_util::write_file(dir / "two.off", off(8, 8, pts, faces));
  MeshReport r = validate_mesh(read_mesh_soup(dir / "two.off"));
  CHECK(r.usable());
  CHECK(r.parts == 2);
  CHECK(r.genus_per_part == std::vector<int>{0, 0});
  auto info = test_util::run_sdm("info --json " + (dir / "two.off"));
  CHECK(info.exit_code == 0);
  CHECK(info.output.find("\"parts\": 2") != std::string::npos);
}

TEST_CASE("Inside-out input is flipped to point outwards", "[validate]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "inv.off", off(4, 4, kTetraPoints, "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n"));
  Mesh m = load_mesh(dir / "inv.off").mesh;
  double volume = 0;
  for (auto f : m.faces()) {
    Eigen::Vector3d p[3];
    int c = 0;
    for (auto v : m.fv_range(f)) p[c++] = point(m, v);
    volume += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  CHECK(volume == Approx(1.0 / 6.0));
}

TEST_CASE("Genus of the real meshes matches their documentation", "[validate]") {
  // shared/models/cgal/README.md: rotor genus 1, double-torus-example genus 2.
  for (auto [file, genus] : {std::pair<const char*, int>{"rotor.off", 1}, {"double-torus-example.off", 2}}) {
    MeshReport r = validate_mesh(read_mesh_soup(std::string(SDM_TEST_DATA) + "/" + file));
    INFO(file);
    CHECK(r.usable());
    CHECK(r.genus_per_part == std::vector<int>{genus});
  }
}
