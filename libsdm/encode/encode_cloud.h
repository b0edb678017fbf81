#pragma once
/// A skeleton displacement map of a point cloud (DESIGN 6.1, "Point clouds"): the map of the cloud's
/// closed surface (cloud_layout.h: the IMLS zero set traced near the points, its gaps filled by
/// faired patches), encoded as a mesh is (encode_sdm.h). Each texel's D is then the crossing of its
/// capsule ray with the zero set where the points reach, and with a patch where the scan has a gap;
/// the share of texels whose surface point lies within the support of the points says how much of
/// the map the scan measured.
#include "libsdm/encode/encode_sdm.h"
#include "libstm/layout/cloud_layout.h"

namespace sdm {

struct CloudReach {
  long texels = 0;   ///< texels inside the rectangles with a displacement
  long reached = 0;  ///< of them, those whose surface point lies within the support of the points
  double share() const { return texels ? double(reached) / double(texels) : 0.0; }
};

/// Per texel of `im` (made for `layout`), whether its surface point (capsule ray at D) lies within
/// the support of the points (PointSetSurface::supported, the support the surface was traced in:
/// 4 local spacings, so a gap counts from 4 spacings inside its rim).
CloudReach cloud_reach(const SdmImage& im, const Layout& layout, const PointSetSurface& surface);

/// encode_sdm of the cloud's surface with its layout, and the texels the points reach.
SdmImage encode_cloud(const PointCloud& cloud, const CloudLayout& layout, const EncodeOptions& options = {},
                      EncodeStats* stats = nullptr, CloudReach* reach = nullptr);

}  // namespace sdm
