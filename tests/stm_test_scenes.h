#pragma once
// Scenes shared by the atlas and STM rendering tests: a cylinder along +y with a hand-made
// one-segment skeleton and a procedural texture that is continuous all the way around it.
#include "libstm/core/image.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"

#include <cmath>

namespace stm_test {

// Colour (in [0, 1]) of the procedural texture at (s, t): periodic in s, smooth in both.
inline Eigen::Vector3d procedural(double s, double t) {
  const double tau = 2 * M_PI;
  return {0.5 + 0.4 * std::sin(tau * 2 * s), 0.5 + 0.4 * std::cos(tau * (3 * s + 2 * t)), 0.5 + 0.4 * std::sin(tau * 2 * t)};
}

inline sdm::Image procedural_image(int w, int h) {
  sdm::Image img(w, h, 4, 255);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d c = procedural((x + 0.5) / w, (h - 1 - y + 0.5) / h);  // row 0 is the top (t = 1)
      for (int k = 0; k < 3; ++k) img.at(x, y)[k] = uint8_t(std::lround(255 * c[k]));
    }
  return img;
}

// The texture coordinate of a point of the cylinder: s = angle around +y from `zero` (a unit
// vector orthogonal to y) over 2 pi, t = height on the side, radius on the caps (continuous).
inline Eigen::Vector2d cylinder_st(const Eigen::Vector3d& p, const Eigen::Vector3d& zero) {
  const Eigen::Vector3d y(0, 1, 0), other = y.cross(zero);
  double s = std::atan2(p.dot(other), p.dot(zero)) / (2 * M_PI);
  if (s < 0) s += 1;
  const double r = std::hypot(p.x(), p.z());
  double t = 0.25 * (p.y() + 2);                   // side, y in [-1, 1] -> [0.25, 0.75]
  if (p.y() <= -1 + 1e-9) t = 0.25 * r;            // bottom cap
  else if (p.y() >= 1 - 1e-9) t = 1 - 0.25 * r;    // top cap
  return {s, t};
}

struct CylinderScene {
  sdm::Mesh mesh;      // axis +y, radius 1, y in [-1, 1], with uv (cylinder_st, unwrapped per face)
  sdm::Layout layout;  // one segment, nodes at y = -0.5 and y = 0.5
  Eigen::Vector3d uv_zero;  // where the mesh's own uv has s = 0: opposite the STM seam
};

// uv_zero is chosen opposite the layout's phi = 0 direction, so that the STM seam falls where the
// source texture is continuous and the two seams never meet.
inline CylinderScene cylinder_scene(int atlas_size, int margin) {
  CylinderScene sc;
  const sdm::Mesh z = sdm::make_primitive("cylinder");
  sc.mesh = z;
  for (auto v : sc.mesh.vertices()) {  // (x, y, z) -> (y, z, x): axis z becomes y, orientation kept
    const auto p = z.point(v);
    sc.mesh.set_point(v, sdm::Mesh::Point(p[1], p[2], p[0]));
  }
  sdm::Skeleton sk;
  sk.nodes = {Eigen::Vector3d(0, -0.5, 0), Eigen::Vector3d(0, 0.5, 0)};
  sk.edges = {{0, 1}};
  for (auto v : sc.mesh.vertices()) sk.vertex_node.push_back(sc.mesh.point(v)[1] < 0 ? 0 : 1);
  sdm::LayoutOptions lo;
  lo.size = atlas_size;
  lo.margin = margin;
  sc.layout = sdm::compute_layout(sc.mesh, sk, lo);
  sc.uv_zero = -sc.layout.segments[0].e1;
  sc.mesh.request_halfedge_texcoords2D();
  for (auto f : sc.mesh.faces()) {
    double s0 = -1;
    for (auto h : sc.mesh.fh_range(f)) {
      Eigen::Vector2d st = cylinder_st(sdm::point(sc.mesh, sc.mesh.to_vertex_handle(h)), sc.uv_zero);
      if (s0 < 0) s0 = st.x();
      st.x() -= std::round(st.x() - s0);  // unwrapped within the face; the texture repeats
      sc.mesh.set_texcoord2D(h, sdm::Mesh::TexCoord2D(st.x(), st.y()));
    }
  }
  return sc;
}

}  // namespace sdm_test
