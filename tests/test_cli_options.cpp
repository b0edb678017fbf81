// The options every command shares (apps/options.h): an output's extension in any case, the memory
// an atlas needs against --max-memory whether --size or a --layout file gives its size, and
// --strict refusing the tolerated findings by their identifiers.
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/validate_mesh.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using test_util::run_sdm;

namespace {

// A capsule, its layout on a 256 atlas and its map.
struct CapsuleFiles {
  test_util::TempDir dir;
  std::string mesh = dir / "cap.obj", layout = dir / "layout.json", map = dir / "cap.exr";
  CapsuleFiles() {
    REQUIRE(run_sdm("primitive capsule -o " + mesh).exit_code == 0);
    REQUIRE(run_sdm("stm " + mesh + " --size 256 -o " + layout).exit_code == 0);
    REQUIRE(run_sdm("encode " + mesh + " --layout " + layout + " -o " + map).exit_code == 0);
  }
};

void expect_refused(const test_util::RunResult& r, const std::string& message) {
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(message) != std::string::npos);
}

}  // namespace

TEST_CASE("an output's extension is recognised in any case", "[cli][options]") {
  CapsuleFiles cap;
  // --write-skeleton X.OBJ writes the skeleton as an OBJ polyline (a 'v' per node, an 'l' per edge), as x.obj does.
  const std::string skeleton = cap.dir / "SK.OBJ", decoded = cap.dir / "D.OBJ";
  auto r = run_sdm("decode " + cap.map + " --lod 1 -o " + decoded + " --write-skeleton " + skeleton);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const nlohmann::json layout = nlohmann::json::parse(std::ifstream(cap.layout));
  std::ifstream in(skeleton);
  std::string line;
  size_t vertices = 0, lines = 0;
  while (std::getline(in, line)) vertices += line.rfind("v ", 0) == 0, lines += line.rfind("l ", 0) == 0;
  CHECK(vertices == layout["skeleton"]["nodes"].size());
  CHECK(lines == layout["skeleton"]["edges"].size());
  CHECK(sdm::read_mesh_soup(decoded).triangles.size() > 0);

  // --rig takes .GLB; transfer takes -o OUT.OBJ, --correspondence C.TXT and --vertex-colors V.PLY (it
  // stops later, at the source without a texture, not at an extension).
  CHECK(run_sdm("decode " + cap.map + " --lod 0 --rig -o " + cap.dir / "R.GLB").exit_code == 0);
  r = run_sdm("transfer --source " + cap.mesh + " --target " + cap.mesh + " -o " + cap.dir / "T.OBJ" + " --correspondence " +
              cap.dir / "C.TXT" + " --vertex-colors " + cap.dir / "V.PLY");
  expect_refused(r, "names no texture in its material and has no vertex colours");
  CHECK(r.output.find("must") == std::string::npos);
  // What is not one of them is still refused, naming the option.
  expect_refused(run_sdm("transfer --source " + cap.mesh + " --target " + cap.mesh + " -o " + cap.dir / "T.STL"), "--output must be");
  expect_refused(run_sdm("decode " + cap.map + " --rig -o " + cap.dir / "R.OBJ"), "--rig writes a glTF skin");
  expect_refused(run_sdm("correspond " + cap.mesh + " " + cap.mesh + " -o " + cap.dir / "C.CSV"), "-o must name a .txt or .json file");
}

TEST_CASE("an atlas beyond --max-memory is refused up front, its size from --size or from the --layout file", "[cli][options]") {
  CapsuleFiles cap;
  // The same layout claiming an 8192 atlas: 10 bytes a texel for encode (0.67 GB), 60 for remap (4 GB).
  nlohmann::json big = nlohmann::json::parse(std::ifstream(cap.layout));
  big["size"] = 8192;
  const std::string big_layout = cap.dir / "big.json", out = cap.dir / "out";
  test_util::write_file(big_layout, big.dump());
  for (const std::string& command : {"encode " + cap.mesh + " -o " + out + ".exr", "remap " + cap.mesh + " -o " + out + ".png"}) {
    expect_refused(run_sdm(command + " --layout " + big_layout + " --max-memory 100M"), "an atlas of 8192^2 texels needs about");
    expect_refused(run_sdm(command + " --size 8192 --max-memory 100M"), "an atlas of 8192^2 texels needs about");
  }
  expect_refused(run_sdm("roundtrip " + cap.mesh + " --size 8192 --max-memory 100M"), "an atlas of 8192^2 texels needs about");
  CHECK_FALSE(fs::exists(out + ".exr"));
  CHECK_FALSE(fs::exists(out + ".png"));
  // The layout's own 256 atlas (0.7 MB) is within the same budget.
  const auto ok = run_sdm("encode " + cap.mesh + " --layout " + cap.layout + " --max-memory 100M -o " + out + ".exr");
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
}

TEST_CASE("The --strict option refuses the tolerated findings by their identifiers and passes the others", "[cli][options]") {
  test_util::TempDir dir;
  // A cube of quads (triangulated on read) and two tetrahedra apart (two parts): tolerated findings
  // --strict lets through; the same tetrahedron with a loose vertex: one it refuses.
  const std::string cube =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n", tetra_faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const std::string apart = tetra + "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n" + tetra_faces + "f 5 7 6\nf 5 6 8\nf 5 8 7\nf 6 7 8\n";
  test_util::write_file(dir / "cube.obj", cube);
  test_util::write_file(dir / "apart.obj", apart);
  test_util::write_file(dir / "loose.obj", tetra + "v 9 9 9\n" + tetra_faces);
  const std::map<std::string, std::string> expected_id = {
      {"cube.obj", "polygons_triangulated"}, {"apart.obj", "parts"}, {"loose.obj", "isolated_vertices"}};
  for (const auto& [name, id] : expected_id) {
    INFO(name);
    const sdm::MeshReport r = sdm::validate_mesh(sdm::read_mesh_soup(dir / name));
    std::set<std::string> ids;
    for (const auto& f : r.findings) ids.insert(f.id);
    CHECK(ids == std::set<std::string>{id});
    const auto info = run_sdm("info --json " + dir / name);
    REQUIRE(info.exit_code == 0);
    CHECK(nlohmann::json::parse(info.output.substr(info.output.find("{\n")))["findings"][0]["id"] == id);
  }
  CHECK(run_sdm("convert --strict " + dir / "cube.obj -o " + dir / "cube.off").exit_code == 0);
  CHECK(run_sdm("convert --strict " + dir / "apart.obj -o " + dir / "apart.off").exit_code == 0);
  expect_refused(run_sdm("convert --strict " + dir / "loose.obj -o " + dir / "loose.off"), "refused by --strict");
  expect_refused(run_sdm("info --strict " + dir / "loose.obj"), "isolated vertices (in no face)");
  CHECK_FALSE(fs::exists(dir / "loose.off"));
}
