#pragma once
/// Distance between two surfaces by dense sampling: the round-trip error of SDM encode/decode.
#include "libstm/mesh/mesh.h"

namespace sdm {

/// `count` points drawn uniformly by area from the surface (fixed seed: deterministic).
Eigen::MatrixX3d sample_surface(const Mesh& mesh, int count, unsigned seed = 1);

struct SurfaceDistance {
  double hausdorff = 0;  ///< symmetric: max over both directions, samples and vertices
  double rms = 0;        ///< root mean square over the samples of both directions
  double mean = 0;
  double diagonal = 0;   ///< bounding-box diagonal of `a`, the reference
  int samples_per_surface = 0;
  /// Where the Hausdorff distance is: a point of one surface and its closest point on the other;
  /// worst_on_b when the point lies on b (b strays from a) rather than on a (b misses part of a).
  Eigen::Vector3d worst_point = Eigen::Vector3d::Zero(), worst_closest = Eigen::Vector3d::Zero();
  bool worst_on_b = false;
};

/// Symmetric Hausdorff and RMS distance between surfaces a and b, each sampled with `samples`
/// points and measured against the other surface's triangles (exact closest points). The Hausdorff
/// distance also takes every vertex of both (a spike's tip is a vertex that random samples miss);
/// the RMS and mean are over the area-uniform samples only.
SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, int samples = 100000);

/// How much of a reference surface another one carries (the quality gate of encode and
/// roundtrip): every vertex of `reference`, weighted by its area (a third of its faces'), measured
/// against the triangles of `carrier`.
struct SurfaceCoverage {
  double share = 0;      ///< area share of the reference's vertices within `tolerance` of the carrier
  double rms = 0;        ///< area-weighted RMS of those distances
  double worst = 0;      ///< the largest distance
  Eigen::Vector3d worst_point = Eigen::Vector3d::Zero();  ///< the reference vertex farthest away
};
SurfaceCoverage surface_coverage(const Mesh& reference, const Mesh& carrier, double tolerance);
/// The same against a carrier given as triangles (rows of corner indices into `points`), as a
/// decoder makes it, without building a halfedge mesh of it.
SurfaceCoverage surface_coverage(const Mesh& reference, const Eigen::MatrixX3d& points, const Eigen::MatrixX3i& triangles,
                                 double tolerance);

}  // namespace sdm
