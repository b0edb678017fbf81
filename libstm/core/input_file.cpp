#include "libstm/core/input_file.h"

#include "libstm/core/errors.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sdm {

namespace {

// Why a file of mode `mode` is not read, or "" for a regular file.
std::string not_regular(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "it is a folder";
  if (S_ISFIFO(mode)) return "it is a named pipe (FIFO), not a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "it is a device, not a regular file";
  if (S_ISSOCK(mode)) return "it is a socket, not a regular file";
  return "it is not a regular file";
}

InputError cannot_read(const std::string& what, const std::string& path, const std::string& why) {
  return InputError("cannot read " + what + " " + path + ": " + why);
}

std::string errno_reason(int e) {
  if (e == ENOENT || e == ENOTDIR) return "no such file";
  if (e == EACCES || e == EPERM) return "permission denied";
  return std::strerror(e);
}

// Closes its descriptor when it goes out of scope.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

void check_input_file(const std::string& path, const std::string& what) {
  struct stat st {};
  if (path.empty()) throw InputError("cannot read " + what + ": the path is empty");
  if (::stat(path.c_str(), &st) != 0) throw cannot_read(what, path, errno_reason(errno));
  const std::string why = not_regular(st.st_mode);
  if (!why.empty()) throw cannot_read(what, path, why);
}

std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes) {
  return read_input_file(path, what, max_bytes, {}, 1);
}

std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t max_bytes, const ReadBudget& budget,
                            double bytes_per_file_byte) {
  check_input_file(path, what);
  // O_NONBLOCK: should the path become a FIFO between the test and the open, the open returns at
  // once instead of waiting for a writer, and the test below refuses it.
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) throw cannot_read(what, path, errno_reason(errno));
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) throw cannot_read(what, path, errno_reason(errno));
  const std::string why = not_regular(st.st_mode);
  if (!why.empty()) throw cannot_read(what, path, why);
  const std::uint64_t size = std::uint64_t(st.st_size);
  if (size > max_bytes)
    throw cannot_read(what, path, "the file is " + byte_count(double(size)) + ", more than the " + byte_count(double(max_bytes)) +
                                      " this reader takes");
  if (budget) budget(bytes_per_file_byte * double(size));
  std::string bytes(size_t(size), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(file.fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw cannot_read(what, path, errno_reason(errno));
    if (n == 0) break;  // the file shrank while being read: what is there is the file
    done += size_t(n);
  }
  bytes.resize(done);
  return bytes;
}

std::string byte_count(double bytes) {
  static const char* unit[] = {"bytes", "KB", "MB", "GB", "TB"};
  int u = 0;
  while (bytes >= 1000 && u < 4) bytes /= 1000, ++u;
  char buf[32];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, unit[u]);
  return buf;
}

}  // namespace sdm
