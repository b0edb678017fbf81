// libFuzzer target: the skeleton JSON reader, then a layout of a capsule computed around it.
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/skeleton.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const sdm::Mesh capsule = sdm::make_primitive("capsule", 300);
  return sdm::fuzz::run_one(data, size, ".json", [](const std::string& path) {
    sdm::LayoutOptions options;
    options.size = 64;
    sdm::compute_layout(capsule, sdm::read_skeleton_json(path), options);
  });
}
