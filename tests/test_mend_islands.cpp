// Islands of a correspondence (mend_islands): a patch of the target whose source points jump to
// another part (touching limbs) is found and looked up again near what surrounds it.
#include "libstm/registration/mend_islands.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <catch2/catch.hpp>

#include <algorithm>

namespace {

// The identity correspondence of a mesh onto itself: every vertex on a face of its own, weight 1 at it.
std::vector<sdm::SourcePoint> identity(const sdm::Mesh& m) {
  std::vector<sdm::SourcePoint> out(m.n_vertices());
  for (auto v : m.vertices()) {
    const auto f = *m.vf_range(v).begin();
    int k = 0;
    for (auto c : m.fv_range(f)) {
      if (c == v) break;
      ++k;
    }
    out[size_t(v.idx())].face = f.idx();
    out[size_t(v.idx())].barycentric = Eigen::Vector3d::Unit(k);
  }
  return out;
}

Eigen::Vector3d at(const sdm::Mesh& m, const sdm::SourcePoint& q) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto c : m.fv_range(m.face_handle(q.face))) p += q.barycentric[k++] * sdm::point(m, c);
  return p;
}

}  // namespace

TEST_CASE("mend_islands: a patch mapped onto another branch is found and mapped back", "[mend_islands]") {
  const sdm::Mesh m = sdm::make_primitive("ypsilon", 1500);
  const sdm::Skeleton s = sdm::extract_skeleton(m);
  std::vector<sdm::SourcePoint> under = identity(m);
  std::vector<Eigen::Vector3d> points, placed;
  for (auto v : m.vertices()) points.push_back(sdm::point(m, v)), placed.push_back(sdm::point(m, v));

  // Right as it is: no island.
  const sdm::CorrespondenceIslands none = sdm::find_islands(m, s, m, under);
  CHECK(std::count(none.island_of.begin(), none.island_of.end(), -1) == long(m.n_vertices()));

  // The 20 vertices nearest one arm's tip take the point of the vertex farthest from it (another arm).
  const Eigen::Vector3d centre = (points[0] + points[1]) / 2;  // any point: find an extremity from it
  size_t tip = 0, far = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if ((points[i] - centre).norm() > (points[tip] - centre).norm()) tip = i;
  for (size_t i = 0; i < points.size(); ++i)
    if ((points[i] - points[tip]).norm() > (points[far] - points[tip]).norm()) far = i;
  std::vector<size_t> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return (points[a] - points[tip]).norm() < (points[b] - points[tip]).norm(); });
  std::vector<char> patch(points.size(), 0);
  for (size_t k = 0; k < 20; ++k) patch[order[k]] = 1, under[order[k]] = identity(m)[far];

  const sdm::CorrespondenceIslands islands = sdm::find_islands(m, s, m, under);
  REQUIRE(islands.island_of.size() == m.n_vertices());
  for (size_t i = 0; i < points.size(); ++i) {
    INFO("vertex " << i << (patch[i] ? " (in the patch)" : ""));
    CHECK((islands.island_of[i] >= 0) == bool(patch[i]));
  }
  REQUIRE(islands.allowed_faces.size() == 1);
  // The faces the island may take lie on its own arm: none of them holds the far vertex.
  for (auto f : m.vf_range(m.vertex_handle(int(far)))) CHECK(!islands.allowed_faces[0][size_t(f.idx())]);

  const int changed = sdm::mend_islands(m, placed, islands, points, islands.island_of, under);
  CHECK(changed == 20);
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) worst = std::max(worst, (at(m, under[i]) - points[i]).norm());
  CHECK(worst < 1e-9 * sdm::bounding_box_diagonal(m));
}
