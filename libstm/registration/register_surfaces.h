#pragma once
/// Similarity registration of one closed surface onto another: iterative closest points (Besl and
/// McKay 1992) in both directions, each step solved in closed form for rotation, uniform scale and
/// translation (Umeyama 1991). Texture transfer uses it to recognise a target that is the source's
/// shape tessellated anew (moved or scaled, perhaps): its skeleton is then the source's, carried
/// over (carry_skeleton), instead of one extracted again, because extraction depends on the
/// tessellation (DECISIONS 5, transfer).
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace sdm {

struct Registration {
  Similarity transform;   ///< source -> target
  /// Distances between the registered source and the target, sampled at both meshes' vertices in both
  /// directions and weighted by vertex area, as fractions of the target's bounding-box diagonal.
  double rms = INFINITY;
  double p99 = INFINITY;  ///< the area-weighted 99th percentile: a few misplaced tips do not count
  double max = INFINITY;
  int iterations = 0;
};

/// The similarity that brings `source` closest to `target`. Started with centroids and RMS radii
/// matched and no rotation, and from each of `starts` (e.g. the similarity of two matched
/// skeletons): the models are assumed in about the same orientation. Starts with the principal
/// axes matched (four ways) find a turned copy, but win only with a quarter of the other's RMS
/// distance. Each start runs at most max_iterations steps; pairs further apart than three times
/// their median distance are left out after the first steps, so parts one surface has and the
/// other lacks do not drag the fit. Deterministic. Both meshes need at least one face.
Registration register_surfaces(const Mesh& source, const Mesh& target, const std::vector<Similarity>& starts = {},
                               int max_iterations = 80);

}  // namespace sdm
