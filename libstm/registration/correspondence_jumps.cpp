#include "libstm/registration/correspondence_jumps.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

#include <string>

namespace sdm {

CorrespondenceJumps correspondence_jumps(const Mesh& source, const Mesh& target, const std::vector<SourcePoint>& assigned, double distance) {
  if (assigned.size() != target.n_vertices())
    throw InputError("correspondence_jumps: " + std::to_string(assigned.size()) + " source points for " + std::to_string(target.n_vertices()) +
                     " target vertices");
  std::vector<Eigen::Vector3d> at(assigned.size());
  for (size_t v = 0; v < assigned.size(); ++v) {
    const SourcePoint& s = assigned[v];
    if (s.face < 0 || size_t(s.face) >= source.n_faces())
      throw InputError("correspondence_jumps: target vertex " + std::to_string(v) + " names source face " + std::to_string(s.face));
    int k = 0;
    at[v].setZero();
    for (auto u : source.fv_range(source.face_handle(s.face))) at[v] += s.barycentric[k++] * point(source, u);
  }
  std::vector<double> area(target.n_vertices(), 0.0);
  double total = 0;
  for (auto f : target.faces()) {
    auto h = target.halfedge_handle(f);
    const double a = triangle_area(point(target, target.from_vertex_handle(h)), point(target, target.to_vertex_handle(h)),
                                   point(target, target.to_vertex_handle(target.next_halfedge_handle(h))));
    for (auto u : target.fv_range(f)) area[size_t(u.idx())] += a / 3;
    total += a;
  }
  CorrespondenceJumps j;
  double jumping = 0, largest = -1;
  for (auto v : target.vertices()) {
    int neighbours = 0, far = 0;
    for (auto u : target.vv_range(v)) ++neighbours, far += (at[size_t(u.idx())] - at[size_t(v.idx())]).norm() > distance;
    if (neighbours == 0 || 2 * far <= neighbours) continue;
    ++j.vertices, jumping += area[size_t(v.idx())];
    if (area[size_t(v.idx())] > largest) largest = area[size_t(v.idx())], j.example = v.idx();
  }
  j.area_share = total > 0 ? jumping / total : 0;
  return j;
}

}  // namespace sdm
