// Hostile and odd files around a mesh: inputs that are not regular files (named pipes, devices,
// folders) wherever a path is read (the mesh, its material library and texture, a glTF buffer or
// image, --skeleton, --layout, --texture, --stm), images whose header claims more than the memory
// budget or the bytes can hold, JSON beyond its size limit, a byte-order mark with the temporary
// folder unusable, file names that are not UTF-8, and valid files the readers refused (ASCII PLY
// with 16- and 32-bit list types, an OBJ face with a comment, map_Kd options and Windows paths).
// Every hostile case is refused by name with exit 2, and every valid one is read.
#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/obj_material.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sys/stat.h>

namespace fs = std::filesystem;
using test_util::memory_cap;
using test_util::run_sdm;
using test_util::TempDir;
using test_util::write_file;

namespace {

// Runs `sdm ARGS` through sh with `limits` applied first, under `timeout` so that a reader that
// blocks on a named pipe fails the test (exit 124) instead of hanging the suite.
test_util::RunResult run_sdm_guarded(const std::string& args, const std::string& limits = "true") {
  return test_util::run_program("sh -c '" + limits + "; exec timeout -k 5 60 " + std::string(SDM_BINARY) + " " + args + "'", "");
}

void expect_refused(const test_util::RunResult& r, const std::string& message) {
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(message) != std::string::npos);
  CHECK(r.output.find("std::") == std::string::npos);
}

// The JSON object that starts a line of its own in the output (--json).
nlohmann::json json_of(const test_util::RunResult& r) {
  INFO(r.output);
  const size_t at = r.output.rfind("\n{\n");
  REQUIRE((r.output.rfind("{\n", 0) == 0 || at != std::string::npos));
  return nlohmann::json::parse(at == std::string::npos ? r.output : r.output.substr(at + 1));
}

const std::string kTetraPoints = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
// A tetrahedron with texture coordinates, a material library `mtl` and its material.
std::string textured_tetra(const std::string& mtl) {
  return "mtllib " + mtl + "\n" + kTetraPoints + "vt 0 0\nvt 1 0\nvt 0 1\nusemtl skin\n" +
         "f 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/2 3/3 4/1\n";
}

std::string big_endian(uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

std::string png_chunk(const std::string& type, const std::string& data) {
  return big_endian(uint32_t(data.size())) + type + data + std::string(4, '\0');  // stb does not check the CRC
}

// A PNG whose header says side x side RGBA, with `padding` bytes of text: tiny files that claim a
// huge image, and (padded) files whose bytes could hold it but whose decoding needs gigabytes.
std::string png_claiming(uint32_t side, size_t padding) {
  const std::string ihdr = big_endian(side) + big_endian(side) + std::string{8, 6, 0, 0, 0};
  return "\x89PNG\r\n\x1a\n" + png_chunk("IHDR", ihdr) + (padding ? png_chunk("tEXt", "c" + std::string(1, '\0') + std::string(padding, 'a')) : "") +
         png_chunk("IDAT", std::string(16, '\0')) + png_chunk("IEND", "");
}

// A baseline JPEG header (SOI, a comment, SOF0) saying side x side, three components.
std::string jpeg_claiming(uint32_t side) {
  const std::string comment(177, 'x');
  std::string s = "\xFF\xD8\xFF\xFE" + std::string{char((comment.size() + 2) >> 8), char((comment.size() + 2) & 255)} + comment;
  s += std::string("\xFF\xC0\x00\x11\x08", 5) + std::string{char(side >> 8), char(side & 255), char(side >> 8), char(side & 255)};
  s += std::string("\x03\x01\x11\x00\x02\x11\x00\x03\x11\x00", 10) + "\xFF\xD9";
  return s;
}

void make_fifo(const std::string& path) { REQUIRE(::mkfifo(path.c_str(), 0600) == 0); }

// A capsule with its skeleton and layout, for the commands that read them.
struct Capsule {
  TempDir dir;
  std::string mesh = dir / "cap.obj", skeleton = dir / "sk.json", layout = dir / "layout.json";
  Capsule() {
    REQUIRE(run_sdm("primitive capsule -o " + mesh).exit_code == 0);
    REQUIRE(run_sdm("skeleton " + mesh + " -o " + skeleton).exit_code == 0);
    REQUIRE(run_sdm("stm " + mesh + " --skeleton " + skeleton + " --size 64 -o " + layout).exit_code == 0);
  }
};

}  // namespace

TEST_CASE("Named pipes, devices and folders named as any input are refused by name with exit 2 at once", "[hostile]") {
  TempDir dir;
  make_fifo(dir / "pipe");
  fs::create_directories(dir.path / "folder");
  const std::string zero = fs::relative("/dev/zero", dir.path).string(), urandom = fs::relative("/dev/urandom", dir.path).string();
  REQUIRE(zero.rfind("../", 0) == 0);
  struct Case {
    std::string name, file, content, message;
  };
  const std::vector<Case> meshes = {
      {"mtllib naming a named pipe", "m.obj", textured_tetra("pipe"), "named pipe"},
      {"mtllib naming /dev/zero by a relative path", "m.obj", textured_tetra(zero), "is a device"},
      {"mtllib naming a folder", "m.obj", textured_tetra("folder"), "is a folder"},
      {"map_Kd naming a named pipe", "t.obj", textured_tetra("t.mtl"), "named pipe"},
      {"map_Kd naming /dev/urandom by a relative path", "u.obj", textured_tetra("u.mtl"), "is a device"},
      {"a glTF buffer naming a named pipe", "b.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 96, "uri": "pipe"}]})",
       "named pipe"},
      {"a glTF buffer naming /dev/zero", "z.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 96, "uri": ")" + zero + R"("}]})",
       "is a device"},
      {"a glTF buffer naming a folder", "f.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 96, "uri": "folder"}]})",
       "is a folder"},
      {"a glTF image naming a named pipe", "i.gltf", R"({"asset": {"version": "2.0"}, "images": [{"uri": "pipe"}]})", "named pipe"},
  };
  write_file(dir / "t.mtl", "newmtl skin\nmap_Kd pipe\n");
  write_file(dir / "u.mtl", "newmtl skin\nmap_Kd " + urandom + "\n");
  for (const auto& c : meshes) {
    SECTION(c.name) {
      write_file(dir / c.file, c.content);
      expect_refused(run_sdm_guarded("info " + dir / c.file), c.message);
      expect_refused(run_sdm_guarded("convert " + dir / c.file + " -o " + dir / "out.obj"), c.message);
      CHECK_FALSE(fs::exists(dir / "out.obj"));
    }
  }
  SECTION("the mesh itself: a named pipe called x.obj or x.ply, a link to /dev/zero called z.obj") {
    make_fifo(dir / "x.obj");
    make_fifo(dir / "x.ply");
    fs::create_symlink("/dev/zero", dir.path / "z.obj");
    expect_refused(run_sdm_guarded("info " + dir / "x.obj"), "named pipe");
    expect_refused(run_sdm_guarded("render " + dir / "x.obj -o " + dir / "out.png"), "named pipe");
    expect_refused(run_sdm_guarded("info " + dir / "x.ply"), "named pipe");
    expect_refused(run_sdm_guarded("info " + dir / "z.obj"), "is a device");
    expect_refused(run_sdm_guarded("skeleton " + dir / "z.obj -o " + dir / "sk.json"), "is a device");
  }
}

TEST_CASE("A named pipe or a device given to --skeleton, --layout, --texture, --stm or as an SDM is refused with exit 2", "[hostile]") {
  Capsule cap;
  const std::string pipe = cap.dir / "pipe", out = cap.dir / "out";
  make_fifo(pipe);
  expect_refused(run_sdm_guarded("stm " + cap.mesh + " --skeleton /dev/zero -o " + out + ".json", memory_cap()), "is a device");
  expect_refused(run_sdm_guarded("encode " + cap.mesh + " --skeleton " + pipe + " -o " + out + ".exr"), "named pipe");
  expect_refused(run_sdm_guarded("encode " + cap.mesh + " --layout /dev/zero -o " + out + ".exr", memory_cap()), "is a device");
  expect_refused(run_sdm_guarded("render " + cap.mesh + " --layout " + pipe + " --checker -o " + out + ".png"), "named pipe");
  expect_refused(run_sdm_guarded("render " + cap.mesh + " --layout " + cap.layout + " --stm /dev/zero -o " + out + ".png"), "is a device");
  expect_refused(run_sdm_guarded("render " + cap.mesh + " --layout " + cap.layout + " --stm " + pipe + " -o " + out + ".png"), "named pipe");
  // A textured mesh with its texture given as a named pipe or /dev/urandom.
  write_file(cap.dir / "tex.obj", textured_tetra("none.mtl"));
  expect_refused(run_sdm_guarded("render " + cap.dir / "tex.obj" + " --texture " + pipe + " -o " + out + ".png"), "named pipe");
  expect_refused(run_sdm_guarded("render " + cap.dir / "tex.obj" + " --texture /dev/urandom -o " + out + ".png"), "is a device");
  // An SDM: OpenEXR opened it before any check.
  fs::rename(pipe, cap.dir / "pipe.exr");
  expect_refused(run_sdm_guarded("decode " + cap.dir / "pipe.exr" + " -o " + out + ".obj"), "named pipe");
  for (const char* ext : {".json", ".exr", ".png", ".obj"}) CHECK_FALSE(fs::exists(out + ext));
}

TEST_CASE("Images whose header claims more than the bytes or the memory budget hold are refused before decoding", "[hostile]") {
  TempDir dir;
  // 16384^2 RGBA in 60 bytes, 16000^2 in a 204-byte JPEG: more pixels than such files can encode.
  write_file(dir / "tiny.png", png_claiming(16384, 0));
  write_file(dir / "tiny.jpg", jpeg_claiming(16000));
  REQUIRE(fs::file_size(dir / "tiny.jpg") == 204);
  // 16384^2 in 40 KB of PNG: deflate could hold it, but decoding takes about 3.3 GB.
  write_file(dir / "big.png", png_claiming(16384, 40000));
  write_file(dir / "tex.obj", textured_tetra("tex.mtl"));
  const std::string out = dir / "out.png";
  for (const std::string image : {"tiny.png", "tiny.jpg"}) {
    SECTION("--texture " + image) {
      expect_refused(run_sdm_guarded("render " + dir / "tex.obj" + " --texture " + dir / image + " -o " + out, memory_cap()), "header claims");
    }
  }
  SECTION("--texture of 16384^2 beyond --max-memory 512M, for render and remap") {
    const auto r = run_sdm_guarded("render " + dir / "tex.obj" + " --texture " + dir / "big.png" + " --max-memory 512M -o " + out, memory_cap());
    expect_refused(r, "16384 x 16384 pixels) needs about");
    expect_refused(r, "--max-memory");
    expect_refused(run_sdm_guarded("remap " + dir / "tex.obj" + " --texture " + dir / "big.png" + " --max-memory 512M -o " + out, memory_cap()),
                   "needs about");
  }
  SECTION("the texture an OBJ's material names") {
    write_file(dir / "tex.mtl", "newmtl skin\nmap_Kd big.png\n");
    expect_refused(run_sdm_guarded("render " + dir / "tex.obj" + " --max-memory 512M -o " + out, memory_cap()), "needs about");
    write_file(dir / "tex.mtl", "newmtl skin\nmap_Kd tiny.jpg\n");
    expect_refused(run_sdm_guarded("render " + dir / "tex.obj" + " -o " + out, memory_cap()), "header claims");
  }
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("read_png refuses a header claiming more than kMaxImageSide a side or than its bytes hold, before allocating", "[hostile]") {
  TempDir dir;
  // 2^20 a side is 64 times kMaxImageSide: 4 TB of RGBA had it been allocated (std::bad_alloc, not
  // InputError); 16384^2 in 60 bytes is within the side limit but beyond what deflate can encode.
  REQUIRE((uint32_t(1) << 20) > uint32_t(sdm::kMaxImageSide));
  write_file(dir / "wide.png", png_claiming(uint32_t(1) << 20, 0));
  write_file(dir / "tiny.png", png_claiming(16384, 0));
  for (const std::string name : {"wide.png", "tiny.png"}) {
    INFO(name);
    try {
      sdm::read_png(dir / name);
      FAIL("read_png took " + name);
    } catch (const sdm::InputError& e) {
      const std::string what = e.what();
      CHECK(what.find("header claims") != std::string::npos);
      CHECK(what.find(name) != std::string::npos);
    }
  }
}

TEST_CASE("An --stm beyond the memory budget and a layout beyond the JSON size limit are refused before reading", "[hostile]") {
  Capsule cap;
  const std::string out = cap.dir / "out.png";
  write_file(cap.dir / "big.png", png_claiming(16384, 40000));
  expect_refused(run_sdm_guarded("render " + cap.mesh + " --layout " + cap.layout + " --stm " + cap.dir / "big.png" + " --max-memory 512M -o " + out,
                                 memory_cap()),
                 "needs about");
  // A sparse file of 600 MB takes no disk; its size alone refuses it.
  std::ofstream(cap.dir / "huge.json").put('{');
  fs::resize_file(cap.dir / "huge.json", std::uintmax_t(600) << 20);
  expect_refused(run_sdm_guarded("render " + cap.mesh + " --layout " + cap.dir / "huge.json" + " --checker -o " + out, memory_cap()),
                 "this reader takes");
  expect_refused(run_sdm_guarded("stm " + cap.mesh + " --skeleton " + cap.dir / "huge.json" + " -o " + cap.dir / "o.json", memory_cap()),
                 "this reader takes");
  // 100 MB of JSON is within the reader's limit but parses into about 32x its text: --max-memory
  // 512M refuses it before the first byte is read, for every command that reads a layout or skeleton.
  std::ofstream(cap.dir / "big.json").put('{');
  fs::resize_file(cap.dir / "big.json", std::uintmax_t(100) << 20);
  const std::string big = cap.dir / "big.json", budget = " --max-memory 512M";
  for (const std::string& command : {"render " + cap.mesh + " --layout " + big + " --checker -o " + out + budget,
                                     "render " + cap.mesh + " --skeleton " + big + " -o " + out + budget,
                                     "stm " + cap.mesh + " --skeleton " + big + " -o " + cap.dir / "o.json" + budget,
                                     "encode " + cap.mesh + " --layout " + big + " -o " + cap.dir / "o.exr" + budget,
                                     "remap " + cap.mesh + " --layout " + big + " -o " + out + budget,
                                     "encode " + cap.mesh + " --skeleton " + big + " -o " + cap.dir / "o.exr" + budget}) {
    INFO(command);
    expect_refused(run_sdm_guarded(command, memory_cap()), "needs about");
  }
  CHECK_FALSE(fs::exists(out));
  CHECK_FALSE(fs::exists(cap.dir / "o.json"));
  CHECK_FALSE(fs::exists(cap.dir / "o.exr"));
}

TEST_CASE("A byte-order mark is read past in memory: no temporary copy, every face kept, the material found", "[hostile]") {
  TempDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  write_file(dir / "tex.mtl", "newmtl skin\nmap_Kd tex.png\n");
  write_file(dir / "bom.obj", bom + textured_tetra("tex.mtl"));
  write_file(dir / "bom.off", bom + "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  // The temporary folder unusable: the copy it used to make was cut short there (faces lost, exit 0).
  const std::string no_tmp = "TMPDIR=" + dir / "missing" + " ";
  for (const std::string file : {"bom.obj", "bom.off"}) {
    SECTION(file) {
      const auto r = test_util::run_program(no_tmp + SDM_BINARY, "convert " + dir / file + " -o " + dir / "out.off");
      INFO(r.output);
      REQUIRE(r.exit_code == 0);
      const auto info = run_sdm("info --json " + dir / "out.off");
      CHECK(json_of(info)["faces"] == 4);
      const auto in = run_sdm("info --json " + dir / file);
      CHECK(json_of(in)["faces"] == 4);
      if (file == "bom.obj") CHECK(json_of(in)["texture"] == (dir.path / "tex.png").string());
    }
  }
  CHECK_FALSE(fs::exists(dir / "missing"));
}

TEST_CASE("File names that are not UTF-8 are printed in --json, and the outputs stay", "[hostile]") {
  TempDir dir;
  const std::string name = dir / "caf\xe9.obj";  // Latin-1
  REQUIRE(run_sdm("primitive capsule -o '" + name + "'").exit_code == 0);
  const auto info = run_sdm("info --json '" + name + "'");
  INFO(info.output);
  CHECK(info.exit_code == 0);
  CHECK(json_of(info)["file"].get<std::string>().find("caf\xEF\xBF\xBD.obj") != std::string::npos);  // U+FFFD for the byte
  const std::string layout = dir / "lay\xe9.json";
  const auto stm = run_sdm("stm '" + name + "' --size 64 --json -o '" + layout + "'");
  INFO(stm.output);
  CHECK(stm.exit_code == 0);
  CHECK(stm.output.find("json.exception") == std::string::npos);
  CHECK(fs::exists(layout));
}

TEST_CASE("ASCII PLY with 16- and 32-bit list types is read as the binary reader reads it", "[hostile]") {
  TempDir dir;
  const std::string points = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  for (const std::string count : {"uint", "uint32", "ushort", "short", "uchar"})
    for (const std::string index : {"uint", "uint32", "ushort", "short", "int"}) {
      const std::string file = dir / ("t_" + count + "_" + index + ".ply");
      write_file(file, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
                       "property list " + count + " " + index + " vertex_indices\nend_header\n" + points + faces);
      const auto r = run_sdm("info --json " + file);
      INFO(file << "\n" << r.output);
      CHECK(r.exit_code == 0);
      if (r.exit_code == 0) {
        CHECK(json_of(r)["faces"] == 4);
        CHECK(json_of(r)["vertices"] == 4);
      }
    }
  // Invented: vertex colours as uchar and a double coordinate, with a ushort list.
  write_file(dir / "c.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty float y\nproperty float z\n"
                            "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 4\n"
                            "property list ushort ushort vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 255 0 0\n0 1 0 255 0 0\n"
                            "0 0 1 255 0 0\n" + faces);
  const auto r = run_sdm("info --json " + dir / "c.ply");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // A corner out of range in the ASCII body is still refused by name.
  write_file(dir / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
                              "property list uint uint vertex_indices\nend_header\n" + points + "3 0 2 9\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  CHECK(run_sdm("info " + dir / "bad.ply").exit_code == 2);
}

TEST_CASE("An OBJ face with a trailing comment is read", "[hostile]") {
  TempDir dir;
  // Plain (the fast reader) and with texture coordinates and a material (the checked reader).
  write_file(dir / "plain.obj", kTetraPoints + "f 1 3 2 # bottom\nf 1 2 4\t# side\nf 1 4 3 #\nf 2 3 4 # top\n");
  write_file(dir / "uv.obj", "mtllib none.mtl\n" + kTetraPoints + "vt 0 0\nvt 1 0\nvt 0 1\n"
                             "f 1/1 3/3 2/2 # bottom\nf 1/1 2/2 4/3 # side\nf 1/1 4/3 3/2\nf 2/2 3/3 4/1 #top\n");
  for (const std::string file : {"plain.obj", "uv.obj"}) {
    const auto r = run_sdm("info --json " + dir / file);
    INFO(file << "\n" << r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(json_of(r)["faces"] == 4);
  }
}

TEST_CASE("map_Kd with options or a Windows path names its texture", "[hostile]") {
  CHECK(sdm::map_file_name("-s 1 1 1 -o 0 0 0 tex.png") == "tex.png");
  CHECK(sdm::map_file_name("-bm 1 tex.png") == "tex.png");
  CHECK(sdm::map_file_name("-clamp on tex.png") == "tex.png");
  CHECK(sdm::map_file_name("-blendu on -blendv off tex.png") == "tex.png");
  CHECK(sdm::map_file_name("textures\\spot.png") == "textures/spot.png");
  CHECK(sdm::map_file_name("-o 0.5 my texture.png") == "my texture.png");  // -o with one value; a name with a blank
  CHECK(sdm::map_file_name("-mm 0 1 -s 2 2 tex.png") == "tex.png");
  CHECK(sdm::map_file_name("") == "");
  TempDir dir;
  write_file(dir / "tex.obj", textured_tetra("tex.mtl"));
  const std::vector<std::pair<std::string, std::string>> lines = {{"-s 1 1 1 -o 0 0 0 tex.png", "tex.png"},
                                                                  {"-bm 1 tex.png", "tex.png"},
                                                                  {"-clamp on tex.png", "tex.png"},
                                                                  {"-blendu on tex.png", "tex.png"},
                                                                  {"textures\\spot.png", "textures/spot.png"}};
  for (const auto& [line, file] : lines) {
    write_file(dir / "tex.mtl", "newmtl other\nmap_Kd unused.png\nnewmtl skin\nKd 1 1 1\nmap_Kd " + line + "\r\n");
    const auto r = run_sdm("info --json " + dir / "tex.obj");
    INFO(line << "\n" << r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(json_of(r)["texture"] == (dir.path / file).string());
  }
}
