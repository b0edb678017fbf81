#pragma once
// Shared by the posing and rigging tests: a model encoded on a skeleton the test gives (its ideal
// one), and the node nearest a point.
#include "libsdm/encode/encode_sdm.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Core>

namespace pose_scenes {

struct Encoded {
  sdm::Mesh mesh;
  sdm::Layout layout;
  sdm::SdmImage image;
};

// `mesh` encoded on `skeleton` (its vertex_node given) at `size`, segments kept whole (split_ratio 0).
inline Encoded encode_on(sdm::Mesh mesh, const sdm::Skeleton& skeleton, int size = 512) {
  Encoded e;
  e.mesh = std::move(mesh);
  sdm::LayoutOptions lo;
  lo.size = size;
  lo.split_ratio = 0;
  e.layout = sdm::compute_layout(e.mesh, skeleton, lo);
  e.image = sdm::encode_sdm(e.mesh, e.layout);
  return e;
}

// The node of `s` nearest p (the first of equals).
inline int nearest_node(const sdm::Skeleton& s, const Eigen::Vector3d& p) {
  int best = 0;
  for (size_t n = 0; n < s.nodes.size(); ++n)
    if ((s.nodes[n] - p).squaredNorm() < (s.nodes[size_t(best)] - p).squaredNorm()) best = int(n);
  return best;
}

}  // namespace pose_scenes
