#include "libstm/mesh/write_positions.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>

namespace sdm {
namespace {

void append_number(std::string& out, double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);  // shortest digits that read back exactly
  out.append(buf, r.ptr);
}

template <typename T>
void append_little_endian(std::string& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  const uint16_t probe = 1;
  const bool little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  if (!little) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

bool float_exact(const Mesh& mesh) {
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k)
      if (double(float(mesh.point(v)[k])) != mesh.point(v)[k]) return false;
  return true;
}

}  // namespace

std::string off_text(const Mesh& mesh) {
  std::string out = "OFF\n" + std::to_string(mesh.n_vertices()) + " " + std::to_string(mesh.n_faces()) + " 0\n";
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    for (int k = 0; k < 3; ++k) {
      append_number(out, p[k]);
      out += k < 2 ? ' ' : '\n';
    }
  }
  for (auto f : mesh.faces()) {
    out += '3';
    for (auto v : mesh.fv_range(f)) out += ' ' + std::to_string(v.idx());
    out += '\n';
  }
  return out;
}

std::string ply_bytes(const Mesh& mesh) {
  const bool as_float = float_exact(mesh);
  const std::string type = as_float ? "float" : "double";
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by sdm\nelement vertex " + std::to_string(mesh.n_vertices()) +
                    "\nproperty " + type + " x\nproperty " + type + " y\nproperty " + type + " z\nelement face " +
                    std::to_string(mesh.n_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k) {
      if (as_float) append_little_endian(out, float(mesh.point(v)[k]));
      else append_little_endian(out, double(mesh.point(v)[k]));
    }
  for (auto f : mesh.faces()) {
    out += char(3);
    for (auto v : mesh.fv_range(f)) append_little_endian(out, int32_t(v.idx()));
  }
  return out;
}

double float32_rounding(const Mesh& mesh) {
  const double diag = bounding_box_diagonal(mesh);
  if (!(diag > 0)) return 0;
  double worst = 0;
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = point(mesh, v);
    worst = std::max(worst, (p - p.cast<float>().cast<double>()).norm());
  }
  return worst / diag;
}

bool writes_float32(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".stl" || ext == ".glb" || ext == ".gltf";
}

}  // namespace sdm
