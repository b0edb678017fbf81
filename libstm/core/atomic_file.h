#pragma once
// Outputs are written under a temporary name beside the target and renamed on success, so that
// a failed or interrupted run never leaves a half-written file behind.
#include <functional>
#include <string>

namespace sdm {

// Calls write(tmp_path), then renames tmp_path to path. If write throws, the temporary file is
// removed and the exception propagates. The temporary keeps the target's extension, for
// writers that choose the format by extension.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Writes a whole text file atomically.
void write_text_file(const std::string& path, const std::string& text);

// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string read_text_file(const std::string& path);

}  // namespace sdm
