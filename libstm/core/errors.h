#pragma once
// Error types shared by the libraries. Libraries never print or exit: they throw, and the
// command line turns InputError into exit code 2 (bad input) and anything else into 1.
#include <stdexcept>
#include <string>

namespace sdm {

// The user's input cannot go through the pipeline; the message says what, where and how to fix it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sdm
