#pragma once
// Outputs are written under a temporary name beside the target and renamed on success, so that
// a failed or interrupted run never leaves a half-written file behind.
#include <cstddef>
#include <functional>
#include <string>

namespace sdm {

// Calls write(tmp_path), then renames tmp_path to path. If write throws, the temporary file is
// removed and the exception propagates. The temporary keeps the target's extension, for
// writers that choose the format by extension. Throws InputError when the target exists and is
// not a regular file (a folder, a device such as /dev/null, a pipe), or its folder is missing.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

// Writes a whole text file atomically.
void write_text_file(const std::string& path, const std::string& text);

// Writes `size` bytes to `path` (truncating it) and checks every step, the close included, so a
// full disk or a file size limit is an error (std::runtime_error naming the path and the reason)
// rather than a silently truncated file. Messages name `name` (the final path of an atomic write),
// or `path` when it is empty.
void write_bytes_checked(const std::string& path, const void* data, size_t size, const std::string& name = "");

// Installs SIGINT, SIGTERM and SIGHUP handlers that remove the temporary files write_atomically
// has open, then die of the signal as before (the exit status still says which signal). Called
// once by the program, not by the libraries. SIGKILL cannot be caught: its temporary stays.
void remove_temporaries_on_signal();

// Reads a whole regular file (read_input_file, within kMaxMeshFileBytes); throws InputError naming
// the path when it cannot be read.
std::string read_text_file(const std::string& path);

}  // namespace sdm
