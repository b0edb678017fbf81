#include "libstm/render/render_skeleton.h"

#include <cmath>

namespace sdm {
namespace {

void add_ball(Mesh& m, const Eigen::Vector3d& c, double r) {
  const int rings = 6, sectors = 10;
  std::vector<Mesh::VertexHandle> v;
  v.push_back(m.add_vertex(Mesh::Point(c.x(), c.y(), c.z() + r)));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      const Eigen::Vector3d p = c + r * Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      v.push_back(m.add_vertex(Mesh::Point(p.x(), p.y(), p.z())));
    }
  v.push_back(m.add_vertex(Mesh::Point(c.x(), c.y(), c.z() - r)));
  auto ring = [&](int i, int j) { return v[1 + (i - 1) * sectors + (j % sectors)]; };
  for (int j = 0; j < sectors; ++j) m.add_face(v[0], ring(1, j), ring(1, j + 1));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.add_face(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      m.add_face(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  for (int j = 0; j < sectors; ++j) m.add_face(v.back(), ring(rings - 1, j + 1), ring(rings - 1, j));
}

void add_tube(Mesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) {
  const Eigen::Vector3d axis = b - a;
  if (axis.norm() <= 0) return;
  const Eigen::Vector3d n = axis.normalized();
  Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const int sectors = 10;
  std::vector<Mesh::VertexHandle> va, vb;
  for (int j = 0; j < sectors; ++j) {
    const double ph = 2 * M_PI * j / sectors;
    const Eigen::Vector3d d = r * (std::cos(ph) * e1 + std::sin(ph) * e2);
    va.push_back(m.add_vertex(Mesh::Point((a + d).x(), (a + d).y(), (a + d).z())));
    vb.push_back(m.add_vertex(Mesh::Point((b + d).x(), (b + d).y(), (b + d).z())));
  }
  for (int j = 0; j < sectors; ++j) {
    const int k = (j + 1) % sectors;
    m.add_face(va[j], va[k], vb[k]);
    m.add_face(va[j], vb[k], vb[j]);
  }
}

}  // namespace

Mesh skeleton_tubes(const Skeleton& s, double radius) {
  Mesh m;
  const std::vector<int> deg = s.degrees();
  for (const auto& e : s.edges) add_tube(m, s.nodes[e[0]], s.nodes[e[1]], radius);
  for (size_t i = 0; i < s.nodes.size(); ++i) add_ball(m, s.nodes[i], (deg[i] == 2 ? 1.6 : 2.6) * radius);
  return m;
}

Image render_with_skeleton(GlContext& gl, const Mesh& mesh, const Skeleton& skeleton, RenderOptions options,
                           double surface_opacity) {
  if (!(options.bbox_min.array() <= options.bbox_max.array()).all()) bounding_box(mesh, options.bbox_min, options.bbox_max);
  const Image surface = render_mesh(gl, mesh, options);
  RenderOptions so = options;
  so.texture = nullptr;
  so.unlit = false;
  so.color = Eigen::Vector3f(0.85f, 0.12f, 0.10f);
  std::vector<uint8_t> mask;
  const Image bones = render_mesh(gl, skeleton_tubes(skeleton, 0.006 * (options.bbox_max - options.bbox_min).norm()), so, &mask);
  Image out = surface;
  for (size_t i = 0, n = size_t(out.width) * out.height; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const double bg = options.background[k];
      double c = bg + surface_opacity * (surface.pixels[4 * i + k] - bg);
      const double a = bones.pixels[4 * i + 3] / 255.0 * (mask[i] ? 1.0 : 0.0);
      c = (1 - a) * c + a * bones.pixels[4 * i + k];
      out.pixels[4 * i + k] = uint8_t(std::lround(std::clamp(c, 0.0, 255.0)));
    }
  return out;
}

}  // namespace sdm
