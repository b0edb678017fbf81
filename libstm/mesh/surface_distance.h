#pragma once
// Distance between two surfaces by dense sampling: the round-trip error of SDM encode/decode.
#include "libstm/mesh/mesh.h"

namespace sdm {

// `count` points drawn uniformly by area from the surface (fixed seed: deterministic).
Eigen::MatrixX3d sample_surface(const Mesh& mesh, int count, unsigned seed = 1);

struct SurfaceDistance {
  double hausdorff = 0;  // symmetric: max over both directions
  double rms = 0;        // root mean square over the samples of both directions
  double mean = 0;
  double diagonal = 0;   // bounding-box diagonal of `a`, the reference
  int samples_per_surface = 0;
};

// Symmetric Hausdorff and RMS distance between surfaces a and b, each sampled with `samples`
// points and measured against the other surface's triangles (exact closest points).
SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, int samples = 100000);

}  // namespace sdm
