// libFuzzer target: one mesh reader (SDM_FUZZ_EXTENSION: ".obj", ".off", ".ply", ".stl", ".glb" or ".gltf"), then
// the validation and the halfedge mesh every command builds from what it read.
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sdm::fuzz::run_one(data, size, SDM_FUZZ_EXTENSION, [](const std::string& path) { sdm::load_mesh(path); });
}
