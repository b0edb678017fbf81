// Merging a cloud's duplicates, measuring it and refusing what no skeleton comes from (point_cloud.h).
#include "libstm/core/errors.h"
#include "libstm/geometry/point_kdtree.h"
#include "libstm/mesh/point_cloud.h"

#include <algorithm>
#include <numeric>

namespace sdm {

namespace {

// Merges points at exactly the position of an earlier one (the earlier kept, in file order).
long merge_duplicates(PointCloud& c, std::vector<int>& index_of) {
  const size_t n = c.points.size();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    const auto &p = c.points[size_t(a)], &q = c.points[size_t(b)];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> first(n);  // per point, the first point at its position
  for (size_t i = 0; i < n; ++i)
    first[size_t(order[i])] = i > 0 && c.points[size_t(order[i])] == c.points[size_t(order[i - 1])] ? first[size_t(order[i - 1])] : order[i];
  index_of.assign(n, -1);
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    if (first[i] != int(i)) {
      index_of[i] = index_of[size_t(first[i])];
      continue;
    }
    index_of[i] = int(kept);
    c.points[kept] = c.points[i];
    if (!c.normals.empty()) c.normals[kept] = c.normals[i];
    if (!c.colors.empty()) c.colors[kept] = c.colors[i];
    ++kept;
  }
  c.points.resize(kept);
  if (!c.normals.empty()) c.normals.resize(kept);
  if (!c.colors.empty()) c.colors.resize(kept);
  return long(n - kept);
}

// Principal extents: square roots of the covariance's eigenvalues, largest first.
Eigen::Vector3d principal_extents(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= double(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  cov /= double(points.size());
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
  return {std::sqrt(std::max(ev[2], 0.0)), std::sqrt(std::max(ev[1], 0.0)), std::sqrt(std::max(ev[0], 0.0))};
}

}  // namespace

CloudReport prepare_cloud(PointCloud& cloud, const std::string& what, std::vector<int>* index_of) {
  CloudReport r;
  r.points_read = long(cloud.points.size());
  r.no_returns = cloud.no_returns;
  for (size_t i = 0; i < cloud.points.size(); ++i)
    if (!cloud.points[i].allFinite())
      throw InputError("point cloud " + what + ": point " + std::to_string(i) + " is not finite. Fix: remove it");
  std::vector<int> map;
  r.duplicates = merge_duplicates(cloud, map);
  if (index_of) *index_of = std::move(map);
  r.points = long(cloud.points.size());
  r.normals_in_file = !cloud.normals.empty();
  r.colors = !cloud.colors.empty();
  const std::string counted = std::to_string(r.points) + " distinct points (" + std::to_string(r.points_read) + " read, " +
                              std::to_string(r.duplicates) + " duplicates merged)";
  if (r.points < kMinCloudPoints)
    throw InputError("point cloud " + what + " has " + counted + "; a skeleton needs at least " + std::to_string(kMinCloudPoints) +
                     ". Fix: scan the object more densely");
  r.bbox_min = r.bbox_max = cloud.points[0];
  for (const auto& p : cloud.points) r.bbox_min = r.bbox_min.cwiseMin(p), r.bbox_max = r.bbox_max.cwiseMax(p);
  r.extents = principal_extents(cloud.points);
  // A scan has thickness across its smallest axis when it has an inside to skeletonise: a sheet
  // or a line has none (flat to a thousandth of its largest extent).
  if (!(r.extents[1] > 1e-3 * r.extents[0]))
    throw InputError("point cloud " + what + ": its " + counted + " lie on a line (principal extents " + number(r.extents[0]) + ", " +
                     number(r.extents[1]) + ", " + number(r.extents[2]) + "); a skeleton needs a solid's surface");
  if (!(r.extents[2] > 1e-3 * r.extents[0]))
    throw InputError("point cloud " + what + ": its " + counted + " lie on a plane (principal extents " + number(r.extents[0]) + ", " +
                     number(r.extents[1]) + ", " + number(r.extents[2]) + "); a skeleton needs a solid's surface");
  r.mean_spacing = mean_nearest_distance(cloud.points, PointKdTree(cloud.points));
  return r;
}

PointCloud load_point_cloud(const std::string& path, CloudReport* report, bool normals) {
  PointCloud c = read_point_cloud(path);
  CloudReport r = prepare_cloud(c, path);
  // A normal the file left zero has no direction: every normal is estimated then, consistently.
  const bool usable = !c.normals.empty() &&
                      std::none_of(c.normals.begin(), c.normals.end(), [](const Eigen::Vector3d& n) { return n.isZero(); });
  if (!usable && normals) {
    c.normals = estimate_normals(c.points);
    r.normals_estimated = true;
  }
  if (report) *report = r;
  return c;
}

nlohmann::json CloudReport::to_json() const {
  return {{"points_read", points_read},
          {"duplicates_merged", duplicates},
          {"no_returns_dropped", no_returns},
          {"points", points},
          {"mean_spacing", mean_spacing},
          {"normals", normals_estimated ? (normals_in_file ? "estimated (the file's had zero vectors)" : "estimated") : "from the file"},
          {"colors", colors},
          {"bbox_min", {bbox_min.x(), bbox_min.y(), bbox_min.z()}},
          {"bbox_max", {bbox_max.x(), bbox_max.y(), bbox_max.z()}},
          {"principal_extents", {extents.x(), extents.y(), extents.z()}}};
}

}  // namespace sdm
