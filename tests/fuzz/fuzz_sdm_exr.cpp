// libFuzzer target: a whole SDM file (OpenEXR's parser, the header's layout and base mesh, the
// pixels), then a decode at level 1.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sdm::fuzz::run_one(data, size, ".exr", [](const std::string& path) {
    sdm::DecodeOptions options;
    options.level = 1;
    sdm::decode_sdm(sdm::read_sdm_exr(path), options);
  });
}
