// Uses the installed headers and libraries: skeleton, layout, encode and decode of the capsule
// primitive (radius 1 around the z axis, total length 4). Exits 0 only when the decoded surface
// is a closed mesh within 1 % of the capsule's length of its analytic surface.
#include <libsdm/decode/decode_sdm.h>
#include <libsdm/encode/encode_sdm.h>
#include <libstm/core/version.h>
#include <libstm/layout/compute_layout.h>
#include <libstm/mesh/primitives.h>
#include <libstm/skeleton/extract_skeleton.h>

#include <algorithm>
#include <cmath>
#include <iostream>

// Distance from p to the capsule: the segment z in [-1, 1] on the axis, inflated by radius 1.
double capsule_distance(const Eigen::Vector3d& p) {
  const Eigen::Vector3d axis(0, 0, std::clamp(p.z(), -1.0, 1.0));
  return std::abs((p - axis).norm() - 1.0);
}

int main() {
  const sdm::Mesh mesh = sdm::make_primitive("capsule", 1200);
  const sdm::Skeleton skeleton = sdm::extract_skeleton(mesh);
  sdm::LayoutOptions options;
  options.size = 256;
  const sdm::Layout layout = sdm::compute_layout(mesh, skeleton, options);
  sdm::DecodeOptions decode;
  decode.level = 2;
  const sdm::Mesh out = sdm::decode_sdm(sdm::encode_sdm(mesh, layout), decode);
  double worst = 0;
  for (auto v : out.vertices()) worst = std::max(worst, capsule_distance(sdm::point(out, v)));
  bool closed = true;
  for (auto e : out.edges()) closed = closed && !out.is_boundary(e);
  std::cout << "sdm " << SDM_VERSION << ": " << skeleton.nodes.size() << " nodes, " << layout.segments.size() << " segments, "
            << out.n_faces() << " faces, worst distance " << worst << (closed ? ", closed" : ", NOT closed") << "\n";
  return closed && worst < 0.04 && out.n_faces() > 0 ? 0 : 1;
}
