#include "libstm/registration/mend_islands.h"

#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <numeric>

namespace sdm {

namespace {

// Union-find over the target's vertices.
int root(std::vector<int>& parent, int x) {
  while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
  return x;
}

// Per node, its neighbours in the skeleton.
std::vector<std::vector<int>> node_neighbours(const Skeleton& s) {
  std::vector<std::vector<int>> adj(s.nodes.size());
  for (const auto& e : s.edges) adj[size_t(e[0])].push_back(e[1]), adj[size_t(e[1])].push_back(e[0]);
  return adj;
}

// The source faces of the nodes in `seed` and of those within `rings` skeleton edges of them.
std::vector<char> faces_near_nodes(const Mesh& source, const Skeleton& skeleton, const std::vector<std::vector<int>>& adj,
                                   std::vector<int> nodes, int rings) {
  std::vector<char> in(skeleton.nodes.size(), 0);
  for (int n : nodes) in[size_t(n)] = 1;
  for (int r = 0; r < rings; ++r) {
    std::vector<int> next;
    for (int n : nodes)
      for (int m : adj[size_t(n)])
        if (!in[size_t(m)]) in[size_t(m)] = 1, next.push_back(m);
    nodes = std::move(next);
  }
  std::vector<char> faces(source.n_faces(), 0);
  for (auto f : source.faces())
    for (auto v : source.fv_range(f))
      if (in[size_t(skeleton.vertex_node[size_t(v.idx())])]) faces[size_t(f.idx())] = 1;
  return faces;
}

}  // namespace

CorrespondenceIslands find_islands(const Mesh& source, const Skeleton& skeleton, const Mesh& target,
                                   const std::vector<SourcePoint>& under, const IslandOptions& opt) {
  const size_t n = target.n_vertices();
  CorrespondenceIslands out;
  out.island_of.assign(n, -1);
  if (under.size() != n || skeleton.vertex_node.size() != source.n_vertices() || n == 0) return out;
  std::vector<Eigen::Vector3d> at(n);
  std::vector<int> node(n);
  for (size_t i = 0; i < n; ++i)
    at[i] = position_of(source, under[i]), node[i] = skeleton.vertex_node[size_t(heaviest_corner(source, under[i]))];
  const double tear = opt.tear * bounding_box_diagonal(source);
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (auto e : target.edges()) {
    const auto h = target.halfedge_handle(e, 0);
    const int a = target.from_vertex_handle(h).idx(), b = target.to_vertex_handle(h).idx();
    if ((at[size_t(a)] - at[size_t(b)]).norm() <= tear) parent[size_t(root(parent, a))] = root(parent, b);
  }
  std::vector<int> size(n, 0);
  for (size_t i = 0; i < n; ++i) ++size[size_t(root(parent, int(i)))];
  const double most = opt.max_share * double(n);
  // Each small part's surroundings: the nodes of the vertices across its torn edges.
  std::vector<int> island_of_root(n, -1);
  std::vector<std::vector<int>> around;
  for (auto e : target.edges()) {
    const auto h = target.halfedge_handle(e, 0);
    const int v[2] = {target.from_vertex_handle(h).idx(), target.to_vertex_handle(h).idx()};
    const int r[2] = {root(parent, v[0]), root(parent, v[1])};
    if (r[0] == r[1]) continue;
    for (int s = 0; s < 2; ++s) {
      if (double(size[size_t(r[s])]) > most || size[size_t(r[s])] >= size[size_t(r[1 - s])]) continue;
      int& id = island_of_root[size_t(r[s])];
      if (id < 0) id = int(around.size()), around.emplace_back();
      around[size_t(id)].push_back(node[size_t(v[1 - s])]);
    }
  }
  const auto adj = node_neighbours(skeleton);
  for (auto& nodes : around) {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    out.allowed_faces.push_back(faces_near_nodes(source, skeleton, adj, nodes, opt.node_rings));
  }
  for (size_t i = 0; i < n; ++i) out.island_of[i] = island_of_root[size_t(root(parent, int(i)))];
  return out;
}

int mend_islands(const Mesh& source, const std::vector<Eigen::Vector3d>& placed, const CorrespondenceIslands& islands,
                 const std::vector<Eigen::Vector3d>& points, const std::vector<int>& point_island, std::vector<SourcePoint>& under) {
  if (islands.allowed_faces.empty()) return 0;
  const Eigen::MatrixX3i F = face_matrix(source);
  Eigen::MatrixX3d P(placed.size(), 3);
  for (size_t v = 0; v < placed.size(); ++v) P.row(Eigen::Index(v)) = placed[v].transpose();
  const TriangleBvh bvh(P, F);
  int changed = 0;
  for (size_t i = 0; i < points.size() && i < point_island.size() && i < under.size(); ++i) {
    const int id = point_island[i];
    if (id < 0 || size_t(id) >= islands.allowed_faces.size()) continue;
    const auto c = bvh.closest_point_among(points[i], islands.allowed_faces[size_t(id)]);
    if (c.face < 0 || c.face == under[i].face) continue;
    under[i] = {c.face, barycentric(c.point, P.row(F(c.face, 0)), P.row(F(c.face, 1)), P.row(F(c.face, 2)))};
    ++changed;
  }
  return changed;
}

}  // namespace sdm
