#include "libstm/mesh/read_plain_text.h"

#include <charconv>
#include <cstring>
#include <string_view>
#include <cmath>
#include <limits>

namespace sdm {

namespace {

// A cursor over one line of the text: numbers and words separated by blanks.
struct Line {
  const char* p;
  const char* end;
  void skip_blanks() {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  }
  bool done() {
    skip_blanks();
    return p == end || *p == '#';
  }
  bool number(double& x) {
    skip_blanks();
    const auto r = std::from_chars(p, end, x);
    // NaN, infinities and values beyond float range are left to the checked path's messages.
    if (r.ec != std::errc() || !(std::abs(x) <= double(std::numeric_limits<float>::max()))) return false;
    p = r.ptr;
    return p == end || *p == ' ' || *p == '\t' || *p == '\r' || *p == '#';
  }
  bool integer(long& x) {
    skip_blanks();
    const auto r = std::from_chars(p, end, x);
    if (r.ec != std::errc()) return false;
    p = r.ptr;
    return true;
  }
  std::string_view word() {
    skip_blanks();
    const char* s = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
    return {s, size_t(p - s)};
  }
};

// Calls `take(line)` for every line of the text; stops and returns false as soon as it does.
template <class F>
bool each_line(const std::string& text, F&& take) {
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
    const char* e = nl ? nl : end;
    Line line{p, e};
    if (!take(line)) return false;
    p = nl ? nl + 1 : end;
  }
  return true;
}

bool three_numbers(Line& line, std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d x;
  if (!line.number(x[0]) || !line.number(x[1]) || !line.number(x[2]) || !line.done()) return false;
  points.push_back(x);
  return true;
}

// One OBJ corner token: its vertex index (1-based, or negative from the end) before any '/'.
bool obj_corner(std::string_view token, long vertices, int& index) {
  long i = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), i);
  if (r.ec != std::errc() || (r.ptr != token.data() + token.size() && *r.ptr != '/')) return false;
  if (i < 0) i += vertices + 1;
  if (i < 1 || i > vertices) return false;
  index = int(i - 1);
  return true;
}

}  // namespace

bool read_plain_obj(const std::string& text, std::vector<Eigen::Vector3d>& points, std::vector<std::vector<int>>& polygons) {
  points.clear(), polygons.clear();
  return each_line(text, [&](Line& line) {
    if (line.done()) return true;
    const std::string_view key = line.word();
    if (key == "v") return three_numbers(line, points);
    if (key == "f") {
      std::vector<int>& poly = polygons.emplace_back();
      while (!line.done()) {
        int index = 0;
        if (!obj_corner(line.word(), long(points.size()), index)) return false;
        poly.push_back(index);
      }
      return poly.size() >= 3;
    }
    return key == "vn" || key == "o" || key == "g" || key == "s";
  }) && !points.empty();
}

bool read_plain_off(const std::string& text, std::vector<Eigen::Vector3d>& points, std::vector<std::vector<int>>& polygons) {
  points.clear(), polygons.clear();
  enum { magic, counts, vertex, face, rest } stage = magic;
  long nv = 0, nf = 0;
  const bool ok = each_line(text, [&](Line& line) {
    if (line.done()) return true;
    switch (stage) {
      case magic:
        stage = counts;
        return line.word() == "OFF" && line.done();
      case counts: {
        long ne = 0;
        if (!line.integer(nv) || !line.integer(nf) || !line.integer(ne) || !line.done() || nv <= 0 || nf < 0) return false;
        // Reserved no further than the text can hold (a line per vertex of at least 6 characters,
        // per face of at least 8): counts a hostile header claims do not allocate.
        points.reserve(std::min(size_t(nv), text.size() / 6)), polygons.reserve(std::min(size_t(nf), text.size() / 8));
        stage = vertex;
        return true;
      }
      case vertex:
        if (!three_numbers(line, points)) return false;
        if (long(points.size()) == nv) stage = nf > 0 ? face : rest;
        return true;
      case face: {
        long n = 0;
        if (!line.integer(n) || n < 3) return false;
        std::vector<int>& poly = polygons.emplace_back();
        for (long k = 0; k < n; ++k) {
          long i = -1;
          if (!line.integer(i) || i < 0 || i >= nv) return false;
          poly.push_back(int(i));
        }
        if (!line.done()) return false;  // colours after the indices
        if (long(polygons.size()) == nf) stage = rest;
        return true;
      }
      case rest:
        return false;  // more than the counts say
    }
    return false;
  });
  return ok && stage == rest;
}

}  // namespace sdm
