// The point-cloud readers (point_cloud.h): .xyz, PLY and OFF without faces, PCD.
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/check_mesh_file.h"
#include "libstm/mesh/point_cloud.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

namespace sdm {

namespace fs = std::filesystem;

namespace {

// The whole file, after the checks every reader makes (a regular, non-empty file).
std::string slurp(const std::string& path) {
  std::string bytes = read_input_file(path, "point cloud", kMaxMeshFileBytes);
  if (bytes.empty()) throw InputError("cannot read point cloud " + path + ": the file is empty");
  if (bytes.size() >= 3 && bytes.compare(0, 3, "\xEF\xBB\xBF") == 0) bytes.erase(0, 3);  // a UTF-8 byte order mark
  return bytes;
}

// A cursor over the text: lines, and blank-separated tokens within a line.
struct Text {
  const std::string& s;
  size_t at = 0;
  long line = 0;
  bool next_line(std::string_view& out) {
    if (at >= s.size()) return false;
    size_t nl = s.find('\n', at);
    if (nl == std::string::npos) nl = s.size();
    out = std::string_view(s).substr(at, nl - at);
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    at = nl + 1;
    ++line;
    return true;
  }
};

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

// `t` as a number, or an InputError naming the file and the line.
double parse_number(std::string_view t, const std::string& path, long line) {
  double x = 0;
  const char* b = t.data();
  if (!t.empty() && t[0] == '+') ++b;
  const auto r = std::from_chars(b, t.data() + t.size(), x);
  if (r.ec == std::errc::result_out_of_range)
    throw InputError("point cloud " + path + " line " + std::to_string(line) + ": '" + std::string(t) +
                     "' is beyond the coordinate range (+-" + number(kMaxCoordinate) + "). Fix: rescale the scan");
  if (r.ec != std::errc() || r.ptr != t.data() + t.size())
    throw InputError("point cloud " + path + " line " + std::to_string(line) + ": '" + std::string(t) +
                     "' is not a number. Fix: remove or correct that line");
  return x;
}

// Refuses a point that is not finite or beyond the coordinate range, naming it.
void check_point(const Eigen::Vector3d& p, const std::string& path, long index, const std::string& where) {
  if (p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate) return;
  const bool nan = p.hasNaN();
  throw InputError("point cloud " + path + ": point " + std::to_string(index) + " (" + where + ") has " +
                   (nan ? "a NaN coordinate" : p.allFinite() ? "a coordinate beyond +-" + number(kMaxCoordinate) : "an infinite coordinate") +
                   ". Fix: remove that point or export the scan again");
}

// A normal as read: unit length when it can be, else zero (no direction: estimated later).
Eigen::Vector3d unit_or_zero(const Eigen::Vector3d& n) {
  const double l = n.norm();
  return std::isfinite(l) && l > 1e-12 ? Eigen::Vector3d(n / l) : Eigen::Vector3d::Zero();
}

// .xyz: `x y z` or `x y z nx ny nz` per line, the same on every line.
PointCloud read_xyz(const std::string& path, const std::string& bytes) {
  PointCloud c;
  Text text{bytes};
  std::string_view line;
  size_t columns = 0;
  while (text.next_line(line)) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    if (t.size() != 3 && t.size() != 6)
      throw InputError("point cloud " + path + " line " + std::to_string(text.line) + " has " + std::to_string(t.size()) +
                       " values; .xyz takes 3 (x y z) or 6 (x y z nx ny nz) per line");
    if (columns == 0) columns = t.size();
    if (t.size() != columns)
      throw InputError("point cloud " + path + " line " + std::to_string(text.line) + " has " + std::to_string(t.size()) +
                       " values where the lines before have " + std::to_string(columns) + ". Fix: give every line the same columns");
    double v[6];
    for (size_t k = 0; k < t.size(); ++k) v[k] = parse_number(t[k], path, text.line);
    const Eigen::Vector3d p(v[0], v[1], v[2]);
    check_point(p, path, long(c.points.size()), "line " + std::to_string(text.line));
    c.points.push_back(p);
    if (columns == 6) c.normals.push_back(unit_or_zero({v[3], v[4], v[5]}));
  }
  if (c.points.empty()) throw InputError("point cloud " + path + " has no points: no line holds x y z");
  return c;
}

// Binary scalars of PLY and PCD.
struct Field {
  std::string name;
  char kind = 'f';  // f: floating, i: signed, u: unsigned
  int size = 4;     // bytes
  int offset = 0;   // in the record
  std::string type; // as the file names it (PLY)
};

double read_scalar(const char* p, const Field& f, bool big_endian) {
  unsigned char b[8];
  std::memcpy(b, p, size_t(f.size));
  if (big_endian) std::reverse(b, b + f.size);
  if (f.kind == 'f') {
    if (f.size == 4) { float x; std::memcpy(&x, b, 4); return x; }
    double x; std::memcpy(&x, b, 8); return x;
  }
  uint64_t u = 0;
  for (int k = f.size; k-- > 0;) u = (u << 8) | b[k];
  if (f.kind == 'u') return double(u);
  const int shift = 64 - 8 * f.size;
  return double(int64_t(u << shift) >> shift);
}

// Where x, y, z, the normal and the colour are among a record's values (-1: absent).
struct Layout {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, r = -1, g = -1, b = -1, rgb = -1;
  void find(const std::vector<Field>& fields) {
    for (int i = 0; i < int(fields.size()); ++i) {
      const std::string& n = fields[size_t(i)].name;
      int* slot = n == "x" ? &x : n == "y" ? &y : n == "z" ? &z
                : n == "nx" || n == "normal_x" ? &nx : n == "ny" || n == "normal_y" ? &ny : n == "nz" || n == "normal_z" ? &nz
                : n == "red" || n == "r" ? &r : n == "green" || n == "g" ? &g : n == "blue" || n == "b" ? &b
                : n == "rgb" || n == "rgba" ? &rgb : nullptr;
      if (slot && *slot < 0) *slot = i;
    }
  }
  bool normals() const { return nx >= 0 && ny >= 0 && nz >= 0; }
  bool colors() const { return (r >= 0 && g >= 0 && b >= 0) || rgb >= 0; }
};

// Appends one record's point, normal and colour (`value(i)`: the record's i-th field).
template <class Value>
void take_record(PointCloud& c, const Layout& l, const std::vector<Field>& fields, const Value& value, const std::string& path,
                 const std::string& where) {
  const Eigen::Vector3d p(value(l.x), value(l.y), value(l.z));
  check_point(p, path, long(c.points.size()), where);
  c.points.push_back(p);
  if (l.normals()) c.normals.push_back(unit_or_zero({value(l.nx), value(l.ny), value(l.nz)}));
  if (!l.colors()) return;
  if (l.rgb >= 0) {  // PCL packs 8-bit r, g, b into one 32-bit field (a float's bits or an integer)
    const Field& f = fields[size_t(l.rgb)];
    const double v = value(l.rgb);
    uint32_t bits = 0;
    if (f.kind == 'f') { const float x = float(v); std::memcpy(&bits, &x, 4); }
    else bits = uint32_t(v);
    c.colors.emplace_back(float((bits >> 16) & 255) / 255.f, float((bits >> 8) & 255) / 255.f, float(bits & 255) / 255.f);
    return;
  }
  const float scale = fields[size_t(l.r)].kind == 'f' ? 1.f : 1.f / 255.f;
  c.colors.emplace_back(float(value(l.r)) * scale, float(value(l.g)) * scale, float(value(l.b)) * scale);
}

}  // namespace

namespace {

// A PLY header: its format and elements, in order.
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<Field> props;
  bool has_list = false;
  int stride = 0;
};
struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  size_t body = 0;  // where the data starts
};

bool ply_type(const std::string& t, Field& f) {
  static const std::pair<const char*, std::pair<char, int>> types[] = {
      {"char", {'i', 1}},   {"int8", {'i', 1}},    {"uchar", {'u', 1}},  {"uint8", {'u', 1}},   {"short", {'i', 2}},
      {"int16", {'i', 2}},  {"ushort", {'u', 2}},  {"uint16", {'u', 2}}, {"int", {'i', 4}},     {"int32", {'i', 4}},
      {"uint", {'u', 4}},   {"uint32", {'u', 4}},  {"float", {'f', 4}},  {"float32", {'f', 4}}, {"double", {'f', 8}},
      {"float64", {'f', 8}}};
  for (const auto& [name, ks] : types)
    if (t == name) { f.kind = ks.first, f.size = ks.second, f.type = t; return true; }
  return false;
}

// Parses the header; false (with `why`) when it is not one.
bool parse_ply_header(const std::string& bytes, PlyHeader& h, std::string& why) {
  Text text{bytes};
  std::string_view line;
  if (!text.next_line(line) || line != "ply") return why = "it does not start with 'ply'", false;
  while (text.next_line(line)) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    const std::string key(t[0]);
    if (key == "end_header") { h.body = text.at; return !h.format.empty() || (why = "no format line", false); }
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format" && t.size() >= 2) { h.format = std::string(t[1]); continue; }
    if (key == "element" && t.size() == 3) {
      PlyElement e;
      e.name = std::string(t[1]);
      const auto r = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
      if (r.ec != std::errc() || e.count < 0) return why = "element " + e.name + " has no valid count", false;
      h.elements.push_back(e);
      continue;
    }
    if (key == "property" && !h.elements.empty()) {
      PlyElement& e = h.elements.back();
      Field f;
      if (t.size() == 5 && t[1] == "list") { e.has_list = true; f.name = std::string(t[4]); e.props.push_back(f); continue; }
      if (t.size() != 3 || !ply_type(std::string(t[1]), f)) return why = "line " + std::to_string(text.line) + " is not a property it knows", false;
      f.name = std::string(t[2]), f.offset = e.stride, e.stride += f.size;
      e.props.push_back(f);
      continue;
    }
    return why = "line " + std::to_string(text.line) + " ('" + std::string(line) + "') is not a header line", false;
  }
  return why = "the header has no end_header", false;
}

const PlyElement* ply_vertices(const PlyHeader& h) {
  for (const auto& e : h.elements)
    if (e.name == "vertex") return &e;
  return nullptr;
}

// Elements beside the vertices, all empty: faces make it a mesh.
void check_ply_cloud(const PlyHeader& h, const std::string& path) {
  for (const auto& e : h.elements)
    if (e.name != "vertex" && e.count > 0)
      throw InputError("PLY " + path + " has " + std::to_string(e.count) + " " + e.name +
                       " elements: it is a mesh, not a point cloud (read it as a mesh)");
  const PlyElement* v = ply_vertices(h);
  if (!v || v->count == 0) throw InputError("point cloud " + path + " has no points: its header counts no vertex element");
  if (v->has_list) throw InputError("PLY " + path + ": a list property on the vertices is not a point cloud's. Fix: export x, y, z only");
}

PointCloud read_ply(const std::string& path, const std::string& bytes) {
  PlyHeader h;
  std::string why;
  if (!parse_ply_header(bytes, h, why)) throw InputError("cannot read PLY " + path + ": " + why);
  check_ply_cloud(h, path);
  const PlyElement& v = *ply_vertices(h);
  Layout l;
  l.find(v.props);
  if (l.x < 0 || l.y < 0 || l.z < 0) throw InputError("PLY " + path + ": the vertices have no x, y and z properties");
  const size_t left = bytes.size() - h.body;
  PointCloud c;
  if (h.format == "ascii") {
    if (size_t(v.count) > left / (2 * v.props.size()) + 1)
      throw InputError("PLY " + path + " counts " + std::to_string(v.count) + " vertices, more than its " + std::to_string(left) +
                       " bytes of data can hold. Fix: correct the header's count");
    c.points.reserve(size_t(v.count));
    Text text{bytes, h.body, 0};
    std::string_view line;
    const long header_lines = long(std::count(bytes.begin(), bytes.begin() + long(h.body), '\n'));
    for (long i = 0; i < v.count; ++i) {
      if (!text.next_line(line)) throw InputError("PLY " + path + " holds " + std::to_string(i) + " of the " + std::to_string(v.count) + " vertices its header counts");
      const auto t = tokens(line);
      const long at = header_lines + text.line;
      if (t.size() != v.props.size())
        throw InputError("PLY " + path + " line " + std::to_string(at) + " has " + std::to_string(t.size()) + " values, the header " + std::to_string(v.props.size()));
      std::vector<double> x(t.size());
      for (size_t k = 0; k < t.size(); ++k) {
        x[k] = parse_number(t[k], path, at);
        const Field& f = v.props[k];
        if (f.kind != 'f' && (x[k] != std::floor(x[k]) || (f.kind == 'u' && x[k] < 0) || std::abs(x[k]) >= std::ldexp(1.0, 8 * f.size)))
          throw InputError("PLY " + path + " line " + std::to_string(at) + ": '" + std::string(t[k]) +
                           "' is not a value for a property of type " + f.type + ". Fix: export the file again");
      }
      take_record(c, l, v.props, [&](int k) { return x[size_t(k)]; }, path, "line " + std::to_string(at));
    }
    return c;
  }
  const bool big = h.format == "binary_big_endian";
  if (!big && h.format != "binary_little_endian") throw InputError("PLY " + path + ": unknown format '" + h.format + "'");
  if (size_t(v.count) > left / size_t(v.stride))
    throw InputError("PLY " + path + " counts " + std::to_string(v.count) + " vertices of " + std::to_string(v.stride) + " bytes, more than its " +
                     std::to_string(left) + " bytes of data hold. Fix: correct the header's count");
  c.points.reserve(size_t(v.count));
  for (long i = 0; i < v.count; ++i) {
    const char* rec = bytes.data() + h.body + size_t(i) * size_t(v.stride);
    take_record(c, l, v.props, [&](int k) { return read_scalar(rec + v.props[size_t(k)].offset, v.props[size_t(k)], big); }, path,
                "vertex " + std::to_string(i));
  }
  return c;
}

// OFF, NOFF or COFF with zero faces: one vertex per line.
PointCloud read_off(const std::string& path, const std::string& bytes) {
  Text text{bytes};
  std::string_view line;
  std::vector<std::string_view> t;
  while (t.empty() && text.next_line(line)) t = tokens(line);
  if (t.empty() || (t[0] != "OFF" && t[0] != "NOFF" && t[0] != "COFF"))
    throw InputError("cannot read OFF " + path + ": it does not start with OFF, NOFF or COFF");
  const std::string kind(t[0]);
  t.erase(t.begin());
  while (t.empty() && text.next_line(line)) t = tokens(line);
  if (t.size() < 2) throw InputError("cannot read OFF " + path + ": no vertex and face counts");
  const double nv = parse_number(t[0], path, text.line), nf = parse_number(t[1], path, text.line);
  if (nf != 0) throw InputError("OFF " + path + " has " + number(nf) + " faces: it is a mesh, not a point cloud");
  if (!(nv >= 1) || nv != std::floor(nv) || nv > double(bytes.size() / 6 + 1))
    throw InputError("OFF " + path + " counts " + number(nv) + " vertices, which its " + std::to_string(bytes.size()) + " bytes cannot hold");
  const size_t want = kind == "OFF" ? 3 : 6;
  PointCloud c;
  c.points.reserve(size_t(nv));
  while (long(c.points.size()) < long(nv)) {
    if (!text.next_line(line)) throw InputError("OFF " + path + " holds " + std::to_string(c.points.size()) + " of the " + number(nv) + " vertices it counts");
    t = tokens(line);
    if (t.empty()) continue;
    if (t.size() < want) throw InputError("OFF " + path + " line " + std::to_string(text.line) + " has " + std::to_string(t.size()) + " values, a " + kind + " vertex " + std::to_string(want));
    double x[6];
    for (size_t k = 0; k < want; ++k) x[k] = parse_number(t[k], path, text.line);
    check_point({x[0], x[1], x[2]}, path, long(c.points.size()), "line " + std::to_string(text.line));
    c.points.emplace_back(x[0], x[1], x[2]);
    if (kind == "NOFF") c.normals.push_back(unit_or_zero({x[3], x[4], x[5]}));
    const float s = kind == "COFF" && std::max({x[3], x[4], x[5]}) > 1 ? 1.f / 255.f : 1.f;
    if (kind == "COFF") c.colors.emplace_back(float(x[3]) * s, float(x[4]) * s, float(x[5]) * s);
  }
  return c;
}

}  // namespace

namespace {

struct PcdHeader {
  std::vector<Field> fields;  // one per value of a record (a field of COUNT n gives n, named once)
  long points = -1;
  std::string data;
  int stride = 0;
  size_t body = 0;
};

// Parses a PCD header (PCL's "PCD file format" v0.5-0.7); throws InputError naming what is wrong.
PcdHeader parse_pcd_header(const std::string& path, const std::string& bytes) {
  PcdHeader h;
  Text text{bytes};
  std::string_view line;
  std::vector<std::string> names, types;
  std::vector<int> sizes, counts;
  long width = -1, height = 1;
  auto fail = [&](const std::string& why) { return InputError("cannot read PCD " + path + " line " + std::to_string(text.line) + ": " + why); };
  while (h.data.empty() && text.next_line(line)) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    const std::string key(t[0]);
    auto ints = [&](std::vector<int>& out) {
      for (size_t k = 1; k < t.size(); ++k) {
        const double x = parse_number(t[k], path, text.line);
        if (!(x >= 1 && x <= 1e6) || x != std::floor(x)) throw fail("'" + std::string(t[k]) + "' is not a positive count");
        out.push_back(int(x));
      }
    };
    if (key == "VERSION" || key == "VIEWPOINT") continue;
    if (key == "FIELDS" || key == "COLUMNS") for (size_t k = 1; k < t.size(); ++k) names.emplace_back(t[k]);
    else if (key == "TYPE") for (size_t k = 1; k < t.size(); ++k) types.emplace_back(t[k]);
    else if (key == "SIZE") ints(sizes);
    else if (key == "COUNT") ints(counts);
    else if (key == "WIDTH" && t.size() == 2) width = long(parse_number(t[1], path, text.line));
    else if (key == "HEIGHT" && t.size() == 2) height = long(parse_number(t[1], path, text.line));
    else if (key == "POINTS" && t.size() == 2) h.points = long(parse_number(t[1], path, text.line));
    else if (key == "DATA" && t.size() == 2) h.data = std::string(t[1]);
    else throw fail("'" + std::string(line) + "' is not a PCD header line");
  }
  if (h.data.empty()) throw fail("the header has no DATA line");
  if (counts.empty()) counts.assign(names.size(), 1);
  if (names.empty() || sizes.size() != names.size() || types.size() != names.size() || counts.size() != names.size())
    throw fail("FIELDS, SIZE, TYPE and COUNT do not name the same number of fields");
  if (h.points < 0) h.points = width * height;
  if (h.points <= 0) throw InputError("point cloud " + path + " has no points: its header counts none");
  for (size_t i = 0; i < names.size(); ++i) {
    const char kind = types[i] == "F" ? 'f' : types[i] == "I" ? 'i' : types[i] == "U" ? 'u' : 0;
    const int s = sizes[i];
    if (!kind || !(s == 1 || s == 2 || s == 4 || s == 8) || (kind == 'f' && s < 4))
      throw fail("field " + names[i] + " has TYPE " + types[i] + " and SIZE " + std::to_string(s) + ", which PCD does not define");
    for (int k = 0; k < counts[i]; ++k) {
      h.fields.push_back({k == 0 ? names[i] : "", kind, s, h.stride, types[i]});
      h.stride += s;
    }
  }
  h.body = text.at;
  return h;
}

PointCloud read_pcd(const std::string& path, const std::string& bytes) {
  const PcdHeader h = parse_pcd_header(path, bytes);
  Layout l;
  l.find(h.fields);
  if (l.x < 0 || l.y < 0 || l.z < 0) throw InputError("PCD " + path + ": the header names no x, y and z fields");
  if (h.data == "binary_compressed")
    throw InputError("PCD " + path + " is binary_compressed, which sdm does not read. Fix: save it as binary or ascii (PCL's pcl_convert_pcd_ascii_binary FILE OUT 1)");
  const size_t left = bytes.size() - h.body;
  PointCloud c;
  auto take = [&](auto&& value, const std::string& where) {
    if (std::isnan(value(l.x)) && std::isnan(value(l.y)) && std::isnan(value(l.z))) { ++c.no_returns; return; }
    take_record(c, l, h.fields, value, path, where);
  };
  if (h.data == "ascii") {
    if (size_t(h.points) > left / (2 * h.fields.size()) + 1)
      throw InputError("PCD " + path + " counts " + std::to_string(h.points) + " points, more than its " + std::to_string(left) + " bytes of data can hold. Fix: correct POINTS");
    c.points.reserve(size_t(h.points));
    Text text{bytes, h.body, long(std::count(bytes.begin(), bytes.begin() + long(h.body), '\n'))};
    std::string_view line;
    for (long i = 0; i < h.points;) {
      if (!text.next_line(line)) throw InputError("PCD " + path + " holds " + std::to_string(i) + " of the " + std::to_string(h.points) + " points its header counts");
      const auto t = tokens(line);
      if (t.empty()) continue;
      if (t.size() != h.fields.size())
        throw InputError("PCD " + path + " line " + std::to_string(text.line) + " has " + std::to_string(t.size()) + " values, the header " + std::to_string(h.fields.size()));
      std::vector<double> v(t.size());
      for (size_t k = 0; k < t.size(); ++k)
        v[k] = (t[k] == "nan" || t[k] == "NaN" || t[k] == "-nan") ? std::nan("") : parse_number(t[k], path, text.line);
      take([&](int k) { return v[size_t(k)]; }, "line " + std::to_string(text.line));
      ++i;
    }
    return c;
  }
  if (h.data != "binary") throw InputError("PCD " + path + ": unknown DATA '" + h.data + "' (ascii, binary)");
  if (size_t(h.points) > left / size_t(h.stride))
    throw InputError("PCD " + path + " counts " + std::to_string(h.points) + " points of " + std::to_string(h.stride) + " bytes, more than its " + std::to_string(left) + " bytes of data hold");
  c.points.reserve(size_t(h.points));
  for (long i = 0; i < h.points; ++i) {
    const char* rec = bytes.data() + h.body + size_t(i) * size_t(h.stride);
    take([&](int k) { return read_scalar(rec + h.fields[size_t(k)].offset, h.fields[size_t(k)], false); }, "point " + std::to_string(i));
  }
  return c;
}

// The first bytes of a file (its header), or empty when it cannot be read.
std::string head_of(const std::string& path, size_t most) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return {};
  std::ifstream in(path, std::ios::binary);
  std::string s(most, '\0');
  in.read(s.data(), std::streamsize(most));
  s.resize(size_t(in.gcount()));
  if (s.size() >= 3 && s.compare(0, 3, "\xEF\xBB\xBF") == 0) s.erase(0, 3);
  return s;
}

}  // namespace

bool is_point_cloud_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".xyz" || ext == ".pcd") return true;
  if (ext != ".ply" && ext != ".off") return false;
  const std::string head = head_of(path, 1 << 16);
  if (ext == ".ply") {
    PlyHeader h;
    std::string why;
    if (!parse_ply_header(head, h, why) || !ply_vertices(h) || ply_vertices(h)->count == 0) return false;
    for (const auto& e : h.elements)
      if (e.name != "vertex" && e.count > 0) return false;
    return true;
  }
  std::istringstream in(head);
  std::string word;
  in >> word;
  if (word != "OFF" && word != "NOFF" && word != "COFF") return false;
  while (in >> std::ws && in.peek() == '#') std::getline(in, word);
  long nv = 0, nf = -1;
  return bool(in >> nv >> nf) && nv > 0 && nf == 0;
}

PointCloud read_point_cloud(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".xyz" && ext != ".ply" && ext != ".off" && ext != ".pcd")
    throw InputError("cannot read point cloud " + path + ": unknown format '" + ext + "' (supported: .xyz, .ply, .off, .pcd)");
  const std::string bytes = slurp(path);
  PointCloud c = ext == ".xyz" ? read_xyz(path, bytes) : ext == ".ply" ? read_ply(path, bytes) : ext == ".off" ? read_off(path, bytes) : read_pcd(path, bytes);
  if (c.points.empty()) throw InputError("point cloud " + path + " has no points" + (c.no_returns ? " (every one is NaN: no return)" : ""));
  return c;
}

}  // namespace sdm
