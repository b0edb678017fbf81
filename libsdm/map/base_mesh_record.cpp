#include "libsdm/map/base_mesh_record.h"

#include "libstm/core/errors.h"
#include "libstm/core/json_int.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace sdm {

bool faces_share_corner(const Eigen::MatrixX3i& triangles, int f, int g) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (triangles(f, a) == triangles(g, b)) return true;
  return false;
}

nlohmann::json base_mesh_to_json(const BaseMesh& base) {
  nlohmann::json j;
  std::vector<int> tris;
  std::vector<double> uv, d;
  for (int f = 0; f < base.triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      tris.push_back(base.triangles(f, c));
      uv.push_back(base.corner_uv[f][c].x());
      uv.push_back(base.corner_uv[f][c].y());
      if (!base.corner_d.empty()) d.push_back(base.corner_d[f][c]);
    }
  j["triangles"] = tris;
  j["face_segment"] = base.face_segment;
  j["corner_uv"] = uv;
  if (!d.empty()) j["corner_d"] = d;
  if (!base.flat_faces.empty()) j["flat_faces"] = base.flat_faces;
  return j;
}

namespace {

// What make_base_mesh guarantees and the tessellation relies on (OpenSubdiv asserts otherwise):
// three distinct corners per face, vertices 0..n-1 all used, every directed edge used once and its
// opposite at most once (consistently oriented; edges without an opposite are the boundary of an
// open mesh's holes), and at most one boundary edge leaving each vertex (two loops touching at a
// vertex would make it non-manifold).
void check_base_topology(const Eigen::MatrixX3i& t) {
  const std::string bad = "invalid base mesh in the SDM header: ";
  const int nf = int(t.rows());
  for (int f = 0; f < nf; ++f)
    if (t(f, 0) == t(f, 1) || t(f, 1) == t(f, 2) || t(f, 0) == t(f, 2))
      throw InputError(bad + "face " + std::to_string(f) + " is degenerate (corners " + std::to_string(t(f, 0)) + ", " +
                       std::to_string(t(f, 1)) + ", " + std::to_string(t(f, 2)) + ")");
  const int64_t top = t.maxCoeff();  // 64-bit: an index of INT_MAX must not wrap below
  if (top + 1 > 3 * int64_t(nf)) throw InputError(bad + "vertex index " + std::to_string(top) + " for " + std::to_string(nf) + " faces");
  const int nv = int(top + 1);
  std::vector<char> used(size_t(nv), 0);
  std::vector<std::pair<int, int>> directed;
  directed.reserve(3 * size_t(nf));
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) used[t(f, c)] = 1, directed.emplace_back(t(f, c), t(f, (c + 1) % 3));
  for (int v = 0; v < nv; ++v)
    if (!used[v]) throw InputError(bad + "vertex " + std::to_string(v) + " belongs to no face");
  std::sort(directed.begin(), directed.end());
  std::vector<char> leaves_boundary(size_t(nv), 0);
  for (size_t i = 0; i < directed.size(); ++i) {
    const auto& [a, b] = directed[i];
    if (i + 1 < directed.size() && directed[i + 1] == directed[i])
      throw InputError(bad + "edge " + std::to_string(a) + "-" + std::to_string(b) + " is used twice in the same direction");
    if (std::binary_search(directed.begin(), directed.end(), std::make_pair(b, a))) continue;
    if (leaves_boundary[size_t(a)]++)
      throw InputError(bad + "vertex " + std::to_string(a) + " lies on two boundary loops (non-manifold)");
  }
}

}  // namespace

BaseMesh base_mesh_from_json(const nlohmann::json& j, int segments) {
  BaseMesh base;
  std::vector<int> tris;
  std::vector<double> uv, d;
  try {
    tris = json_ints(j.at("triangles"));
    base.face_segment = json_ints(j.at("face_segment"));
    uv = j.at("corner_uv").get<std::vector<double>>();
    if (j.contains("corner_d")) d = j.at("corner_d").get<std::vector<double>>();
    if (j.contains("flat_faces")) base.flat_faces = json_ints(j.at("flat_faces"));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("invalid base mesh in the SDM header: ") + e.what());
  }
  const size_t nf = base.face_segment.size();
  if (tris.size() != 3 * nf || uv.size() != 6 * nf || nf == 0)
    throw InputError("invalid base mesh in the SDM header: " + std::to_string(nf) + " faces but " +
                     std::to_string(tris.size()) + " corner indices and " + std::to_string(uv.size()) + " uv values");
  if (!d.empty() && d.size() != 3 * nf)
    throw InputError("invalid base mesh in the SDM header: " + std::to_string(nf) + " faces but " + std::to_string(d.size()) +
                     " corner displacements");
  base.triangles.resize(Eigen::Index(nf), 3);
  base.corner_uv.resize(nf);
  if (!d.empty()) base.corner_d.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    if (base.face_segment[f] < 0 || base.face_segment[f] >= segments)
      throw InputError("invalid base mesh in the SDM header: face " + std::to_string(f) + " names segment " +
                       std::to_string(base.face_segment[f]) + " of " + std::to_string(segments));
    for (int c = 0; c < 3; ++c) {
      if (tris[3 * f + c] < 0) throw InputError("invalid base mesh in the SDM header: negative vertex index");
      base.triangles(Eigen::Index(f), c) = tris[3 * f + c];
      base.corner_uv[f][c] = {uv[6 * f + 2 * c], uv[6 * f + 2 * c + 1]};
      if (!base.corner_uv[f][c].allFinite())
        throw InputError("invalid base mesh in the SDM header: face " + std::to_string(f) + " has NaN or infinite texel coordinates");
      if (!d.empty()) {
        base.corner_d[f][c] = d[3 * f + c];
        if (!std::isfinite(d[3 * f + c]))
          throw InputError("invalid base mesh in the SDM header: face " + std::to_string(f) + " has a NaN or infinite corner displacement");
      }
    }
  }
  for (size_t k = 0; k < base.flat_faces.size(); ++k)
    if (base.flat_faces[k] < 0 || size_t(base.flat_faces[k]) >= nf || (k > 0 && base.flat_faces[k] <= base.flat_faces[k - 1]))
      throw InputError("invalid base mesh in the SDM header: flat face " + std::to_string(base.flat_faces[k]) +
                       " is out of range 0.." + std::to_string(nf - 1) + " or out of order");
  check_base_topology(base.triangles);
  return base;
}

}  // namespace sdm
