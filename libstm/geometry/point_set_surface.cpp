#include "libstm/geometry/point_set_surface.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/geometry/point_kdtree.h"

#include <algorithm>
#include <cmath>

namespace sdm {

PointSetSurface::PointSetSurface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                                 const PointSetSurfaceOptions& options)
    : points_(points), normals_(normals), options_(options) {
  if (points.size() != normals.size()) throw InputError("a point set surface needs one normal per point");
  if (options.neighbours < 1 || options.neighbours > kMaxNeighbours || options.spacing_rank < 1 || options.spacing_rank >= kMaxNeighbours)
    throw InputError("a point set surface weighs 1 to " + std::to_string(kMaxNeighbours) + " neighbours");
  if (points.size() < size_t(std::max(options.neighbours, options.spacing_rank) + 1))
    throw InputError("a point set surface needs more than " + std::to_string(std::max(options.neighbours, options.spacing_rank)) + " points");
  tree_ = std::make_unique<PointKdTree>(points);
  spacing_.assign(points.size(), 0.0);
  const int rank = options_.spacing_rank + 1;
  parallel_for(int(points.size()), 1024, [&](int i) {
    int index[kMaxNeighbours];
    double d2[kMaxNeighbours];
    const int m = tree_->nearest(points[size_t(i)], rank, index, d2);
    spacing_[size_t(i)] = std::sqrt(d2[m - 1]);
  });
  std::vector<double> sorted = spacing_;
  std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
  median_spacing_ = sorted[sorted.size() / 2];
}

PointSetSurface::~PointSetSurface() = default;

PointSetSurface::Sample PointSetSurface::at(const Eigen::Vector3d& x) const {
  int near[kMaxNeighbours];
  double d2[kMaxNeighbours];
  const int m = tree_->nearest(x, options_.neighbours, near, d2);
  Sample s;
  if (m == 0 || std::sqrt(d2[0]) > options_.reach * spacing_[size_t(near[0])]) return s;
  double mean_spacing = 0;
  for (int k = 0; k < m; ++k) mean_spacing += spacing_[size_t(near[k])];
  mean_spacing /= double(m);
  const double h2 = std::pow(options_.width * mean_spacing, 2);
  // Weights relative to the nearest point's, so that a query far from every point (but within the
  // support of a sparse one) does not underflow.
  double weight = 0, value = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int k = 0; k < m; ++k) {
    const double w = std::exp(-(d2[k] - d2[0]) / h2);
    const size_t j = size_t(near[k]);
    weight += w;
    value += w * normals_[j].dot(x - points_[j]);
    normal += w * normals_[j];
  }
  s.defined = weight > 0 && normal.norm() > 1e-12 * weight;
  if (!s.defined) return s;
  s.value = value / weight;
  s.normal = normal.normalized();
  return s;
}

Eigen::Vector3d PointSetSurface::project(const Eigen::Vector3d& x, int steps) const {
  Eigen::Vector3d y = x;
  for (int i = 0; i < steps; ++i) {
    const Sample s = at(y);
    if (!s.defined) return x;
    y -= s.value * s.normal;
  }
  return y;
}

bool PointSetSurface::supported(const Eigen::Vector3d& x) const {
  double d2 = 0;
  const int near = tree_->nearest_one(x, &d2);
  return near >= 0 && std::sqrt(d2) <= options_.reach * spacing_[size_t(near)];
}

}  // namespace sdm
