#pragma once
// Similarity registration of one closed surface onto another: iterative closest points (Besl and
// McKay 1992) in both directions, each step solved in closed form for rotation, uniform scale and
// translation (Umeyama 1991). Texture transfer uses it to recognise a target that is the source's
// shape tessellated anew (moved or scaled, perhaps): its skeleton is then the source's, carried
// over (carry_skeleton), instead of one extracted again, because extraction depends on the
// tessellation (DESIGN 6, transfer).
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace sdm {

struct Similarity {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
  Similarity inverse() const;
};

struct Registration {
  Similarity transform;   // source -> target
  // Distances between the registered source and the target, sampled at both meshes' vertices in both
  // directions and weighted by vertex area, as fractions of the target's bounding-box diagonal.
  double rms = INFINITY;
  double p99 = INFINITY;  // the area-weighted 99th percentile: a few misplaced tips do not count
  double max = INFINITY;
  int iterations = 0;
};

// The similarity that brings `source` closest to `target`. Started with centroids and RMS radii
// matched and no rotation, and from each of `starts` (e.g. the similarity of two matched
// skeletons): the models are assumed in about the same orientation. Starts with the principal axes
// matched (four ways) find a turned copy, but win only with a quarter of the other's RMS distance. Each start runs at most
// max_iterations steps; pairs further apart than three times their median distance are left out
// after the first steps, so parts one surface has and the other lacks do not drag the fit.
// Deterministic. Both meshes need at least one face.
// Weighted least-squares similarity y ~ T(x) (Umeyama), reflections excluded. Needs x, y, w of one size.
Similarity fit_similarity(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y, const std::vector<double>& w);

// The q-quantile of `values` where each counts with its weight (e.g. distances weighted by area).
double weighted_quantile(const std::vector<double>& values, const std::vector<double>& weights, double q);

// A third of the area of the faces around each vertex (times `factor`): the surface a vertex
// sample stands for, so that dense and sparse regions count alike.
std::vector<double> vertex_areas(const Mesh& mesh, double factor = 1.0);

// Barycentric coordinates of p (on or near the triangle's plane) in triangle (a, b, c).
Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

Registration register_surfaces(const Mesh& source, const Mesh& target, const std::vector<Similarity>& starts = {},
                               int max_iterations = 80);

}  // namespace sdm
