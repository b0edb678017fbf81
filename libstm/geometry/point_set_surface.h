#pragma once
/// The surface a point cloud with normals describes: the zero set of an implicit moving-least-squares
/// function (IMLS; Shen, O'Brien and Shewchuk 2004, Kolluri 2008), f(x) = sum_i w_i(x) n_i . (x - p_i)
/// / sum_i w_i(x), with Gaussian weights w_i(x) = exp(-|x - p_i|^2 / h^2) over the k nearest points
/// and h proportional to their local spacing, so denser and sparser parts of a scan keep their own
/// detail and noise along the normals averages out over the kernel. f is defined only within the
/// support of the points: near a point (a few local spacings); a gap in a scan has no surface.
#include <Eigen/Dense>

#include <memory>
#include <vector>

namespace sdm {

class PointKdTree;

struct PointSetSurfaceOptions {
  int neighbours = 20;    ///< points weighted at a query (the k nearest; at most PointSetSurface::kMaxNeighbours)
  double width = 2.0;     ///< Gaussian width h as a multiple of the neighbours' mean local spacing
  double reach = 4.0;     ///< a query is in the support when its nearest point lies within reach local spacings
  int spacing_rank = 6;   ///< a point's local spacing: the distance to its spacing_rank-th nearest other point
};

class PointSetSurface {
 public:
  static constexpr int kMaxNeighbours = 64;  ///< the most neighbours a query weighs (and spacing_rank + 1)
  /// `points` distinct, `normals` one unit vector per point, oriented consistently (estimate_normals);
  /// both kept by reference and must outlive the surface.
  PointSetSurface(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const PointSetSurfaceOptions& options = {});
  ~PointSetSurface();

  struct Sample {
    bool defined = false;  ///< within the support of the points
    double value = 0;      ///< f(x): about the signed distance to the surface, positive outside
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< the weighted normal at x (unit)
  };
  Sample at(const Eigen::Vector3d& x) const;

  /// x moved onto the zero set along the weighted normal (x <- x - f(x) n(x), `steps` times; each
  /// step a Newton step when f is a distance); x itself where it leaves the support.
  Eigen::Vector3d project(const Eigen::Vector3d& x, int steps = 3) const;

  /// Whether x lies within the support of the points (PointSetSurfaceOptions::reach).
  bool supported(const Eigen::Vector3d& x) const;

  double spacing(int i) const { return spacing_[size_t(i)]; }
  double median_spacing() const { return median_spacing_; }
  const PointKdTree& tree() const { return *tree_; }

 private:
  const std::vector<Eigen::Vector3d>& points_;
  const std::vector<Eigen::Vector3d>& normals_;
  PointSetSurfaceOptions options_;
  std::unique_ptr<PointKdTree> tree_;
  std::vector<double> spacing_;
  double median_spacing_ = 0;
};

}  // namespace sdm
