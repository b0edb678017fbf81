#pragma once
/// Every file the program reads is opened here (DECISIONS 1, "Files that are not files"): only a regular file, after following
/// symbolic links, and never with a blocking open, so that a named pipe (FIFO), a device such as
/// /dev/zero or /dev/urandom, a socket or a folder named as an input, a material, a texture or a
/// glTF buffer is refused by name at once instead of hanging or growing without end; and never
/// more bytes than the reader's limit, checked before the first byte is read.
#include <cstdint>
#include <functional>
#include <string>

namespace sdm {

/// \throw InputError "cannot read <what> <path>: <reason>" unless `path` names a regular file
/// (symbolic links followed): no such file, a folder, a named pipe, a device, a socket.
void check_input_file(const std::string& path, const std::string& what);

/// The whole file, read through check_input_file's test (made again on the opened file, which is
/// opened without blocking).
/// \throw InputError naming the file when it cannot be read or holds more
/// than `max_bytes`, before reading it; `what` says what the file is ("mesh", "texture", "layout").
std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes);

/// Asked, before a file is read, for the bytes reading it will hold (e.g. a command's
/// --max-memory); refuses by throwing.
using ReadBudget = std::function<void(double bytes)>;

/// read_input_file, asking `budget` (when given) first for `bytes_per_file_byte` times the file's
/// size: what the text and what is built from it (a JSON tree, say) hold together.
/// \throw InputError as read_input_file; whatever `budget` throws.
std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes, const ReadBudget& budget,
                            double bytes_per_file_byte);

/// A byte count for a message: "783 KB", "1.5 GB".
std::string byte_count(double bytes);

}  // namespace sdm
