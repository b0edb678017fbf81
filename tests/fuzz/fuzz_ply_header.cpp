// libFuzzer target: the PLY header and body paths in memory, without a file: the fast reader
// (read_binary_ply.h, binary and ASCII) and, where it declines, the checks that come before
// OpenMesh's reader (check_mesh_file.h), which parse the header strictly.
#include "libstm/mesh/check_mesh_file.h"
#include "libstm/mesh/read_binary_ply.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    sdm::BinaryPly ply;
    if (!sdm::read_binary_ply(bytes, ply)) sdm::check_mesh_file("fuzz.ply", bytes, ".ply");
  } catch (const sdm::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sdm fuzz: the PLY threw %s\n", e.what());
    std::abort();
  }
  return 0;
}
