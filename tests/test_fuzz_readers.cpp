// Bounded mutation fuzzing of every reader: small valid seeds (a tetrahedron in each
// mesh format, a capsule's skeleton, layout and SDM header) are mutated (tokens replaced by hostile
// values, lines dropped or repeated, files cut short, bytes flipped, JSON leaves replaced or
// removed) and fed to the readers and the stage that consumes them, in-process. A reader may
// accept its input or throw InputError; any other exception fails the test, and a crash or a
// sanitizer report fails the run (the sanitizer build runs these too). The seed of the random
// generator is fixed, so a failure repeats; SDM_FUZZ_ITERATIONS sets the iterations per reader
// (default 200) for a longer run.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/core/errors.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/obj_material.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <sys/resource.h>

using namespace sdm;

namespace {

// A reader that trusts a mutated count fails with bad_alloc under this cap (2 GB of address
// space, this test process only: ctest runs each case alone) instead of exhausting the machine.
// The sanitizer build reserves its shadow memory up front, so it runs without the cap.
// The cap holds while the object lives (the tests after it in the same process get theirs back).
struct MemoryCap {
  rlimit before{};
  MemoryCap() {
    getrlimit(RLIMIT_AS, &before);
#if !defined(__SANITIZE_ADDRESS__)
    const rlimit cap{std::min<rlim_t>(rlim_t(2) << 30, before.rlim_max), before.rlim_max};
    setrlimit(RLIMIT_AS, &cap);
#endif
  }
  ~MemoryCap() { setrlimit(RLIMIT_AS, &before); }
};

int iterations() {
  const char* n = std::getenv("SDM_FUZZ_ITERATIONS");
  return n ? std::max(1, std::atoi(n)) : 200;
}

const std::vector<std::string> kHostileTokens = {"-1", "0", "2147483647", "-2147483648", "4294967296", "2000000000", "nan", "inf",
                                                 "-inf", "1e39", "1e308", "-1e308", "1e-320", "/", "//", "/1", "1//", "x", "", "3.5", "3e12"};

// One text mutation: replace a token, drop or repeat a line, cut the text, or flip a byte.
std::string mutate_text(const std::string& seed, std::mt19937& rng) {
  std::string s = seed;
  const int kinds = 1 + int(rng() % 3);
  for (int k = 0; k < kinds && !s.empty(); ++k) {
    const size_t at = rng() % s.size();
    switch (rng() % 5) {
      case 0: {  // a token (between whitespace) replaced
        size_t b = s.find_last_of(" \n", at), e = s.find_first_of(" \n", at);
        b = b == std::string::npos ? 0 : b + 1;
        if (e == std::string::npos) e = s.size();
        if (b <= e) s.replace(b, e - b, kHostileTokens[rng() % kHostileTokens.size()]);
        break;
      }
      case 1: {  // a line dropped
        const size_t b = s.rfind('\n', at), e = s.find('\n', at);
        if (b != std::string::npos && e != std::string::npos) s.erase(b, e - b);
        break;
      }
      case 2: {  // a line repeated
        const size_t b = s.rfind('\n', at), e = s.find('\n', at);
        if (b != std::string::npos && e != std::string::npos) s.insert(e, s.substr(b, e - b));
        break;
      }
      case 3: s.resize(at); break;  // cut short
      default: s[at] = char(rng() % 256);
    }
  }
  return s;
}

// One JSON mutation: a random leaf replaced by a hostile value, or a random element removed.
void mutate_json(nlohmann::json& j, std::mt19937& rng) {
  nlohmann::json* node = &j;
  while ((node->is_object() || node->is_array()) && !node->empty() && rng() % 8 != 0) {
    const size_t i = rng() % node->size();
    auto it = node->begin();
    std::advance(it, long(i));
    if ((it->is_primitive() || it->empty()) && rng() % 3 == 0) {
      if (node->is_array()) node->erase(i);
      else node->erase(it.key());
      return;
    }
    node = &*it;
  }
  static const std::vector<nlohmann::json> values = {0, -1, 1, 2147483647, -2147483648LL, 4294967296LL, 1e308, -1e308, 1e-300, 0.5, 3e12, "x",
                                                      nullptr, nlohmann::json::array(), nlohmann::json::object()};
  *node = values[rng() % values.size()];
}

// Runs `f`; InputError is an accepted answer, anything else fails with the input saved.
template <class F>
void expect_no_failure(const std::string& what, int i, F&& f) {
  try {
    f();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    FAIL(what << " mutation " << i << " threw " << typeid(e).name() << ": " << e.what());
  }
}

}  // namespace

TEST_CASE("Mutated mesh files are accepted or refused with InputError, never anything else", "[hostile][fuzz]") {
  test_util::TempDir dir;
  const std::string pts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"off", "OFF\n4 4 0\n" + pts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/2 3/3 4/1\n"},
      {"ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
              "property list uchar int vertex_indices\nend_header\n" + pts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
              "property list uint ushort vertex_indices\nend_header\n" + pts + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
      {"stl", "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
              "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
              "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
              "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n"},
      // The tetrahedron as glTF with its buffer embedded (base64: 4 float VEC3 positions, 12 uint indices).
      {"gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 96, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAIAAAABAAAAAAAAAAEAAAADAAAAAAAAAAMAAAACAAAAAQAAAAIAAAADAAAA"}], "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48}], "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 4, "min": [0, 0, 0], "max": [1, 1, 1]}, {"bufferView": 1, "componentType": 5125, "type": "SCALAR", "count": 12}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})"},
  };
  const MemoryCap cap;
  std::mt19937 rng(15);
  for (const auto& [ext, seed] : seeds) {
    const std::string path = dir / ("m." + ext);
    for (int i = 0; i < iterations(); ++i) {
      test_util::write_file(path, mutate_text(seed, rng));
      expect_no_failure(ext, i, [&] { load_mesh(path); });
    }
  }
}

TEST_CASE("Mutated material libraries are accepted or refused with InputError", "[hostile][fuzz]") {
  test_util::TempDir dir;
  const std::string seed = "newmtl a\nKd 1 1 1\nmap_Kd -s 1 1 1 -o 0 0 0 -bm 1 -clamp on a.png\nnewmtl b\nmap_Kd textures\\b.png\n";
  const std::string obj = "mtllib m.mtl\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\nf 1 3 2\n";
  const MemoryCap cap;
  std::mt19937 rng(16);
  for (int i = 0; i < iterations(); ++i) {
    test_util::write_file(dir / "m.mtl", mutate_text(seed, rng));
    expect_no_failure("mtl", i, [&] { obj_texture(obj, dir / "m.obj"); });
  }
}

TEST_CASE("Mutated skeleton, layout and SDM headers are accepted or refused with InputError", "[hostile][fuzz]") {
  const MemoryCap cap;
  const Mesh mesh = make_primitive("capsule", 300);
  const Skeleton skeleton = extract_skeleton(mesh);
  LayoutOptions lo;
  lo.size = 64;
  const Layout layout = compute_layout(mesh, skeleton, lo);
  const SdmImage sdm = encode_sdm(mesh, layout);
  std::mt19937 rng(15);
  const int n = iterations();
  for (int i = 0; i < n / 4; ++i) {  // each one computes a layout: fewer
    nlohmann::json j = skeleton_to_json(skeleton);
    mutate_json(j, rng);
    expect_no_failure("skeleton", i, [&] { compute_layout(mesh, skeleton_from_json(j), lo); });
  }
  for (int i = 0; i < n; ++i) {
    nlohmann::json j = layout_to_json(layout);
    mutate_json(j, rng);
    expect_no_failure("layout", i, [&] { stm_coordinates(mesh, layout_from_json(j)); });
  }
  for (int i = 0; i < n; ++i) {
    SdmImage im = sdm;
    mutate_json(im.layout, rng);
    DecodeOptions d;
    d.level = 1;
    expect_no_failure("SDM header", i, [&] { decode_sdm(im, d); });
  }
}

// Inputs the libFuzzer runs found (tests/fuzz/regressions; `make fuzz`): each reader refuses its
// own with InputError, within the memory cap. SDMs whose header OpenEXR reads differently from
// its size fields (an attribute name past 32 bytes, a box2i said to be 13 bytes: OpenEXR then
// allocated 1.6-1.9 GB) or whose window makes OpenEXR size its buffers at 2 GB; a skeleton and a
// layout with 3e12 where an index belongs (a float-to-int cast, undefined); glTF files whose image
// buffer view runs past the buffer (tinygltf handed stb the unchecked length: a heap over-read) or
// whose image claims a gigabyte of pixels, or whose indices are floats (a cast to size_t, undefined).
TEST_CASE("Fuzzer findings are refused with InputError", "[hostile][fuzz]") {
  const MemoryCap cap;
  const std::filesystem::path dir = std::filesystem::path(SDM_TEST_DATA) / ".." / "fuzz" / "regressions";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string path = entry.path().string(), ext = entry.path().extension().string();
    INFO(path);
    bool refused = false;
    try {
      if (ext == ".exr") read_sdm_exr(path);
      else if (path.find("skeleton_json") != std::string::npos) read_skeleton_json(path);
      else if (path.find("layout_json") != std::string::npos) read_layout_json(path);
      else read_mesh_soup(path);
    } catch (const InputError& e) {
      refused = true;
    }
    CHECK(refused);
    ++files;
  }
  CHECK(files >= 8);
}
