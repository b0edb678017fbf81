#include "libstm/layout/atlas_triangles.h"

#include "libstm/core/errors.h"

#include <algorithm>

namespace sdm {

namespace {

// Local (u, v) of a face's corners, unwrapped across phi = 0 (see AtlasTriangle).
std::array<Eigen::Vector2d, 3> face_local(const Layout& L, int s, const std::array<Eigen::Vector3d, 3>& p, bool* seam) {
  const LayoutSegment& g = L.segments[s];
  const CapsuleFrame f = capsule_frame(L, s);
  const double h = g.h;
  std::array<CapsuleUV, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = capsule_uv(f, g.w, h, g.d, p[k]);
  // A corner on the axis (a pole) has no angle: it takes its neighbours'.
  const double eps = 1e-9 * std::max(g.radius + g.length, 1e-300);
  std::array<double, 3> u{c[0].u, c[1].u, c[2].u};
  std::vector<int> ok;
  for (int k = 0; k < 3; ++k)
    if (c[k].rho > eps) ok.push_back(k);
  if (!ok.empty()) {
    // Keep the largest circular gap outside the triangle.
    std::sort(ok.begin(), ok.end(), [&](int i, int j) { return u[i] < u[j]; });
    const int n = int(ok.size());
    int gap_after = n - 1;  // the gap from ok[n-1] around to ok[0]
    double gap = u[ok[0]] + h - u[ok[n - 1]];
    for (int i = 0; i + 1 < n; ++i)
      if (u[ok[i + 1]] - u[ok[i]] > gap) gap = u[ok[i + 1]] - u[ok[i]], gap_after = i;
    for (int i = 0; i <= gap_after && gap_after != n - 1; ++i) u[ok[i]] += h;
    double lo = u[ok[0]], hi = lo, mean = 0;
    for (int k : ok) lo = std::min(lo, u[k]), hi = std::max(hi, u[k]), mean += u[k];
    mean /= n;
    // Past h: either stay there or shift down by h, whichever leaves less outside [0, h].
    if (hi > h && h - lo < hi - h) {
      for (int k : ok) u[k] -= h;
      mean -= h;
      lo -= h, hi -= h;
    }
    for (int k = 0; k < 3; ++k)
      if (c[k].rho <= eps) u[k] = mean;
    if (seam) *seam = lo < 0 || hi > h;
  } else if (seam) {
    *seam = false;
  }
  return {Eigen::Vector2d(u[0], c[0].v), Eigen::Vector2d(u[1], c[1].v), Eigen::Vector2d(u[2], c[2].v)};
}

}  // namespace

std::vector<AtlasTriangle> atlas_triangles(const Mesh& mesh, const Layout& L, const std::vector<int>& fs) {
  if (fs.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");
  std::vector<AtlasTriangle> out;
  out.reserve(mesh.n_faces() + mesh.n_faces() / 8);
  for (auto f : mesh.faces()) {
    const int s = fs[f.idx()];
    if (s < 0 || s >= int(L.segments.size())) throw InputError("face " + std::to_string(f.idx()) + " names no segment of the layout");
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    bool seam = false;
    AtlasTriangle t;
    t.face = f.idx(), t.segment = s, t.copy = 0;
    t.local = face_local(L, s, p, &seam);
    const LayoutSegment& g = L.segments[s];
    for (int i = 0; i < 3; ++i) t.atlas[i] = local_to_atlas(g, t.local[i].x(), t.local[i].y());
    out.push_back(t);
    if (!seam) continue;
    double hi = t.local[0].x();
    for (const auto& q : t.local) hi = std::max(hi, q.x());
    const double shift = hi > g.h ? -double(g.h) : double(g.h);
    t.copy = 1;
    for (int i = 0; i < 3; ++i) {
      t.local[i].x() += shift;
      t.atlas[i] = local_to_atlas(g, t.local[i].x(), t.local[i].y());
    }
    out.push_back(t);
  }
  return out;
}

}  // namespace sdm
