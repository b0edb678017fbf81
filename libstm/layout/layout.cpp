#include "libstm/layout/layout.h"

namespace sdm {

CapsuleFrame capsule_frame(const Layout& L, int s) {
  const LayoutSegment& g = L.segments.at(s);
  const Eigen::Vector3d &a = L.skeleton.nodes.at(g.a), &b = L.skeleton.nodes.at(g.b);
  return {a - g.extend_a * g.radius * g.axis, b + g.extend_b * g.radius * g.axis, g.e1, g.e2};
}

double capsule_length(const LayoutSegment& g) { return g.length + (g.extend_a + g.extend_b) * g.radius + 2 * g.cap; }

Eigen::Vector2d local_to_atlas(const LayoutSegment& g, double u, double v) {
  return g.rotated ? Eigen::Vector2d(g.x + u, g.y + v) : Eigen::Vector2d(g.x + v, g.y + u);
}

}  // namespace sdm
