#include "libstm/mesh/spatial_order.h"


#include <algorithm>
#include <cstdint>
#include <numeric>

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
std::vector<int> morton_order(const Mesh& mesh) {
  Eigen::Vector3d lo, hi;
  bounding_box(mesh, lo, hi);
  const double size = (hi - lo).maxCoeff();
  std::vector<std::pair<uint64_t, int>> code(mesh.n_vertices());
  for (auto v : mesh.vertices()) code[size_t(v.idx())] = {morton(point(mesh, v), lo, size), v.idx()};
  std::sort(code.begin(), code.end());
  std::vector<int> index(code.size());
  for (size_t i = 0; i < code.size(); ++i) index[size_t(code[i].second)] = int(i);
  return index;
}

}  // namespace

Mesh spatially_ordered(const Mesh& mesh) {
  const std::vector<int> index = morton_order(mesh);
  const size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
  MeshSoup soup;
  soup.points.resize(nv);
  for (auto v : mesh.vertices()) soup.points[size_t(index[size_t(v.idx())])] = point(mesh, v);
  const bool uv = mesh.has_halfedge_texcoords2D();
  std::vector<std::array<int, 3>> faces(nf);
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv(uv ? nf : 0);
  // Faces by their smallest new corner (a counting sort), then by the other two (ties keep the old
  // order): the order of sorting the sorted corner triples, in linear time.
  std::vector<std::array<int, 3>> key(nf);
  std::vector<size_t> start(nv + 1, 0);
  for (auto f : mesh.faces()) {
    const size_t i = size_t(f.idx());
    int c = 0;
    for (auto h : mesh.fh_range(f)) {
      faces[i][size_t(c)] = index[size_t(h.to().idx())];
      if (uv) corner_uv[i][size_t(c)] = Eigen::Vector2d(mesh.texcoord2D(h)[0], mesh.texcoord2D(h)[1]);
      ++c;
    }
    key[i] = faces[i];
    std::sort(key[i].begin(), key[i].end());
    ++start[size_t(key[i][0]) + 1];
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<size_t> order(nf);
  std::vector<size_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < nf; ++f) order[fill[size_t(key[f][0])]++] = f;
  for (size_t v = 0; v < nv; ++v)
    std::stable_sort(order.begin() + long(start[v]), order.begin() + long(start[v + 1]),
                     [&](size_t a, size_t b) { return key[a] < key[b]; });
  soup.triangles.reserve(nf);
  for (size_t f : order) {
    soup.triangles.push_back(faces[f]);
    if (uv)
      for (const auto& t : corner_uv[f]) soup.uv.push_back(t);
  }
  return build_mesh(soup);
}

bool scattered_numbering(const Mesh& mesh) {
  const size_t nf = mesh.n_faces(), step = std::max<size_t>(1, nf / 10000);
  std::vector<int> spread;
  for (size_t f = 0; f < nf; f += step) {
    int lo = INT32_MAX, hi = -1;
    for (auto v : mesh.fv_range(Mesh::FaceHandle(int(f)))) lo = std::min(lo, v.idx()), hi = std::max(hi, v.idx());
    spread.push_back(hi - lo);
  }
  if (spread.empty()) return false;
  std::nth_element(spread.begin(), spread.begin() + long(spread.size() / 2), spread.end());
  return double(spread[spread.size() / 2]) > 0.05 * double(mesh.n_vertices());
}

}  // namespace sdm
