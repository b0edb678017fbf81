#pragma once
// Skeleton displacement maps of point clouds on the command line (libsdm/encode/encode_cloud.h):
// `sdm encode CLOUD` and `sdm roundtrip CLOUD`; the mesh commands hand a cloud over here when
// is_point_cloud_file says so.
#include <string>

namespace sdm::cli {

struct CloudMapArgs {
  std::string cloud, out, png, precision = "10", reference;
  int size = 1024, lod = 3, samples = 100000;
  double face_error = 0.0025;
  double max_rms = -1;
  bool json = false;
};

/// `sdm encode CLOUD -o MAP.exr`: the map of the cloud's surface; --json reports the share of texels
/// the points reach.
int cloud_encode(const CloudMapArgs& a);

/// `sdm roundtrip CLOUD [--reference MESH]`: encode, decode, and measure the decoded surface against
/// the points (one-sided, points to surface) and against the reference mesh (both ways).
int cloud_roundtrip(const CloudMapArgs& a);

}  // namespace sdm::cli
