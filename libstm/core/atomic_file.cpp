#include "libstm/core/atomic_file.h"

#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <unistd.h>

namespace fs = std::filesystem;

namespace sdm {
namespace {

// The temporary files being written, for the signal handler: fixed slots of plain characters so
// that the handler reads them without allocating (only async-signal-safe calls in a handler).
constexpr int kSlots = 16;
constexpr size_t kPathMax = 4096;
struct TemporarySlot {
  volatile std::sig_atomic_t used = 0;
  char path[kPathMax] = {};
};
std::array<TemporarySlot, kSlots> g_temporaries;
std::mutex g_temporaries_mutex;

int register_temporary(const std::string& path) {
  if (path.size() >= kPathMax) return -1;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  for (int i = 0; i < kSlots; ++i)
    if (!g_temporaries[i].used) {
      std::memcpy(g_temporaries[i].path, path.c_str(), path.size() + 1);
      g_temporaries[i].used = 1;
      return i;
    }
  return -1;  // more nested writes than slots: that one is not removed on a signal
}

void unregister_temporary(int slot) {
  if (slot < 0) return;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  g_temporaries[slot].used = 0;
}

extern "C" void remove_temporaries_and_die(int sig) {
  for (auto& t : g_temporaries)
    if (t.used) unlink(t.path);
  std::signal(sig, SIG_DFL);
  raise(sig);
}

}  // namespace

void remove_temporaries_on_signal() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, remove_temporaries_and_die);
}

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path() && !fs::exists(target.parent_path()))
    throw InputError("cannot write " + path + ": folder " + target.parent_path().string() +
                     " does not exist");
  if (fs::is_directory(target, ec)) throw InputError("cannot write " + path + ": it is a folder");
  if (fs::exists(target, ec) && !fs::is_regular_file(target, ec))
    throw InputError("cannot write " + path + ": it exists and is not a regular file (a device, pipe or socket); "
                     "name a file to write");
  fs::path tmp = target;
  tmp.replace_filename("." + target.stem().string() + ".tmp" + std::to_string(getpid()) +
                       target.extension().string());
  const int slot = register_temporary(tmp.string());
  try {
    write(tmp.string());
    fs::rename(tmp, target);
  } catch (...) {
    fs::remove(tmp, ec);
    unregister_temporary(slot);
    throw;
  }
  unregister_temporary(slot);
}

void write_bytes_checked(const std::string& path, const void* data, size_t size, const std::string& name) {
  const std::string shown = name.empty() ? path : name;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + shown + ": " + std::strerror(errno));
  const size_t written = size ? std::fwrite(data, 1, size, f) : 0;
  const int write_errno = errno;
  const bool flushed = std::fflush(f) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (written != size || !flushed || !closed)
    throw std::runtime_error("cannot write " + shown + ": " +
                             std::strerror(written != size ? write_errno : (!flushed ? flush_errno : errno)) +
                             " (the disk may be full)");
}

void write_text_file(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& tmp) { write_bytes_checked(tmp, text.data(), text.size(), path); });
}

std::string read_text_file(const std::string& path) {
  return read_input_file(path, "file", kMaxMeshFileBytes);
}

}  // namespace sdm
