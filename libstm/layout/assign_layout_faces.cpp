#include "libstm/layout/assign_layout_faces.h"

#include "libstm/layout/segments.h"

#include <array>

namespace sdm {

std::vector<int> assign_faces(const Mesh& mesh, const Layout& L, const Skeleton& skeleton) {
  std::vector<double> radius;
  radius.reserve(L.segments.size());
  std::vector<std::array<double, 2>> extension;  // per edge, at edges[e][0] and edges[e][1]
  for (size_t s = 0; s < L.segments.size(); ++s) {
    const LayoutSegment& g = L.segments[s];
    radius.push_back(g.radius);
    const bool same = s >= skeleton.edges.size() || skeleton.edges[s][0] == g.a;
    if (L.assignment >= 3) extension.push_back({same ? g.extend_a : g.extend_b, same ? g.extend_b : g.extend_a});
  }
  return assign_faces_with_radii(mesh, skeleton, radius, L.assignment >= 2, extension);
}

std::vector<int> assign_faces(const Mesh& mesh, const Layout& L) { return assign_faces(mesh, L, L.skeleton); }

}  // namespace sdm
