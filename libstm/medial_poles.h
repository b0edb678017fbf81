#pragma once
// Inner medial poles of a closed triangle mesh by the shrinking-ball method (Ma et al. 2012): for
// every vertex, the centre of the largest ball inside the volume that touches the surface at the
// vertex. Used to anchor the contraction to the medial axis, so that it neither drifts nor
// swallows short limbs.
#include <Eigen/Dense>

namespace stm {

// V: n x 3, F: m x 3, closed; orientation may be either way (the inside is found from the signed
// volume). Returns n x 3 ball centres. Radii are capped at half the bounding-box diagonal.
// Deterministic; commutes with rigid motions.
Eigen::MatrixX3d medial_poles(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

}  // namespace stm
