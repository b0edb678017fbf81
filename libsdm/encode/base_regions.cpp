#include "libsdm/encode/base_regions.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/triangle_bvh.h"

#include <algorithm>

namespace sdm {

BaseRegions::BaseRegions(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const BaseMesh& base) : F_(F), base_(base.triangles) {
  // The flat base faces as a soup: corners where the encoder has them.
  const Eigen::Index nf = base.triangles.rows();
  Eigen::MatrixX3d P(3 * nf, 3);
  Eigen::MatrixX3i T(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) P.row(3 * f + c) = base.corner_position[size_t(f)][size_t(c)].transpose(), T(f, c) = int(3 * f + c);
  const TriangleBvh flat(P, T);
  auto longest = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  };
  base_length_.resize(size_t(nf));
  for (Eigen::Index f = 0; f < nf; ++f) base_length_[size_t(f)] = longest(P.row(3 * f), P.row(3 * f + 1), P.row(3 * f + 2));
  face_length_.resize(size_t(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) face_length_[size_t(f)] = longest(V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
  owner_.assign(size_t(V.rows()), -1);
  parallel_for(int(V.rows()), 4096, [&](int v) { owner_[size_t(v)] = flat.closest_point(V.row(v).transpose()).face; });
}

bool BaseRegions::plausible(int face, int base_face) const {
  if (F_.rows() == 0 || face_length_[size_t(face)] > base_length_[size_t(base_face)]) return true;
  for (int k = 0; k < 3; ++k)
    if (faces_share_corner(base_, owner_[size_t(F_(face, k))], base_face)) return true;
  return false;
}

}  // namespace sdm
