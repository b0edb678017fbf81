// A skeleton carried onto another tessellation of the same shape (carry_skeleton): nodes through
// the registration, every new vertex to the node its surface point belongs to in the source.
#include "libstm/registration/carry_skeleton.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/mesh/primitives.h"
#include "libstm/registration/register_surfaces.h"
#include "libstm/layout/segments.h"

#include "synthetic_shapes.h"

#include <catch2/catch.hpp>

#include <cmath>

TEST_CASE("a skeleton carried onto a moved retessellation keeps its graph and its vertex regions", "[carry_skeleton]") {
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1500);
  const sdm::Skeleton sa = sdm::extract_skeleton(a);
  // b: another tessellation, turned 90 degrees about z, scaled and moved.
  sdm::Similarity T;
  T.scale = 2;
  T.rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation = {1, 2, 3};
  const sdm::Mesh b = synth::moved(synth::remeshed(a, 0.8), [&](const Eigen::Vector3d& p) { return T(p); });
  REQUIRE(b.n_vertices() != a.n_vertices());
  const sdm::Skeleton sb = sdm::carry_skeleton(a, sa, b, T);
  CHECK(sb.edges == sa.edges);
  REQUIRE(sb.nodes.size() == sa.nodes.size());
  for (size_t i = 0; i < sa.nodes.size(); ++i) CHECK((sb.nodes[i] - T(sa.nodes[i])).norm() < 1e-12);
  REQUIRE(sb.vertex_node.size() == b.n_vertices());
  std::vector<int> count(sb.nodes.size(), 0);
  for (int x : sb.vertex_node) ++count[x];
  CHECK(*std::min_element(count.begin(), count.end()) >= 1);
  // Every vertex of b takes the node of the source vertex nearest to its preimage: that node lies
  // no further from the preimage than the source's own vertices there lie from theirs (plus an edge).
  const sdm::Similarity Ti = T.inverse();
  double worst_source = 0;
  for (auto v : a.vertices()) worst_source = std::max(worst_source, (sdm::point(a, v) - sa.nodes[sa.vertex_node[v.idx()]]).norm());
  double edge = 0;
  for (auto e : a.edges()) edge = std::max(edge, a.calc_edge_length(e));
  int far = 0;
  for (auto v : b.vertices())
    far += (Ti(sdm::point(b, v)) - sa.nodes[sb.vertex_node[v.idx()]]).norm() > worst_source + edge;
  CHECK(far == 0);
  // The segments of both models see the same surface: face areas per segment agree within a few percent.
  const std::vector<int> fa = sdm::assign_faces(a, sa), fb = sdm::assign_faces(b, sb);
  std::vector<double> area_a(sa.edges.size(), 0), area_b(sa.edges.size(), 0);
  double total = 0;
  for (auto f : a.faces()) area_a[fa[f.idx()]] += a.calc_face_area(f), total += a.calc_face_area(f);
  for (auto f : b.faces()) area_b[fb[f.idx()]] += b.calc_face_area(f) / (T.scale * T.scale);
  for (size_t s = 0; s < sa.edges.size(); ++s) {
    INFO("segment " << s << ": area " << area_a[s] << " in the source, " << area_b[s] << " carried");
    CHECK(std::abs(area_a[s] - area_b[s]) < 0.05 * area_a[s] + 0.005 * total);
  }
}
