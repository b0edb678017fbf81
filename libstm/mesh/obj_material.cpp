#include "libstm/mesh/obj_material.h"

#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/text_lines.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <vector>

namespace fs = std::filesystem;

namespace sdm {

namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string trimmed(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && blank(s[a])) ++a;
  while (b > a && blank(s[b - 1])) --b;
  return s.substr(a, b - a);
}

// The line's keyword (lower-cased) and the text after it, trimmed.
std::string split_key(const std::string& line, std::string& rest) {
  size_t a = 0;
  while (a < line.size() && blank(line[a])) ++a;
  size_t b = a;
  while (b < line.size() && !blank(line[b])) ++b;
  std::string key = line.substr(a, b - a);
  std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  rest = trimmed(line.substr(b));
  return key;
}

bool is_number(const std::string& token) {
  char* end = nullptr;
  std::strtod(token.c_str(), &end);
  return !token.empty() && end == token.c_str() + token.size();
}

// The materials of one library in the order it defines them, each with its map_Kd ("" for none).
void read_library(const fs::path& mtl, std::vector<std::string>& order, std::map<std::string, std::string>& texture) {
  const std::string text = read_input_file(mtl.string(), "material library", kMaxMaterialFileBytes);
  TextLines lines(text);
  std::string line, rest, current;
  while (lines.getline(line)) {
    const std::string key = split_key(line, rest);
    if (key == "newmtl") {
      current = rest;
      if (!texture.count(current)) order.push_back(current), texture[current] = "";
    } else if (key == "map_kd" && texture.count(current)) {
      const std::string name = map_file_name(rest);
      if (!name.empty()) texture[current] = (mtl.parent_path() / name).lexically_normal().string();
    }
  }
}

// The libraries an mtllib line names: the whole text when such a file exists (a name with blanks),
// else each word.
std::vector<fs::path> libraries(const std::string& rest, const fs::path& dir) {
  std::string name = rest;
  std::replace(name.begin(), name.end(), '\\', '/');
  std::error_code ec;
  if (name.empty()) return {};
  if (fs::exists(dir / name, ec)) return {(dir / name).lexically_normal()};
  std::vector<fs::path> out;
  size_t at = 0;
  while (at < name.size()) {
    while (at < name.size() && blank(name[at])) ++at;
    size_t end = at;
    while (end < name.size() && !blank(name[end])) ++end;
    if (end > at) out.push_back((dir / name.substr(at, end - at)).lexically_normal());
    at = end;
  }
  return out;
}

}  // namespace

std::string map_file_name(const std::string& arguments) {
  // Options and how many values each takes; -o, -s and -t take one to three numbers.
  static const std::map<std::string, int> kOptions = {{"-blendu", 1}, {"-blendv", 1}, {"-bm", 1},      {"-boost", 1}, {"-cc", 1},
                                                      {"-clamp", 1},  {"-imfchan", 1}, {"-texres", 1}, {"-type", 1},  {"-mm", 2},
                                                      {"-o", -3},     {"-s", -3},      {"-t", -3}};
  size_t at = 0;
  auto token = [&](size_t& start) {
    while (at < arguments.size() && blank(arguments[at])) ++at;
    start = at;
    while (at < arguments.size() && !blank(arguments[at])) ++at;
    return arguments.substr(start, at - start);
  };
  size_t start = 0;
  std::string t = token(start);
  for (auto option = kOptions.find(t); option != kOptions.end(); option = kOptions.find(t)) {
    const int n = option->second;
    for (int k = 0; k < std::abs(n); ++k) {
      const size_t before = at;
      size_t s = 0;
      const std::string value = token(s);
      if (n < 0 && k > 0 && !is_number(value)) {
        at = before;  // -o, -s, -t with fewer than three numbers
        break;
      }
    }
    t = token(start);
  }
  std::string name = trimmed(arguments.substr(start));
  std::replace(name.begin(), name.end(), '\\', '/');
  return name;
}

std::string obj_texture(const std::string& text, const std::string& obj_path) {
  const fs::path dir = fs::absolute(fs::path(obj_path)).parent_path();
  std::vector<std::string> order;
  std::map<std::string, std::string> texture;
  std::map<std::string, long> faces;
  TextLines lines(text);
  std::string line, rest, current;
  while (lines.getline(line)) {
    const std::string key = split_key(line, rest);
    if (key == "f") {
      if (!current.empty()) ++faces[current];
    } else if (key == "usemtl") {
      current = rest;
    } else if (key == "mtllib") {
      for (const fs::path& mtl : libraries(rest, dir)) {
        std::error_code ec;
        if (fs::exists(mtl, ec)) read_library(mtl, order, texture);  // a missing library: no texture, as before
      }
    }
  }
  std::string best;
  long most = -1;
  for (const std::string& m : order)
    if (!texture[m].empty() && faces[m] > most) most = faces[m], best = texture[m];
  // A texture that is there must be a file: a named pipe or a device is refused now, by name, rather
  // than when a command reads it. One that is missing is the command's to report, if it needs it.
  std::error_code ec;
  if (!best.empty() && fs::exists(best, ec)) check_input_file(best, "texture");
  return best;
}

void prepare_obj_for_openmesh(std::string& text) {
  size_t at = 0;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    size_t p = at;
    while (p < end && blank(text[p])) ++p;
    if (text.compare(p, 6, "mtllib") == 0 && (p + 6 == end || blank(text[p + 6]))) text[p] = '#';
    // A comment after values: '#' after a blank, to the end of the line.
    for (size_t c = p + 1; c < end && text[p] != '#'; ++c)
      if (text[c] == '#' && blank(text[c - 1])) {
        std::fill(text.begin() + long(c), text.begin() + long(end), ' ');
        break;
      }
    at = end + 1;
  }
}

}  // namespace sdm
