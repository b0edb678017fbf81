#pragma once
/// Error types shared by the libraries. Libraries never print or exit: they throw, and the
/// command line turns InputError into exit code 2 (bad input) and anything else into 1.
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sdm {

/// The user's input cannot go through the pipeline; the message says what, where and how to fix it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A number for a message, in at most 6 significant digits ("1e+308", "0.25", "nan"), where
/// std::to_string would print 309 digits or round a small value to 0.000000.
inline std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace sdm
