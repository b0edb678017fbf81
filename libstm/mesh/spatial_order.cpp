#include "libstm/mesh/spatial_order.h"


#include <algorithm>
#include <cstdint>
#include <cmath>

namespace sdm {

namespace {

// The 21 low bits of x spread to every third bit.
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// Morton code of p in the box [lo, lo + size] at 21 bits per axis.
uint64_t morton(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, double size) {
  uint64_t code = 0;
  for (int k = 0; k < 3; ++k) {
    const double t = size > 0 ? (p[k] - lo[k]) / size : 0.0;
    code |= spread_bits(uint64_t(std::clamp(t, 0.0, 1.0) * double((1 << 21) - 1))) << k;
  }
  return code;
}

// Vertex i of the renumbering: the i-th along the Morton curve (ties by the old number).
std::vector<int> morton_order(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double size = points.empty() ? 0.0 : (hi - lo).maxCoeff();
  std::vector<std::pair<uint64_t, int>> code(points.size());
  for (size_t v = 0; v < points.size(); ++v) code[v] = {morton(points[v], lo, size), int(v)};
  std::sort(code.begin(), code.end());
  std::vector<int> index(code.size());
  for (size_t i = 0; i < code.size(); ++i) index[size_t(code[i].second)] = int(i);
  return index;
}

}  // namespace

MeshSoup spatially_ordered(const MeshSoup& soup) {
  const std::vector<int> index = morton_order(soup.points);
  const size_t nv = soup.points.size(), nf = soup.triangles.size();
  const bool uv = soup.uv.size() == 3 * nf && nf > 0;
  MeshSoup out;
  out.points.resize(nv);
  for (size_t v = 0; v < nv; ++v) out.points[size_t(index[v])] = soup.points[v];
  if (soup.colors.size() == nv) {
    out.colors.resize(nv);
    for (size_t v = 0; v < nv; ++v) out.colors[size_t(index[v])] = soup.colors[v];
  }
  // Faces by their smallest new corner (a counting sort), then by the other two (ties keep the old
  // order): the order of sorting the sorted corner triples, in linear time.
  std::vector<std::array<int, 3>> faces(nf), key(nf);
  std::vector<size_t> start(nv + 1, 0);
  for (size_t f = 0; f < nf; ++f) {
    for (size_t c = 0; c < 3; ++c) faces[f][c] = index[size_t(soup.triangles[f][c])];
    key[f] = faces[f];
    std::sort(key[f].begin(), key[f].end());
    ++start[size_t(key[f][0]) + 1];
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<size_t> order(nf);
  std::vector<size_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < nf; ++f) order[fill[size_t(key[f][0])]++] = f;
  for (size_t v = 0; v < nv; ++v)
    std::stable_sort(order.begin() + long(start[v]), order.begin() + long(start[v + 1]),
                     [&](size_t a, size_t b) { return key[a] < key[b]; });
  out.triangles.reserve(nf);
  for (size_t f : order) {
    out.triangles.push_back(faces[f]);
    if (uv)
      for (size_t c = 0; c < 3; ++c) out.uv.push_back(soup.uv[3 * f + c]);
  }
  return out;
}

Mesh spatially_ordered(const Mesh& mesh) {
  MeshSoup soup = mesh_to_soup(mesh);
  if (mesh.has_halfedge_texcoords2D())
    for (auto f : mesh.faces())
      for (auto h : mesh.fh_range(f)) soup.uv.emplace_back(mesh.texcoord2D(h)[0], mesh.texcoord2D(h)[1]);
  return build_mesh(spatially_ordered(soup));
}

bool scattered_numbering(const std::vector<std::array<int, 3>>& triangles, size_t vertices) {
  std::vector<int> spread;
  for (size_t f = 0, step = std::max<size_t>(1, triangles.size() / 10000); f < triangles.size(); f += step) {
    const auto& t = triangles[f];
    spread.push_back(std::max({t[0], t[1], t[2]}) - std::min({t[0], t[1], t[2]}));
  }
  if (spread.empty()) return false;
  std::nth_element(spread.begin(), spread.begin() + long(spread.size() / 2), spread.end());
  return double(spread[spread.size() / 2]) > 0.05 * double(vertices);
}

bool scattered_numbering(const Mesh& mesh) {
  // The same faces as the list version samples (fewer than 20,000 here, so it takes every one).
  std::vector<std::array<int, 3>> sample;
  for (size_t f = 0, step = std::max<size_t>(1, mesh.n_faces() / 10000); f < mesh.n_faces(); f += step) {
    std::array<int, 3> t{};
    int c = 0;
    for (auto v : mesh.fv_range(Mesh::FaceHandle(int(f)))) t[size_t(c++)] = v.idx();
    sample.push_back(t);
  }
  return scattered_numbering(sample, mesh.n_vertices());
}

}  // namespace sdm
