#include "libstm/layout/draw_atlas.h"

#include "libstm/core/atomic_file.h"
#include "libstm/layout/atlas_triangles.h"

#include "libstm/core/image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sdm {

namespace {

std::array<std::uint8_t, 3> segment_color(int s) {
  // Golden-ratio hues: neighbouring indices get distant colours.
  const double hue = std::fmod(s * 0.618033988749895, 1.0) * 6;
  const double x = 1 - std::abs(std::fmod(hue, 2.0) - 1);
  double r = 0, g = 0, b = 0;
  switch (int(hue)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  auto c = [](double v) { return std::uint8_t(std::lround(40 + 200 * v)); };
  return {c(r), c(g), c(b)};
}

}  // namespace

std::vector<std::uint8_t> draw_atlas(const Mesh& mesh, const Layout& L, const std::vector<int>& face_segment) {
  const int S = L.size;
  std::vector<std::uint8_t> img(size_t(S) * S * 4, 0);
  auto put = [&](int x, int y, std::array<std::uint8_t, 3> c) {
    const size_t i = (size_t(S - 1 - y) * S + x) * 4;
    img[i] = c[0], img[i + 1] = c[1], img[i + 2] = c[2], img[i + 3] = 255;
  };
  auto extent = [](const LayoutSegment& g) { return g.rotated ? std::make_pair(g.h, g.w) : std::make_pair(g.w, g.h); };
  for (const auto& g : L.segments) {
    const auto [ex, ey] = extent(g);
    for (int y = std::max(0, g.y - L.margin); y < std::min(S, g.y + ey + L.margin); ++y)
      for (int x = std::max(0, g.x - L.margin); x < std::min(S, g.x + ex + L.margin); ++x) {
        const bool inside = x >= g.x && x < g.x + ex && y >= g.y && y < g.y + ey;
        put(x, y, inside ? std::array<std::uint8_t, 3>{200, 200, 200} : std::array<std::uint8_t, 3>{70, 70, 70});
      }
  }
  for (const auto& t : atlas_triangles(mesh, L, face_segment)) {
    const LayoutSegment& g = L.segments[t.segment];
    const auto [ex, ey] = extent(g);
    auto base = segment_color(t.segment);
    const double shade = 0.8 + 0.2 * double((unsigned(t.face) * 2654435761u) >> 24) / 255.0;
    for (auto& c : base) c = std::uint8_t(c * shade);
    const auto& A = t.atlas[0];
    const auto& B = t.atlas[1];
    const auto& C = t.atlas[2];
    const double area = (B - A).x() * (C - A).y() - (C - A).x() * (B - A).y();
    if (area == 0) continue;
    const int x0 = std::max<int>(g.x, int(std::floor(std::min({A.x(), B.x(), C.x()}))));
    const int x1 = std::min<int>(g.x + ex - 1, int(std::ceil(std::max({A.x(), B.x(), C.x()}))));
    const int y0 = std::max<int>(g.y, int(std::floor(std::min({A.y(), B.y(), C.y()}))));
    const int y1 = std::min<int>(g.y + ey - 1, int(std::ceil(std::max({A.y(), B.y(), C.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        auto edge = [&](const Eigen::Vector2d& P, const Eigen::Vector2d& Q) {
          return ((Q - P).x() * (p - P).y() - (p - P).x() * (Q - P).y()) / area;
        };
        const double l0 = edge(B, C), l1 = edge(C, A), l2 = edge(A, B);
        if (l0 >= 0 && l1 >= 0 && l2 >= 0) put(x, y, base);
      }
  }
  return img;
}

void write_atlas_png(const Mesh& mesh, const Layout& L, const std::vector<int>& face_segment, const std::string& path) {
  Image img;
  img.width = img.height = L.size;
  img.channels = 4;
  img.pixels = draw_atlas(mesh, L, face_segment);
  write_png(img, path);  // its size limit and checked writes
}

Image checker_atlas(const Layout& layout, int square) {
  Image im;
  im.width = im.height = layout.size;
  im.channels = 4;
  im.pixels.assign(size_t(layout.size) * layout.size * 4, 160);
  for (size_t i = 3; i < im.pixels.size(); i += 4) im.pixels[i] = 255;
  square = std::max(1, square);
  for (size_t s = 0; s < layout.segments.size(); ++s) {
    const LayoutSegment& seg = layout.segments[s];
    const int ex = seg.rotated ? seg.h : seg.w, ey = seg.rotated ? seg.w : seg.h;
    const auto c = segment_color(int(s));
    for (int y = seg.y - layout.margin; y < seg.y + ey + layout.margin; ++y)
      for (int x = seg.x - layout.margin; x < seg.x + ex + layout.margin; ++x) {
        if (x < 0 || y < 0 || x >= layout.size || y >= layout.size) continue;
        // Local coordinates, wrapped around the axis so the margins continue the pattern.
        int u = seg.rotated ? x - seg.x : y - seg.y, v = seg.rotated ? y - seg.y : x - seg.x;
        u = ((u % seg.h) + seg.h) % seg.h;
        const bool dark = ((u / square) + ((v + square * 1024) / square)) % 2;
        std::uint8_t* p = &im.pixels[(size_t(layout.size - 1 - y) * layout.size + x) * 4];
        for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(dark ? c[k] / 2 : std::min(255, c[k] / 2 + 128));
      }
  }
  return im;
}

}  // namespace sdm
