#include "libsdm/encode/encode_cloud.h"

#include "libsdm/map/texels.h"
#include "libstm/core/parallel.h"
#include "libstm/geometry/capsule_ray.h"

namespace sdm {

CloudReach cloud_reach(const SdmImage& im, const Layout& layout, const PointSetSurface& surface) {
  CloudReach total;
  for (size_t s = 0; s < layout.segments.size(); ++s) {
    const LayoutSegment& seg = layout.segments[s];
    const CapsuleFrame frame = capsule_frame(layout, int(s));
    const int ex = seg.rotated ? seg.h : seg.w, ey = seg.rotated ? seg.w : seg.h;
    std::vector<CloudReach> row(static_cast<size_t>(ey));
    parallel_for(ey, 4, [&](int j) {
      for (int i = 0; i < ex; ++i) {
        const int ix = seg.x + i, iy = seg.y + j;
        const float D = im.D[texel_index(im, ix, iy)];
        if (!std::isfinite(D)) continue;
        const Eigen::Vector2d uv = texel_local_uv(seg, ix, iy);
        const CapsuleRay ray = capsule_ray(frame, seg.w, seg.h, seg.d, uv.x(), uv.y());
        ++row[size_t(j)].texels;
        row[size_t(j)].reached += surface.supported(ray.origin + double(D) * ray.direction);
      }
    });
    for (const CloudReach& r : row) total.texels += r.texels, total.reached += r.reached;
  }
  return total;
}

SdmImage encode_cloud(const PointCloud& cloud, const CloudLayout& layout, const EncodeOptions& options, EncodeStats* stats,
                      CloudReach* reach) {
  SdmImage im = encode_sdm(layout.surface, layout.layout, options, stats);
  if (reach) {
    report_progress(options.progress, "measuring where the points reach");
    const PointSetSurface surface(cloud.points, layout.normals, PointSetSurfaceOptions());
    *reach = cloud_reach(im, layout.layout, surface);
  }
  return im;
}

}  // namespace sdm
