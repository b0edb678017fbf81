// libFuzzer target: an OBJ's material library (obj_material.h): the fuzzer's bytes are the MTL
// that a small OBJ names with mtllib and usemtl, read for the texture of its most used material.
#include "libstm/mesh/obj_material.h"
#include "tests/fuzz/fuzz_common.h"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sdm::fuzz::run_one(data, size, ".mtl", [](const std::string& path) {
    const std::string name = std::filesystem::path(path).filename().string();
    sdm::obj_texture("mtllib " + name + "\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\nf 1 3 2\n", path);
  });
}
