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

}  // namespace

Mesh spatially_ordered(const Mesh& mesh) {
  Eigen::Vector3d lo, hi;
  bounding_box(mesh, lo, hi);
  const double size = (hi - lo).maxCoeff();
  const size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
  std::vector<uint64_t> code(nv);
  for (auto v : mesh.vertices()) code[size_t(v.idx())] = morton(point(mesh, v), lo, size);
  std::vector<int> order(nv), index(nv);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return code[size_t(a)] < code[size_t(b)]; });
  for (size_t i = 0; i < nv; ++i) index[size_t(order[i])] = int(i);

  MeshSoup soup;
  soup.points.reserve(nv);
  for (int v : order) soup.points.push_back(point(mesh, Mesh::VertexHandle(v)));
  const bool uv = mesh.has_halfedge_texcoords2D();
  std::vector<std::array<int, 3>> faces(nf);
  std::vector<std::array<Eigen::Vector2d, 3>> corner_uv(uv ? nf : 0);
  for (auto f : mesh.faces()) {
    int c = 0;
    for (auto h : mesh.fh_range(f)) {
      faces[size_t(f.idx())][size_t(c)] = index[size_t(h.to().idx())];
      if (uv) corner_uv[size_t(f.idx())][size_t(c)] = Eigen::Vector2d(mesh.texcoord2D(h)[0], mesh.texcoord2D(h)[1]);
      ++c;
    }
  }
  auto sorted = [&](size_t f) {
    std::array<int, 3> s = faces[f];
    std::sort(s.begin(), s.end());
    return s;
  };
  std::vector<size_t> face_order(nf);
  std::iota(face_order.begin(), face_order.end(), size_t(0));
  std::stable_sort(face_order.begin(), face_order.end(), [&](size_t a, size_t b) { return sorted(a) < sorted(b); });
  soup.triangles.reserve(nf);
  for (size_t f : face_order) {
    soup.triangles.push_back(faces[f]);
    if (uv)
      for (const auto& t : corner_uv[f]) soup.uv.push_back(t);
  }
  return build_mesh(soup);
}

}  // namespace sdm
