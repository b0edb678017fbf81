#include "libstm/mesh/check_mesh_file.h"

#include "libstm/core/errors.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/text_lines.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>
#include <vector>

namespace sdm {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

namespace {

// Lines of a text file with their numbers; `comments` strips '#' to the end of the line.
struct Lines {
  std::string path;
  TextLines in;
  long number = 0;
  bool comments = false;
  Lines(const std::string& p, const std::string& text) : path(p), in(text) {}
  // The next line, or false at the end. A NUL byte is refused: the readers split lines at it
  // differently than these checks would (a face 'f \0 /1 2' reached OpenMesh's assertion).
  bool read(std::string& line) {
    if (!in.getline(line)) return false;
    ++number;
    if (line.find('\0') != std::string::npos)
      throw InputError("mesh " + path + " holds a NUL byte on line " + std::to_string(number) +
                       ": it is not a text mesh file (a binary file with a text extension, or damaged)");
    return true;
  }
  // The next line with something on it (after stripping comments), or false at the end.
  bool next_data(std::string& line) {
    while (read(line)) {
      if (comments) {
        const auto p = line.find('#');
        if (p != std::string::npos) line.resize(p);
      }
      if (line.find_first_not_of(" \t\r\n\v\f") != std::string::npos) return true;
    }
    return false;
  }
};

// Counts vertices with non-finite coordinates (the first one's place kept for the message) and
// refuses a finite coordinate beyond the float range at once.
struct CoordinateCheck {
  explicit CoordinateCheck(std::string p) : path(std::move(p)) {}
  std::string path;
  long bad = 0, vertices = 0;
  std::string first_bad;
  void add(const double xyz[3], const std::string& where) {
    ++vertices;
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(xyz[k])) {
        if (!bad++) first_bad = "vertex " + std::to_string(vertices - 1) + " " + where;
        return;
      }
      if (std::abs(xyz[k]) > kMaxCoordinate) {
        std::ostringstream v;
        v << xyz[k];
        throw InputError("mesh " + path + " has a coordinate of " + v.str() + " (vertex " + std::to_string(vertices - 1) + " " + where +
                         "), beyond the single-precision range (+-3.4e38) the mesh readers use. Fix: scale the model down");
      }
    }
  }
  void finish() const {
    if (bad)
      throw InputError("mesh " + path + " has " + std::to_string(bad) + " vertices with NaN or infinite coordinates, e.g. " + first_bad +
                       ". Fix: remove or repair those vertices in the modelling tool");
  }
};

// Up to `n` numbers from the start of `s` with strtod (which reads nan and inf); returns how many.
// Up to n numbers from the start of s; `rest` (when given) gets where parsing stopped.
int parse_numbers(const char* s, double* out, int n, const char** rest = nullptr) {
  int k = 0;
  while (k < n) {
    char* end = nullptr;
    const double x = std::strtod(s, &end);
    if (end == s) break;
    out[k++] = x;
    s = end;
  }
  if (rest) *rest = s;
  return k;
}

// A whole-token integer, or false.
bool parse_integer(const std::string& token, long long& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(token.c_str(), &end, 10);
  return errno == 0 && *end == '\0';
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> t;
  for (std::string w; s >> w;) t.push_back(w);
  return t;
}

std::string at_line(long n) { return "on line " + std::to_string(n); }

// Refuses element counts that the file cannot hold: each element needs at least `min_bytes`.
void check_counts_fit(const std::string& path, const std::string& what, long long count, double min_bytes, std::uintmax_t bytes,
                      long line) {
  if (count < 0)
    throw InputError("mesh " + path + ": the header " + at_line(line) + " announces " + std::to_string(count) + " " + what +
                     ": a count cannot be negative");
  if (double(count) * min_bytes > double(bytes))
    throw InputError("mesh " + path + ": the header " + at_line(line) + " announces " + std::to_string(count) + " " + what +
                     ", more than a file of " + std::to_string(bytes) + " bytes can hold: the header is wrong or the file is truncated");
}

// One OFF face line: a corner count and that many integer indices, nothing else.
void check_off_face(const std::string& path, const std::string& line, long lineno) {
  const auto t = tokens(line);
  long long k = 0;
  if (!parse_integer(t[0], k) || k < 0)
    throw InputError("mesh " + path + ": face " + at_line(lineno) + " starts with '" + t[0] + "', not a corner count");
  // OpenMesh reads faces token by token, not by line: a wrong count shifts every face after it
  // (a count of 2e9 read from a shifted index made it allocate gigabytes).
  if (k < 3) throw InputError("mesh " + path + ": face " + at_line(lineno) + " has " + std::to_string(k) + " corners; a face needs 3 or more");
  if (k > (long long)t.size() - 1)
    throw InputError("mesh " + path + ": face " + at_line(lineno) + " announces " + std::to_string(k) + " corners but lists " +
                     std::to_string(t.size() - 1) + " numbers");
  // OpenMesh reads the values after the corners (a face colour) as the next faces: four faces with
  // colours became 760 faces, and '3 0 1 3 0 26' a reservation of 1.6 GB (found by libFuzzer).
  if ((long long)t.size() - 1 > k)
    throw InputError("mesh " + path + ": face " + at_line(lineno) + " has " + std::to_string((long long)t.size() - 1 - k) +
                     " values after its " + std::to_string(k) + " corners (a face colour?), which this reader would misread " +
                     "as faces: remove them, or convert the file to PLY");
  for (long long c = 1; c <= k; ++c) {
    long long v = 0;
    if (!parse_integer(t[size_t(c)], v))
      throw InputError("mesh " + path + ": face " + at_line(lineno) + " has corner '" + t[size_t(c)] + "', not a vertex index");
  }
}

// One OFF vertex line: x y z, then the normal (N), texture coordinates (ST) and a colour of 3 or 4
// values (C) that the magic announces, nothing else. OpenMesh reads vertices token by token, so a
// line short of its normal ('NOFF' with 3 values, found by libFuzzer) shifted every face after it
// into counts it reserved gigabytes for.
void check_off_vertex(const std::string& path, const std::string& line, long lineno, const std::string& magic, int values, bool has_color,
                      CoordinateCheck& coords) {
  double v[13];  // at most ST + N + 3 + a colour of 4, and one more to see a surplus
  const char* rest = nullptr;
  const int n = parse_numbers(line.c_str(), v, values + 5, &rest);
  const bool ok = has_color ? (n == values + 3 || n == values + 4) : n == values;
  if (!ok || std::strspn(rest, " \t\r\n\v\f") != std::strlen(rest))
    throw InputError("mesh " + path + ": the vertex " + at_line(lineno) + " has " + std::to_string(tokens(line).size()) + " values where " +
                     magic + " has " + std::to_string(values) + (has_color ? " and a colour of 3 or 4" : "") + " (x y z" +
                     (values >= 6 ? ", a normal" : "") + (values == 5 || values == 8 ? ", texture coordinates" : "") + ")");
  coords.add(v, at_line(lineno));
}

void check_off(const std::string& path, const std::string& text) {
  const std::uintmax_t bytes = text.size();
  Lines lines(path, text);
  lines.comments = true;
  std::string line;
  if (!lines.next_data(line)) return;
  auto head = tokens(line);
  const std::string magic = head[0];
  // OpenMesh reads [ST][C][N][4][n]OFF; on anything else ('OFFB4', found by the fuzzer) it read
  // its counts from the end of the file into uninitialised variables and reserved what they held.
  static const std::regex off_magic("(ST)?C?N?4?n?OFF");
  if (!std::regex_match(magic, off_magic))
    throw InputError("cannot read mesh " + path + ": the first line starts with '" + magic.substr(0, 40) +
                     "', not an OFF header (OFF, optionally prefixed by ST, C, N, 4 and n)");
  const std::string prefix = magic.substr(0, magic.size() - 3);
  if (prefix.find_first_of("n4") != std::string::npos)
    throw InputError("mesh " + path + " is " + magic + " (4D or n-dimensional OFF), which this reader does not take: write it as OFF");
  // Binary OFF: OpenMesh's reader takes its counts unchecked ('OFF BINARY' and one byte reserved
  // 1.5 GB, found by libFuzzer). Rare in practice; refused rather than half-checked.
  if (line.find("BINARY") != std::string::npos)
    throw InputError("mesh " + path + " is binary OFF, which this reader does not take: write it as ASCII OFF, PLY or STL");
  // OpenMesh takes the counts from the line after the magic and ignores the rest of the magic's
  // line: 'OFF 4 4 0' on one line read the first vertex as the counts ('OFF 0 0 0' then a long
  // number: 1.6 GB reserved, found by libFuzzer).
  if (head.size() > 1)
    throw InputError("mesh " + path + ": line " + std::to_string(lines.number) + " has the counts beside '" + magic +
                     "', where this reader does not look for them: put them on the next line ('" + magic + "' alone, then 'V F 0')");
  long header_line = lines.number;
  if (!lines.next_data(line)) throw InputError("mesh " + path + " is truncated at line " + std::to_string(lines.number) + ": no counts");
  head = tokens(line), header_line = lines.number;
  long long nv = 0, nf = 0, ne = 0;
  if (head.size() < 2 || !parse_integer(head[0], nv) || !parse_integer(head[1], nf))
    throw InputError("mesh " + path + ": the OFF header " + at_line(header_line) + " does not give vertex and face counts");
  // OpenMesh reads the edge count before the vertices: without it, it took the first coordinate (or,
  // at the end of the file, an uninitialised value: 1 GB reserved for 'OFF 0 0', found by libFuzzer).
  if (head.size() < 3 || !parse_integer(head[2], ne))
    throw InputError("mesh " + path + ": the OFF header " + at_line(header_line) +
                     " gives no edge count after the vertex and face counts (write 0: 'V F 0')");
  // Anything after the three counts was read by OpenMesh as counts or vertices of its own ('OFF 0 0
  // 0 3OFF 0 2 2': 1 GB reserved, found by libFuzzer).
  if (head.size() > 3)
    throw InputError("mesh " + path + ": the OFF header " + at_line(header_line) + " has '" + head[3].substr(0, 40) +
                     "' after its three counts (vertices, faces, edges)");
  check_counts_fit(path, "vertices", nv, 6, bytes, header_line);
  check_counts_fit(path, "faces", nf, 2, bytes, header_line);
  check_counts_fit(path, "vertices and faces", nv + nf, 2, bytes, header_line);
  CoordinateCheck coords(path);
  auto truncated = [&](long long v, long long f) {
    return InputError("mesh " + path + " is truncated at line " + std::to_string(lines.number) + ": the header " + at_line(header_line) +
                      " announces " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces, the file ends after " +
                      std::to_string(v) + " vertices and " + std::to_string(f) + " faces");
  };
  const int values = 3 + 3 * (prefix.find('N') != std::string::npos) + 2 * (prefix.rfind("ST", 0) == 0);
  const bool has_color = prefix.find('C') != std::string::npos;
  for (long long i = 0; i < nv; ++i) {
    if (!lines.next_data(line)) throw truncated(i, 0);
    check_off_vertex(path, line, lines.number, magic, values, has_color, coords);
  }
  coords.finish();
  for (long long f = 0; f < nf; ++f) {
    if (!lines.next_data(line)) throw truncated(nv, f);
    check_off_face(path, line, lines.number);
  }
}

struct PlyElement {
  std::string name;
  long long count = 0;
  double min_bytes = 0;  // the least bytes one of them takes
  long line = 0;
  std::vector<bool> is_list;  // per property, in order
  std::vector<std::string> count_type, value_type;  // per property (count_type: lists only)
};

// The range of a PLY integer type, or false for a floating-point one.
bool ply_integer_range(const std::string& type, double& lo, double& hi) {
  if (type == "char" || type == "int8") lo = -128, hi = 127;
  else if (type == "uchar" || type == "uint8") lo = 0, hi = 255;
  else if (type == "short" || type == "int16") lo = -32768, hi = 32767;
  else if (type == "ushort" || type == "uint16") lo = 0, hi = 65535;
  else if (type == "int" || type == "int32") lo = -2147483648.0, hi = 2147483647.0;
  else if (type == "uint" || type == "uint32") lo = 0, hi = 4294967295.0;
  else return false;
  return true;
}

// Bytes of a PLY scalar type, or 0 for a name that is not one.
double ply_scalar_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32") return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// The PLY header, strictly: OpenMesh's parser loops for ever without end_header and crashes on a
// property before any element or on an unknown keyword or type.
std::vector<PlyElement> read_ply_header(const std::string& path, Lines& lines, bool& ascii) {
  std::string line;
  std::vector<PlyElement> elements;
  auto bad = [&](const std::string& why) { return InputError("mesh " + path + ": the PLY header " + at_line(lines.number) + " " + why); };
  while (lines.read(line)) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    const std::string& key = t[0];
    if (lines.number == 1 && key != "ply") throw bad("does not start with 'ply'");
    if (key == "end_header") return elements;
    if (key == "format") {
      if (t.size() != 3 || (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") || t[2] != "1.0")
        throw bad("names an unknown format (PLY 1.0 is ascii, binary_little_endian or binary_big_endian)");
      ascii = t[1] == "ascii";
    } else if (key == "element") {
      PlyElement e{t.size() > 1 ? t[1] : "", 0, 0, lines.number, {}, {}, {}};
      // Exactly three words: OpenMesh read a line with more ('... z\velement face (4', found by
      // libFuzzer) into an element count of its own and reserved 1.2 GB.
      if (t.size() != 3 || !parse_integer(t[2], e.count)) throw bad("does not give just an element name and count");
      elements.push_back(e);
    } else if (key == "property") {
      const bool list = t.size() > 1 && t[1] == "list";
      if (elements.empty()) throw bad("has a property before any element");
      if (t.size() != (list ? 5u : 3u) || ply_scalar_size(t[1 + list]) == 0 || (list && ply_scalar_size(t[3]) == 0))
        throw bad("has a property that is not 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
      elements.back().min_bytes += ascii ? 2 : ply_scalar_size(t[1 + list]);
      elements.back().is_list.push_back(list);
      elements.back().count_type.push_back(list ? t[2] : "");
      elements.back().value_type.push_back(t[1 + 2 * list]);
    } else if (key != "ply" && key != "comment" && key != "obj_info") {
      throw bad("has the unknown keyword '" + key + "'");
    }
  }
  throw InputError("mesh " + path + ": the PLY header has no end_header line (the file is truncated or not PLY)");
}

// One ASCII PLY element line: a number per scalar property, a count and that many numbers per list
// property, nothing else. OpenMesh's ASCII reader went on with uninitialised values after a token it
// could not parse (a flipped byte in a vertex line, found by the mutation fuzzer) and reserved what
// they held.
void check_ply_line(const std::string& path, const PlyElement& e, const std::string& line, long lineno) {
  const auto t = tokens(line);
  auto bad = [&](const std::string& why) {
    return InputError("mesh " + path + ": " + e.name + " " + at_line(lineno) + " " + why + " (its element has " +
                      std::to_string(e.is_list.size()) + " properties)");
  };
  size_t k = 0;
  // Integer types take whole numbers in range: OpenMesh read '2.5' for a uchar as 2 and then '.5'
  // as the next value, which shifted the faces into a 1 GB count (found by libFuzzer).
  auto number = [&](double& x, const std::string& type) {
    if (k >= t.size()) throw bad("has too few values");
    char* end = nullptr;
    x = std::strtod(t[k].c_str(), &end);
    if (end == t[k].c_str() || *end != '\0') throw bad("has '" + t[k].substr(0, 40) + "', not a number");
    double lo = 0, hi = 0;
    long long i = 0;
    if (ply_integer_range(type, lo, hi) && (!parse_integer(t[k], i) || double(i) < lo || double(i) > hi))
      throw bad("has '" + t[k].substr(0, 40) + "' for a property of type " + type);
    ++k;
  };
  double x = 0;
  for (size_t p = 0; p < e.is_list.size(); ++p) {
    if (!e.is_list[p]) {
      number(x, e.value_type[p]);
      continue;
    }
    number(x, e.count_type[p]);
    if (!(x >= 0) || x != std::floor(x) || x > double(t.size())) throw bad("has a list of " + t[k - 1].substr(0, 40) + " values");
    for (long long n = (long long)x; n > 0; --n) number(x, e.value_type[p]);
  }
  if (k != t.size()) throw bad("has more values than its properties take");
}

void check_ply(const std::string& path, const std::string& text) {
  const std::uintmax_t bytes = text.size();
  Lines lines(path, text);
  bool ascii = true;
  const std::vector<PlyElement> elements = read_ply_header(path, lines, ascii);
  long long total = 0;
  for (const auto& e : elements) {
    check_counts_fit(path, e.name + "s", e.count, std::max(1.0, e.min_bytes), bytes, e.line);
    total += e.count;
  }
  if (!ascii) return;
  std::string line;
  long long seen = 0;
  for (const auto& e : elements)
    for (long long i = 0; i < e.count; ++i, ++seen) {
      if (!lines.next_data(line))
        throw InputError("mesh " + path + " is truncated at line " + std::to_string(lines.number) + ": the header announces " +
                         std::to_string(total) + " elements (vertices, faces, ...), the file ends after " + std::to_string(seen));
      check_ply_line(path, e, line, lines.number);
    }
}

// One OBJ face corner v[/vt[/vn]]: every index present, non-zero, and (relative ones) resolvable.
void check_obj_corner(const std::string& path, const std::string& corner, long lineno, long long nv, long long nt, long long& max_v,
                      long long& max_t) {
  auto bad = [&](const std::string& why) {
    return InputError("mesh " + path + ": face corner '" + corner + "' " + at_line(lineno) + " " + why +
                      " (OBJ corners are v, v/vt, v/vt/vn or v//vn, with 1-based or negative indices)");
  };
  std::vector<std::string> part(1);
  for (char c : corner) {
    if (c == '/') part.emplace_back();
    else part.back().push_back(c);
  }
  if (part.size() > 3) throw bad("has more than three indices");
  long long v = 0;
  if (!parse_integer(part[0], v)) throw bad("has no vertex index");
  if (v == 0 || (v < 0 && nv + v < 0)) throw bad("names vertex " + std::to_string(v) + " with " + std::to_string(nv) + " defined before it");
  max_v = std::max(max_v, v);
  for (size_t k = 1; k < part.size(); ++k) {
    if (part[k].empty()) continue;
    long long i = 0;
    if (!parse_integer(part[k], i) || i == 0) throw bad("has an invalid texture or normal index '" + part[k] + "'");
    if (k == 1 && i < 0 && nt + i < 0) throw bad("names texture coordinate " + std::to_string(i) + " with " + std::to_string(nt) + " before it");
    if (k == 1) max_t = std::max(max_t, i);
  }
}

void check_obj(const std::string& path, const std::string& text) {
  Lines lines(path, text);
  std::string line;
  CoordinateCheck coords(path);
  long long nv = 0, nt = 0, max_v = 0, max_t = 0;
  long max_v_line = 0, max_t_line = 0;
  while (lines.read(line)) {
    // Any white space ends the key: OpenMesh read 'f\r 1 2 3' as a face (libFuzzer), these checks
    // did not, and an unchecked corner '/3' reached OpenMesh's assertion.
    const size_t p = line.find_first_not_of(" \t\r\v\f");
    if (p == std::string::npos || p + 1 >= line.size()) continue;
    const std::string key = line.substr(p, line.find_first_of(" \t\r\v\f", p) - p);
    const char* rest = line.c_str() + p + key.size();
    if (key == "v") {
      double xyz[3];
      if (parse_numbers(rest, xyz, 3) < 3)
        throw InputError("mesh " + path + ": vertex " + at_line(lines.number) + " has fewer than 3 coordinates");
      coords.add(xyz, at_line(lines.number));
      ++nv;
    } else if (key == "vt") {
      ++nt;
    } else if (key == "f") {
      // A comment after the corners ('f 1 2 3 # quad half') is not a corner.
      const char* hash = std::strchr(rest, '#');
      for (const auto& corner : tokens(hash ? std::string(rest, size_t(hash - rest)) : std::string(rest))) {
        const long long mv = max_v, mt = max_t;
        check_obj_corner(path, corner, lines.number, nv, nt, max_v, max_t);
        if (max_v > mv) max_v_line = lines.number;
        if (max_t > mt) max_t_line = lines.number;
      }
    }
  }
  coords.finish();
  if (max_v > nv)
    throw InputError("mesh " + path + ": a face " + at_line(max_v_line) + " names vertex " + std::to_string(max_v) + " but the file has " +
                     std::to_string(nv) + " vertices");
  if (max_t > nt)
    throw InputError("mesh " + path + ": a face " + at_line(max_t_line) + " names texture coordinate " + std::to_string(max_t) +
                     " but the file has " + std::to_string(nt));
}

void check_stl(const std::string& path, const std::string& text) {
  const std::uintmax_t bytes = text.size();
  char header[84] = {};
  text.copy(header, 84);
  uint32_t n = 0;
  std::memcpy(&n, header + 80, 4);  // little-endian in the format, as on the machines this runs on
  CoordinateCheck coords(path);
  if (bytes >= 84 && 84 + 50 * std::uintmax_t(n) == bytes) {
    for (uint32_t t = 0; t < n; ++t)
      for (int c = 0; c < 3; ++c) {
        float p[3];
        std::memcpy(p, text.data() + 84 + 50 * size_t(t) + 12 + 12 * c, 12);
        const double xyz[3] = {p[0], p[1], p[2]};
        coords.add(xyz, "(corner " + std::to_string(c) + " of triangle " + std::to_string(t) + ")");
      }
    coords.finish();
    return;
  }
  const std::string start(header, std::min<size_t>(84, text.size()));
  const auto first = start.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || start.compare(first, 5, "solid") != 0)
    throw InputError("mesh " + path + " is neither binary STL (its header announces " + std::to_string(n) + " triangles, " +
                     std::to_string(84 + 50 * std::uintmax_t(n)) + " bytes, but the file has " + std::to_string(bytes) +
                     ": truncated?) nor ASCII STL (starting with 'solid')");
  Lines lines(path, text);
  std::string line;
  while (lines.read(line)) {
    const auto p = line.find_first_not_of(" \t\r\v\f");
    if (p == std::string::npos || line.compare(p, 6, "vertex") != 0) continue;
    double xyz[3];
    if (parse_numbers(line.c_str() + p + 6, xyz, 3) < 3)
      throw InputError("mesh " + path + ": vertex " + at_line(lines.number) + " has fewer than 3 coordinates");
    coords.add(xyz, at_line(lines.number));
  }
  coords.finish();
}

}  // namespace

void check_mesh_file(const std::string& path, const std::string& text, const std::string& ext) {
  if (ext == ".off") check_off(path, text);
  else if (ext == ".ply") check_ply(path, text);
  else if (ext == ".obj") check_obj(path, text);
  else if (ext == ".stl") check_stl(path, text);
}

}  // namespace sdm
