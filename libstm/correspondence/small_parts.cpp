#include "libstm/correspondence/small_parts.h"

#include "libstm/core/errors.h"
#include "libstm/core/union_find.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sdm {

namespace {

// Per vertex, its vertex-connected part (the representative's index).
std::vector<int> vertex_parts(const Mesh& mesh) {
  UnionFind uf(std::max<size_t>(mesh.n_vertices(), 1));
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    uf.unite(mesh.from_vertex_handle(h).idx(), mesh.to_vertex_handle(h).idx());
  }
  std::vector<int> part(mesh.n_vertices());
  for (auto v : mesh.vertices()) part[size_t(v.idx())] = uf.find(v.idx());
  return part;
}

// One line on a part left out: its vertices, its share of the mesh's area and its centre.
std::string part_line(const Mesh& mesh, const std::vector<int>& part, int id, double area, double total) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  int n = 0;
  for (auto v : mesh.vertices())
    if (part[size_t(v.idx())] == id) c += point(mesh, v), ++n;
  c /= std::max(n, 1);
  std::ostringstream s;
  s.precision(3);
  s << "a separate part of " << n << " vertices (" << 100 * area / std::max(total, 1e-300) << " % of the area, around (" << c.x() << ", "
    << c.y() << ", " << c.z() << "), vertex " << id << ")";
  return s.str();
}

}  // namespace

MainParts without_small_parts(const Mesh& mesh, const SmallPartOptions& opt) {
  MainParts out;
  const std::vector<int> part = vertex_parts(mesh);
  std::vector<double> area(mesh.n_vertices(), 0.0);
  std::vector<Eigen::Vector3d> lo(mesh.n_vertices(), Eigen::Vector3d::Constant(INFINITY)), hi(mesh.n_vertices(), Eigen::Vector3d::Constant(-INFINITY));
  for (auto f : mesh.faces()) area[size_t(part[size_t(mesh.fv_range(f).begin()->idx())])] += face_area(mesh, f);
  for (auto v : mesh.vertices()) {
    const size_t p = size_t(part[size_t(v.idx())]);
    lo[p] = lo[p].cwiseMin(point(mesh, v)), hi[p] = hi[p].cwiseMax(point(mesh, v));
  }
  const double largest = area.empty() ? 0 : *std::max_element(area.begin(), area.end());
  double total = 0;
  for (double a : area) total += a;
  const double diagonal = bounding_box_diagonal(mesh);
  std::vector<char> small(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices()) {
    const int p = part[size_t(v.idx())];
    if (p != v.idx()) continue;  // once per part, at its representative
    const double size = (hi[size_t(p)] - lo[size_t(p)]).norm();
    if (area[size_t(p)] < largest && area[size_t(p)] < opt.area_fraction * largest && size < opt.size_fraction * diagonal) {
      small[size_t(p)] = 1;
      out.left_out.push_back(part_line(mesh, part, p, area[size_t(p)], total));
    }
  }
  if (out.left_out.empty()) {
    out.mesh = mesh;
    for (auto v : mesh.vertices()) out.vertex_of.push_back(v.idx());
    for (auto f : mesh.faces()) out.face_of.push_back(f.idx());
    return out;
  }
  // The kept faces as a soup (uv per corner, as build_mesh reads it), points in input order.
  MeshSoup soup;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (auto v : mesh.vertices())
    if (!small[size_t(part[size_t(v.idx())])]) index[size_t(v.idx())] = int(soup.points.size()), soup.points.push_back(point(mesh, v)),
                                               out.vertex_of.push_back(v.idx());
  const bool uv = mesh.has_halfedge_texcoords2D();
  for (auto f : mesh.faces()) {
    if (small[size_t(part[size_t(mesh.fv_range(f).begin()->idx())])]) continue;
    std::array<int, 3> t{};
    int c = 0;
    for (auto h : mesh.fh_range(f)) {
      t[size_t(c++)] = index[size_t(h.to().idx())];
      if (uv) soup.uv.push_back(Eigen::Vector2d(mesh.texcoord2D(h)[0], mesh.texcoord2D(h)[1]));
    }
    soup.triangles.push_back(t);
    out.face_of.push_back(f.idx());
  }
  out.mesh = build_mesh(soup);
  return out;
}

MainParts main_parts(const Mesh& mesh, const std::string& what, bool strict, const Progress& progress) {
  MainParts parts = without_small_parts(mesh);
  if (parts.reduced() && strict)
    throw InputError("'" + what + "' has " + parts.left_out.front() + " beside its main part (refused by --strict): its skeleton gets a "
                     "part of its own and the branchings differ. Fix: leave out --strict to match the main parts alone");
  for (const auto& line : parts.left_out)
    report_progress(progress, "warning: '" + what + "': " + line + " left out of the matching; its vertices take the nearest vertex's source point");
  return parts;
}

std::vector<SourcePoint> onto_input_source(const MainParts& source, const Mesh& input, std::vector<SourcePoint> points) {
  if (!source.reduced()) return points;
  for (auto& p : points) {
    if (p.face < 0) continue;
    const int f = source.face_of[size_t(p.face)];
    int corner[3], c = 0;
    for (auto v : source.mesh.fv_range(source.mesh.face_handle(p.face))) corner[c++] = source.vertex_of[size_t(v.idx())];
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    c = 0;
    for (auto v : input.fv_range(input.face_handle(f))) {
      for (int k = 0; k < 3; ++k)
        if (corner[k] == v.idx()) w[c] = p.barycentric[k];
      ++c;
    }
    p.face = f, p.barycentric = w;
  }
  return points;
}

std::vector<SourcePoint> onto_input_target(const MainParts& target, const Mesh& input, const std::vector<SourcePoint>& points) {
  if (!target.reduced()) return points;
  std::vector<SourcePoint> out(input.n_vertices());
  std::vector<char> kept(input.n_vertices(), 0);
  for (size_t i = 0; i < target.vertex_of.size(); ++i) out[size_t(target.vertex_of[i])] = points[i], kept[size_t(target.vertex_of[i])] = 1;
  for (auto v : input.vertices()) {
    if (kept[size_t(v.idx())]) continue;
    double best = INFINITY;
    for (size_t i = 0; i < target.vertex_of.size(); ++i) {
      const double d = (point(input, input.vertex_handle(target.vertex_of[i])) - point(input, v)).squaredNorm();
      if (d < best) best = d, out[size_t(v.idx())] = points[i];
    }
  }
  return out;
}

}  // namespace sdm
