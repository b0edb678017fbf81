#include "libstm/mesh/drop_small_parts.h"

#include "libstm/core/errors.h"
#include "libstm/core/union_find.h"

#include <cmath>

namespace sdm {

DroppedParts drop_small_parts(const Mesh& mesh, double fraction) {
  if (!(fraction >= 0) || !std::isfinite(fraction)) throw InputError("--min-part must be a fraction >= 0, got " + number(fraction));
  UnionFind parts(mesh.n_vertices());
  for (auto f : mesh.faces()) {
    auto fv = mesh.cfv_begin(f);
    const int a = fv->idx();
    for (++fv; fv.is_valid(); ++fv) parts.unite(a, fv->idx());
  }
  const int nv = int(mesh.n_vertices());
  std::vector<Eigen::Vector3d> lo(nv, Eigen::Vector3d::Constant(INFINITY)), hi(nv, Eigen::Vector3d::Constant(-INFINITY));
  std::vector<int> faces(nv, 0);
  for (auto v : mesh.vertices()) {
    const int r = parts.find(v.idx());
    lo[r] = lo[r].cwiseMin(point(mesh, v)), hi[r] = hi[r].cwiseMax(point(mesh, v));
  }
  for (auto f : mesh.faces()) faces[parts.find(mesh.cfv_begin(f)->idx())]++;
  const double limit = fraction * bounding_box_diagonal(mesh);
  DroppedParts out;
  std::vector<Mesh::VertexHandle> vh(nv);
  for (auto v : mesh.vertices()) {
    const int r = parts.find(v.idx());
    if ((hi[r] - lo[r]).norm() >= limit) vh[v.idx()] = out.mesh.add_vertex(mesh.point(v));
    else if (r == v.idx()) {
      const Eigen::Vector3d c = 0.5 * (lo[r] + hi[r]);
      out.dropped.push_back("a part of " + std::to_string(faces[r]) + " faces, " + number((hi[r] - lo[r]).norm()) + " across, at (" +
                            number(c.x()) + ", " + number(c.y()) + ", " + number(c.z()) + ")");
    }
  }
  if (out.mesh.n_vertices() == 0) throw InputError("--min-part " + number(fraction) + " drops every part of the mesh");
  const bool uv = mesh.has_halfedge_texcoords2D();
  if (uv) out.mesh.request_halfedge_texcoords2D();
  for (auto f : mesh.faces()) {
    std::vector<Mesh::VertexHandle> corners;
    for (auto v : mesh.fv_range(f)) corners.push_back(vh[v.idx()]);
    if (!corners[0].is_valid()) continue;
    const auto nf = out.mesh.add_face(corners);
    if (!uv || !nf.is_valid()) continue;
    auto h = mesh.cfh_begin(f);
    for (auto g = out.mesh.fh_begin(nf); g.is_valid(); ++g, ++h) out.mesh.set_texcoord2D(*g, mesh.texcoord2D(*h));
  }
  return out;
}

}  // namespace sdm
