#include "libstm/mesh/drop_small_parts.h"

#include "libstm/core/errors.h"
#include "libstm/core/union_find.h"

#include <cmath>

namespace sdm {
namespace {

std::string part_line(int faces, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  return "a part of " + std::to_string(faces) + " faces, " + number((hi - lo).norm()) + " across, at (" + number(c.x()) + ", " +
         number(c.y()) + ", " + number(c.z()) + ")";
}

void check_fraction(double fraction) {
  if (!(fraction >= 0) || !std::isfinite(fraction)) throw InputError("--min-part must be a fraction >= 0, got " + number(fraction));
}

}  // namespace

std::vector<std::string> drop_small_soup_parts(MeshSoup& soup, double fraction, std::vector<int>* kept_faces) {
  check_fraction(fraction);
  const int nv = int(soup.points.size());
  auto in_range = [&](const std::array<int, 3>& t) { return t[0] >= 0 && t[0] < nv && t[1] >= 0 && t[1] < nv && t[2] >= 0 && t[2] < nv; };
  UnionFind parts(size_t(std::max(nv, 1)));
  for (const auto& t : soup.triangles)
    if (in_range(t)) parts.unite(t[0], t[1]), parts.unite(t[0], t[2]);
  std::vector<Eigen::Vector3d> lo(size_t(nv), Eigen::Vector3d::Constant(INFINITY)), hi(size_t(nv), Eigen::Vector3d::Constant(-INFINITY));
  std::vector<int> faces(size_t(nv), 0);
  Eigen::Vector3d all_lo = Eigen::Vector3d::Constant(INFINITY), all_hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const auto& t : soup.triangles) {
    if (!in_range(t)) continue;
    const int r = parts.find(t[0]);
    ++faces[size_t(r)];
    for (int v : t) {
      const Eigen::Vector3d& p = soup.points[size_t(v)];
      lo[size_t(r)] = lo[size_t(r)].cwiseMin(p), hi[size_t(r)] = hi[size_t(r)].cwiseMax(p);
      all_lo = all_lo.cwiseMin(p), all_hi = all_hi.cwiseMax(p);
    }
  }
  const double limit = fraction * (all_hi - all_lo).norm();
  // (NaN sizes compare false: such parts stay.)
  auto dropped = [&](int r) { return (hi[size_t(r)] - lo[size_t(r)]).norm() < limit; };
  std::vector<std::string> lines;
  for (int r = 0; r < nv; ++r)
    if (faces[size_t(r)] > 0 && parts.find(r) == r && dropped(r)) lines.push_back(part_line(faces[size_t(r)], lo[size_t(r)], hi[size_t(r)]));
  if (lines.empty()) return lines;
  size_t kept = 0;
  if (kept_faces) kept_faces->clear();
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (in_range(soup.triangles[f]) && dropped(parts.find(soup.triangles[f][0]))) continue;
    if (kept_faces) kept_faces->push_back(int(f));
    if (!soup.uv.empty())
      for (size_t c = 0; c < 3; ++c) soup.uv[3 * kept + c] = soup.uv[3 * f + c];
    soup.triangles[kept++] = soup.triangles[f];
  }
  if (kept == 0) throw InputError("--min-part " + number(fraction) + " drops every part of the mesh");
  soup.triangles.resize(kept);
  if (!soup.uv.empty()) soup.uv.resize(3 * kept);
  return lines;
}

}  // namespace sdm
