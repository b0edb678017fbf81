#pragma once
/// The lines of a text held in memory, as std::getline gives them from a stream (the '\n' dropped,
/// a last line without one kept), without copying the text into a stream first.
#include <cstring>
#include <string>

namespace sdm {

struct TextLines {
  const std::string& text;
  size_t at = 0;
  explicit TextLines(const std::string& t) : text(t) {}
  bool getline(std::string& line) {
    if (at >= text.size()) return false;
    const void* nl = std::memchr(text.data() + at, '\n', text.size() - at);
    const size_t end = nl ? size_t(static_cast<const char*>(nl) - text.data()) : text.size();
    line.assign(text, at, end - at);
    at = nl ? end + 1 : text.size();
    return true;
  }
};

}  // namespace sdm
