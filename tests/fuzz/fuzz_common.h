#pragma once
// Shared by the libFuzzer targets (`make fuzz`): each target writes the fuzzer's bytes
// to a file, as a user's input arrives, and runs the reader and the stage that consumes its result.
// InputError is a correct answer to any input; any other exception aborts, so libFuzzer reports
// it with the input that caused it, as it does a crash, a sanitizer report, a leak, a timeout or an
// allocation beyond -malloc_limit_mb.
#include "libstm/core/errors.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <unistd.h>

namespace sdm::fuzz {

// A file of this process under /dev/shm (or /tmp), named with `extension`, holding the bytes.
inline std::string write_input(const uint8_t* data, size_t size, const std::string& extension) {
  static const std::string dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path = dir + "/sdm-fuzz-" + std::to_string(getpid()) + extension;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

template <class F>
int run_one(const uint8_t* data, size_t size, const std::string& extension, F&& consume) {
  const std::string path = write_input(data, size, extension);
  try {
    consume(path);
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sdm fuzz: %s threw %s\n", path.c_str(), e.what());
    std::abort();
  }
  std::remove(path.c_str());
  return 0;
}

}  // namespace sdm::fuzz
