#include "libstm/layout/l2_stretch.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

#include <cmath>

namespace sdm {

double l2_stretch(const Mesh& mesh, const std::vector<int>& faces) {
  if (!mesh.has_halfedge_texcoords2D()) throw InputError("l2_stretch needs texture coordinates");
  std::vector<int> fl = faces;
  if (fl.empty())
    for (auto f : mesh.faces()) fl.push_back(f.idx());
  double A3 = 0, A2 = 0, sum = 0;
  for (int fi : fl) {
    const auto f = mesh.face_handle(fi);
    Eigen::Vector3d q[3];
    Eigen::Vector2d st[3];
    int k = 0;
    for (auto h : mesh.fh_range(f)) {
      q[k] = point(mesh, mesh.to_vertex_handle(h));
      const auto& t = mesh.texcoord2D(h);
      st[k] = {t[0], t[1]};
      ++k;
    }
    const double a3 = triangle_area(q[0], q[1], q[2]);
    const double a2 = 0.5 * ((st[1].x() - st[0].x()) * (st[2].y() - st[0].y()) - (st[2].x() - st[0].x()) * (st[1].y() - st[0].y()));
    A3 += a3;
    A2 += std::abs(a2);
    if (a2 == 0) continue;  // degenerate in the parameter domain: no finite stretch; skipped
    // Sander et al. 2001: Ss = dq/ds, St = dq/dt of the affine map (s, t) -> q.
    const Eigen::Vector3d Ss = (q[0] * (st[1].y() - st[2].y()) + q[1] * (st[2].y() - st[0].y()) + q[2] * (st[0].y() - st[1].y())) / (2 * a2);
    const Eigen::Vector3d St = (q[0] * (st[2].x() - st[1].x()) + q[1] * (st[0].x() - st[2].x()) + q[2] * (st[1].x() - st[0].x())) / (2 * a2);
    sum += a3 * 0.5 * (Ss.squaredNorm() + St.squaredNorm());
  }
  if (!(A3 > 0) || !(A2 > 0)) return 0;
  // Scaling the domain by k (area by k^2) divides the squared stretch by k^2: A2 k^2 = A3.
  return std::sqrt(sum / A3 * (A2 / A3));
}

}  // namespace sdm
