#pragma once
/// How a long stage reports what it is doing: one line at a time, to a callback the caller chooses
/// (the command line prints them on stderr; tests and library users may pass nothing).
#include <functional>
#include <string>

namespace sdm {

/// Receives one progress line (no trailing newline). May be empty: report_progress then does nothing.
using Progress = std::function<void(const std::string&)>;

/// Calls `progress` with `line` when a callback was given.
inline void report_progress(const Progress& progress, const std::string& line) {
  if (progress) progress(line);
}

}  // namespace sdm
