// libFuzzer target: the layout JSON reader, then the STM coordinates of a capsule in it.
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/primitives.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const sdm::Mesh capsule = sdm::make_primitive("capsule", 300);
  return sdm::fuzz::run_one(data, size, ".json",
                            [](const std::string& path) { sdm::stm_coordinates(capsule, sdm::read_layout_json(path)); });
}
