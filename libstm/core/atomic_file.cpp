#include "libstm/core/atomic_file.h"

#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>
#include <unistd.h>

namespace fs = std::filesystem;

namespace sdm {
namespace {

// The temporary files of the process, for the signal handler: fixed slots of plain characters so
// that the handler reads them without allocating (only async-signal-safe calls in a handler).
constexpr int kSlots = 64;
constexpr size_t kPathMax = 4096;
struct TemporarySlot {
  std::atomic<int> used{0};
  char path[kPathMax] = {};
};
static_assert(std::atomic<int>::is_always_lock_free, "the handler reads the slots' flags");
std::array<TemporarySlot, kSlots> g_temporaries;
std::mutex g_temporaries_mutex;

// What the process does with its temporaries: writes them, renames an OutputCommit's (the
// handler then leaves them and notes the signal for commit() to raise), or removes them and dies.
enum : int { kRunning = 0, kCommitting = 1, kDying = 2 };
std::atomic<int> g_state{kRunning};
std::atomic<int> g_deferred_signal{0};

// The open OutputCommit's files and the ScratchFiles (guarded by g_temporaries_mutex).
struct Pending {
  int slot;
  std::string tmp, target;
};
bool g_commit_open = false;
std::vector<Pending> g_pending;
std::set<std::string> g_scratch;

int register_locked(const std::string& path) {
  if (path.size() >= kPathMax) return -1;
  for (int i = 0; i < kSlots; ++i)
    if (!g_temporaries[i].used.load()) {
      std::memcpy(g_temporaries[i].path, path.c_str(), path.size() + 1);
      g_temporaries[i].used.store(1);  // after the path: the handler never reads half of one
      return i;
    }
  return -1;  // more temporaries than slots: that one is not removed on a signal
}

int register_temporary(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  return register_locked(path);
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_temporaries[slot].used.store(0);
}

void unlink_temporaries() {
  for (auto& t : g_temporaries)
    if (t.used.load()) ::unlink(t.path);
}

extern "C" void remove_temporaries_and_die(int sig) {
  g_deferred_signal.store(sig);
  int expected = kRunning;
  // Committing: commit() raises the signal again once every output is in place. Dying: the
  // thread that got the first signal ends the program.
  if (!g_state.compare_exchange_strong(expected, kDying)) return;
  unlink_temporaries();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

extern "C" void remove_temporaries_at_exit() { unlink_temporaries(); }

// A test's hook: with SDM_TEST_PAUSE_AFTER_WRITE=TEXT, the first time a file whose path contains
// TEXT is written (or "commit" once the first output of a commit is renamed) the program says so
// on stderr and sleeps up to 60 s, so that a test can send a signal exactly there.
void test_pause(const std::string& what) {
  static const char* const hook = std::getenv("SDM_TEST_PAUSE_AFTER_WRITE");
  static std::atomic<bool> paused{false};
  if (!hook || !*hook || what.find(hook) == std::string::npos || paused.exchange(true)) return;
  std::fprintf(stderr, "sdm: test pause after %s\n", what.c_str());
  std::fflush(stderr);
  ::sleep(60);  // a signal ends it
}

// Leaves `tmp` for the open OutputCommit to rename to `target`; false when none is open or the
// target is a ScratchFile (written at once).
bool defer_rename(int slot, const std::string& tmp, const std::string& target) {
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  if (!g_commit_open || g_scratch.count(target)) return false;
  for (const Pending& p : g_pending)
    if (p.tmp == tmp) {  // the same target written again: one temporary, renamed once
      if (slot != p.slot) unregister_temporary(slot);
      return true;
    }
  g_pending.push_back({slot, tmp, target});
  return true;
}

// Where the file `path` is now: the temporary of an output the open OutputCommit has not renamed
// yet (a glTF embedding the atlas written just before), else `path`.
std::string written_path(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  if (g_pending.empty()) return path;
  const fs::path wanted = fs::absolute(path).lexically_normal();
  for (const Pending& p : g_pending)
    if (fs::absolute(p.target).lexically_normal() == wanted) return p.tmp;
  return path;
}

}  // namespace

void remove_temporaries_on_signal() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
    struct sigaction now = {}, before = {};
    if (sigaction(sig, nullptr, &before) == 0 && before.sa_handler == SIG_IGN) continue;
    now.sa_handler = remove_temporaries_and_die;
    sigemptyset(&now.sa_mask);
    now.sa_flags = SA_RESTART;
    sigaction(sig, &now, nullptr);
  }
  static std::once_flag at_exit;
  std::call_once(at_exit, [] { std::atexit(remove_temporaries_at_exit); });
}

OutputCommit::OutputCommit() {
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  if (g_commit_open) throw std::logic_error("OutputCommit: another one is open");
  g_commit_open = true;
  g_pending.clear();
}

OutputCommit::~OutputCommit() {
  if (done_) return;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  for (const Pending& p : g_pending) {
    ::unlink(p.tmp.c_str());
    unregister_temporary(p.slot);
  }
  g_pending.clear();
  g_commit_open = false;
}

void OutputCommit::commit() {
  std::vector<Pending> pending;
  {
    std::lock_guard<std::mutex> lock(g_temporaries_mutex);
    pending.swap(g_pending);
    g_commit_open = false;
  }
  done_ = true;
  int expected = kRunning;
  if (!g_state.compare_exchange_strong(expected, kCommitting))
    for (;;) ::pause();  // a signal handler is removing the temporaries and ends the program
  std::error_code ec;
  size_t renamed = 0;
  for (; renamed < pending.size(); ++renamed) {
    fs::rename(pending[renamed].tmp, pending[renamed].target, ec);
    if (ec) break;
    if (renamed == 0) test_pause("commit");
  }
  if (ec) {
    std::error_code ignored;
    for (size_t i = 0; i < pending.size(); ++i) fs::remove(i < renamed ? pending[i].target : pending[i].tmp, ignored);
  }
  for (const Pending& p : pending) unregister_temporary(p.slot);
  g_state.store(kRunning);
  if (const int sig = g_deferred_signal.exchange(0)) ::raise(sig);
  if (ec) throw std::runtime_error("cannot write " + pending[renamed].target + ": " + ec.message());
}

ScratchFile::ScratchFile(std::string path) : path_(std::move(path)) {
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  slot_ = register_locked(path_);
  g_scratch.insert(path_);
}

ScratchFile::~ScratchFile() {
  std::error_code ec;
  fs::remove(path_, ec);
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  unregister_temporary(slot_);
  g_scratch.erase(path_);
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
    if (!defer_rename(slot, tmp.string(), path)) {
      fs::rename(tmp, target);
      unregister_temporary(slot);
    }
  } catch (...) {
    fs::remove(tmp, ec);
    unregister_temporary(slot);
    throw;
  }
  test_pause(path);
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
  return read_input_file(written_path(path), "file", kMaxMeshFileBytes);
}

}  // namespace sdm
