#include "libstm/mesh/read_binary_ply.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace sdm {

namespace {

enum class Type { none, i8, u8, i16, u16, i32, u32, f32, f64 };

Type type_named(const std::string& s) {
  if (s == "char" || s == "int8") return Type::i8;
  if (s == "uchar" || s == "uint8") return Type::u8;
  if (s == "short" || s == "int16") return Type::i16;
  if (s == "ushort" || s == "uint16") return Type::u16;
  if (s == "int" || s == "int32") return Type::i32;
  if (s == "uint" || s == "uint32") return Type::u32;
  if (s == "float" || s == "float32") return Type::f32;
  if (s == "double" || s == "float64") return Type::f64;
  return Type::none;
}

size_t size_of(Type t) {
  switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: return 8;
    default: return 0;
  }
}

// One value of type t at p, in the file's byte order.
double value_at(const char* p, Type t, bool swap) {
  unsigned char b[8];
  const size_t n = size_of(t);
  std::memcpy(b, p, n);
  if (swap)
    for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
  switch (t) {
    case Type::i8: return double(int8_t(b[0]));
    case Type::u8: return double(b[0]);
    case Type::i16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case Type::u16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case Type::i32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case Type::u32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case Type::f32: { float v; std::memcpy(&v, b, 4); return double(v); }
    case Type::f64: { double v; std::memcpy(&v, b, 8); return v; }
    default: return 0;
  }
}

struct Header {
  bool swap = false;
  bool ascii = false;
  size_t vertex_properties = 0;  // ASCII: values per vertex line; offsets below count values
  Type vertex_type[64] = {};     // ASCII: each value's type (a vertex of more properties: OpenMesh's path)
  size_t data = 0;  // offset of the first vertex
  long long vertices = -1, faces = -1;
  size_t vertex_stride = 0;
  size_t xyz[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX}, rgb[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};  // offsets in a vertex
  Type xyz_type[3] = {}, rgb_type[3] = {};
  Type count_type = Type::none, index_type = Type::none;
};

// A vertex property: its offset recorded when it is a coordinate or a colour channel.
bool add_vertex_property(Header& h, const std::string& type, const std::string& name) {
  const Type t = type_named(type);
  if (t == Type::none || h.vertex_properties >= 64) return false;
  static const char* coords[3] = {"x", "y", "z"};
  static const char* channels[3] = {"red", "green", "blue"};
  const size_t at = h.ascii ? h.vertex_properties : h.vertex_stride;
  for (int k = 0; k < 3; ++k) {
    if (name == coords[k]) h.xyz[k] = at, h.xyz_type[k] = t;
    if (name == channels[k]) h.rgb[k] = at, h.rgb_type[k] = t;
  }
  h.vertex_type[h.vertex_properties++] = t;
  h.vertex_stride += size_of(t);
  return true;
}

// The header, strictly: vertex then face elements, scalar vertex properties, one corner list per
// face; false for anything else.
bool parse_header(const std::string& bytes, Header& h) {
  const size_t end = bytes.find("end_header");
  if (bytes.compare(0, 4, "ply\n") != 0 || end == std::string::npos || end > (1u << 16)) return false;
  const size_t newline = bytes.find('\n', end);
  if (newline == std::string::npos || bytes.find_first_not_of(" \t\r", end + 10) != newline) return false;
  h.data = newline + 1;
  std::istringstream in(bytes.substr(4, end - 4));
  std::string line, element;
  bool format = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key, a, b, c, d, extra;
    words >> key >> a >> b >> c >> d >> extra;
    if (key == "comment" && a == "TextureFile") return false;  // a texture: OpenMesh's path
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (b != "1.0" || !c.empty() || (a != "binary_little_endian" && a != "binary_big_endian" && a != "ascii")) return false;
      h.ascii = a == "ascii";
      const uint16_t one = 1;
      const bool little = *reinterpret_cast<const unsigned char*>(&one) == 1;
      h.swap = (a == "binary_big_endian") == little;
      format = true;
    } else if (key == "element" && c.empty() && format) {
      long long n = -1;
      std::istringstream(b) >> n;
      if (n < 0 || (a == "vertex" && h.vertices < 0 && h.faces < 0)) h.vertices = n;
      else if (a == "face" && h.vertices >= 0 && h.faces < 0) h.faces = n;
      else return false;
      if (n < 0) return false;
      element = a;
    } else if (key == "property" && element == "vertex" && c.empty() && a != "list") {
      if (!add_vertex_property(h, a, b)) return false;
    } else if (key == "property" && element == "face" && a == "list" && extra.empty() && h.count_type == Type::none &&
               (d == "vertex_indices" || d == "vertex_index")) {
      h.count_type = type_named(b), h.index_type = type_named(c);
      if (h.count_type == Type::none || h.index_type == Type::none || h.count_type == Type::f32 || h.count_type == Type::f64 ||
          h.index_type == Type::f32 || h.index_type == Type::f64)
        return false;
    } else {
      return false;
    }
  }
  const bool has_colors = h.rgb[0] != SIZE_MAX || h.rgb[1] != SIZE_MAX || h.rgb[2] != SIZE_MAX;
  for (int k = 0; k < 3; ++k)
    if (h.xyz[k] == SIZE_MAX || (has_colors && (h.rgb[k] == SIZE_MAX || h.rgb_type[k] != Type::u8))) return false;
  return format && h.vertices >= 0 && h.faces >= 0 && h.count_type != Type::none;
}

// The range of an integer type, or false for a floating-point one.
bool integer_range(Type t, double& lo, double& hi) {
  switch (t) {
    case Type::i8: lo = -128, hi = 127; return true;
    case Type::u8: lo = 0, hi = 255; return true;
    case Type::i16: lo = -32768, hi = 32767; return true;
    case Type::u16: lo = 0, hi = 65535; return true;
    case Type::i32: lo = -2147483648.0, hi = 2147483647.0; return true;
    case Type::u32: lo = 0, hi = 4294967295.0; return true;
    default: return false;
  }
}

// A cursor over the ASCII body: one value of a type at a time, lines kept apart.
struct AsciiBody {
  const char* p;
  const char* end;
  bool blank(char c) const { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
  // To the start of the next line with a value on it; false at the end of the text.
  bool next_line() {
    while (p < end && (blank(*p) || *p == '\n')) ++p;
    return p < end;
  }
  bool line_done() {
    while (p < end && blank(*p)) ++p;
    if (p == end) return true;
    if (*p != '\n') return false;
    ++p;
    return true;
  }
  // One value of type t on the current line: a whole number within range for the integer types, a
  // finite number within float range for the others; false for anything else.
  bool value(Type t, double& x) {
    while (p < end && blank(*p)) ++p;
    const auto r = std::from_chars(p, end, x);
    if (r.ec != std::errc() || (r.ptr < end && !blank(*r.ptr) && *r.ptr != '\n')) return false;
    p = r.ptr;
    double lo = 0, hi = 0;
    if (integer_range(t, lo, hi)) return x == std::floor(x) && x >= lo && x <= hi;
    return std::abs(x) <= double(std::numeric_limits<float>::max());
  }
};

// Appends a face: triangles while every face is one, all faces as polygons from the first that is not.
void add_face(const std::vector<int>& corners, BinaryPly& out) {
  if (corners.size() == 3 && out.polygons.empty()) {
    out.triangles.push_back({corners[0], corners[1], corners[2]});
    return;
  }
  if (out.polygons.empty())
    for (const auto& t : out.triangles) out.polygons.push_back({t[0], t[1], t[2]});
  out.triangles.clear();
  out.polygons.push_back(corners);
}

// The ASCII body after the header: a line per vertex with its values, a line per face with its
// corner count and corners. False for anything the checked path should report instead.
bool read_ascii_body(const std::string& bytes, const Header& h, BinaryPly& out) {
  AsciiBody in{bytes.data() + h.data, bytes.data() + bytes.size()};
  const size_t nv = size_t(h.vertices), nf = size_t(h.faces);
  // Reserved no further than the text can hold (two characters a value).
  if (double(nv) * double(2 * h.vertex_properties) > double(bytes.size()) || double(nf) * 8 > double(bytes.size())) return false;
  const bool has_colors = h.rgb[0] != SIZE_MAX;
  out.points.resize(nv);
  out.colors.assign(has_colors ? nv : 0, Eigen::Vector3f::Zero());
  double values[64];
  for (size_t v = 0; v < nv; ++v) {
    if (!in.next_line()) return false;
    for (size_t k = 0; k < h.vertex_properties; ++k)
      if (!in.value(h.vertex_type[k], values[k])) return false;
    if (!in.line_done()) return false;
    for (int k = 0; k < 3; ++k) out.points[v][k] = values[h.xyz[k]];
    if (has_colors)
      for (int k = 0; k < 3; ++k) out.colors[v][k] = float(values[h.rgb[k]]) / 255.f;
  }
  std::vector<int> corners;
  for (size_t f = 0; f < nf; ++f) {
    double n = 0;
    if (!in.next_line() || !in.value(h.count_type, n) || n < 0 || n > double(in.end - in.p)) return false;
    corners.resize(size_t(n));
    for (int& c : corners) {
      double i = 0;
      if (!in.value(h.index_type, i) || i < 0 || i >= double(nv)) return false;  // out of range: OpenMesh's path reports it
      c = int(i);
    }
    if (!in.line_done()) return false;
    add_face(corners, out);
  }
  return !in.next_line();  // nothing after the faces
}

}  // namespace

bool read_binary_ply(const std::string& bytes, BinaryPly& out) {
  Header h;
  if (!parse_header(bytes, h)) return false;
  if (h.ascii) return read_ascii_body(bytes, h, out);
  const size_t nv = size_t(h.vertices), nf = size_t(h.faces);
  if ((bytes.size() - h.data) / std::max<size_t>(h.vertex_stride, 1) < nv) return false;
  const char* p = bytes.data() + h.data;
  out.points.resize(nv);
  const bool has_colors = h.rgb[0] != SIZE_MAX;
  out.colors.assign(has_colors ? nv : 0, Eigen::Vector3f::Zero());
  for (size_t v = 0; v < nv; ++v, p += h.vertex_stride) {
    for (int k = 0; k < 3; ++k) out.points[v][k] = value_at(p + h.xyz[k], h.xyz_type[k], h.swap);
    if (has_colors)
      for (int k = 0; k < 3; ++k) out.colors[v][k] = float(value_at(p + h.rgb[k], Type::u8, false)) / 255.f;
  }
  const char* end = bytes.data() + bytes.size();
  const size_t cs = size_of(h.count_type), is = size_of(h.index_type);
  if (size_t(end - p) / (cs + 3 * is) < nf) return false;  // not even triangles fit
  out.triangles.reserve(nf);
  std::vector<int> corners;
  for (size_t f = 0; f < nf; ++f) {
    if (size_t(end - p) < cs) return false;
    const double n = value_at(p, h.count_type, h.swap);
    p += cs;
    if (n < 0 || double(end - p) < n * double(is)) return false;
    corners.resize(size_t(n));
    for (int& c : corners) {
      const double i = value_at(p, h.index_type, h.swap);
      p += is;
      if (i < 0 || i >= double(nv)) return false;  // out of range: OpenMesh's path reports it
      c = int(i);
    }
    add_face(corners, out);
  }
  return true;
}

}  // namespace sdm
