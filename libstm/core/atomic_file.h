#pragma once
/// Outputs are written under a temporary name beside the target and renamed on success, so that
/// a failed or interrupted run never leaves a half-written file behind.
#include <cstddef>
#include <functional>
#include <string>

namespace sdm {

/// Calls write(tmp_path), then renames tmp_path to path. If write throws, the temporary file is
/// removed and the exception propagates. The temporary keeps the target's extension, for
/// writers that choose the format by extension.
/// \throw InputError when the target exists and is
/// not a regular file (a folder, a device such as /dev/null, a pipe), or its folder is missing.
void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes a whole text file atomically.
void write_text_file(const std::string& path, const std::string& text);

/// Writes `size` bytes to `path` (truncating it) and checks every step, the close included, so a
/// full disk or a file size limit is an error (std::runtime_error naming the path and the reason)
/// rather than a silently truncated file. Messages name `name` (the final path of an atomic write),
/// or `path` when it is empty.
void write_bytes_checked(const std::string& path, const void* data, size_t size, const std::string& name = "");

/// Installs SIGINT, SIGTERM, SIGHUP and SIGPIPE handlers that remove the registered temporary files
/// (those write_atomically has open, an OutputCommit's, ScratchFiles), then die of the signal as
/// before (the exit status still says which signal), and removes them at exit() too. A signal the
/// program was started with ignored (nohup, a batch's workers) stays ignored. Called once by the
/// program, not by the libraries. SIGKILL cannot be caught: its temporaries stay.
void remove_temporaries_on_signal();

/// The outputs of one run, all of them or none (DESIGN 3.3, "Writing"): while an OutputCommit is open, every
/// write_atomically leaves its file under its temporary name (registered, so a signal removes it)
/// and commit() renames them all, with the signals of remove_temporaries_on_signal held back until
/// the last rename is done. Destroyed uncommitted (an exception, a failed command), it removes the
/// temporaries: the targets stay as they were. One at a time (std::logic_error otherwise).
class OutputCommit {
 public:
  OutputCommit();
  ~OutputCommit();
  OutputCommit(const OutputCommit&) = delete;
  OutputCommit& operator=(const OutputCommit&) = delete;
  /// Renames every temporary to its target, in the order written. A rename that fails removes the
  /// targets already renamed and the other temporaries and throws std::runtime_error naming it.
  void commit();

 private:
  bool done_ = false;
};

/// A file of the program's own, not an output (a map written only to be read back): registered
/// so that a signal or exit() removes it, removed by the destructor, and written at once by
/// write_atomically even while an OutputCommit is open.
class ScratchFile {
 public:
  explicit ScratchFile(std::string path);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int slot_ = -1;
};

/// Reads a whole regular file (read_input_file, within kMaxMeshFileBytes); throws InputError naming
/// the path when it cannot be read.
std::string read_text_file(const std::string& path);

}  // namespace sdm
