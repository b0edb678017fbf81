#include "libstm/layout/compute_layout.h"

#include "libstm/core/errors.h"
#include "libstm/core/limits.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/layout/pack_rectangles.h"
#include "libstm/layout/segment_frames.h"
#include "libstm/layout/segments.h"
#include "libstm/layout/split_segments.h"
#include "libstm/layout/assign_layout_faces.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace sdm {

namespace {

// A segment whose rectangle gets no whole texel even when the largest rectangle spans the atlas
// cannot be packed at this size: a speck beside the model (a tiny separate part) fails at every
// size, and "use a larger --size" sent the user round in circles. Names the segment, its size and
// place, the size that would hold it, and --min-part (drop_small_parts.h) for a speck.
void check_no_speck(const Mesh& mesh, const Layout& L, const std::vector<Eigen::Vector2d>& sizes, const LayoutOptions& opt) {
  double largest = 0;
  for (const auto& z : sizes) largest = std::max(largest, z.maxCoeff());
  int worst = -1;
  for (int s = 0; s < int(sizes.size()); ++s)
    if (worst < 0 || sizes[s].minCoeff() < sizes[worst].minCoeff()) worst = s;
  const double ratio = largest / sizes[worst].minCoeff();  // texels the largest side needs for 1 texel of the smallest
  const double needed = ratio + 2 * opt.margin;
  if (needed <= opt.size) return;
  const LayoutSegment& g = L.segments[worst];
  const Eigen::Vector3d at = 0.5 * (L.skeleton.nodes[g.a] + L.skeleton.nodes[g.b]);
  const double diagonal = bounding_box_diagonal(mesh), extent = std::max(g.length + 2 * g.cap, 2 * g.radius);
  std::string fix = needed <= kMaxImageSide ? "use --size " + std::to_string(int(std::ceil(needed))) + " or more"
                                            : "no --size up to " + std::to_string(kMaxImageSide) + " holds it";
  const double part = std::pow(10.0, std::ceil(std::log10(2 * extent / diagonal)));  // a round fraction above it
  if (extent < 0.05 * diagonal)
    fix += "; if it is a speck beside the model, drop the parts under " + number(part) + " of the diagonal with --min-part " + number(part);
  throw InputError("segment " + std::to_string(worst) + " (radius " + number(g.radius) + ", length " + number(g.length) + ", around (" +
                   number(at.x()) + ", " + number(at.y()) + ", " + number(at.z()) + "), " + number(100 * extent / diagonal) +
                   " % of the model's diagonal) is " + number(ratio) + " times smaller than the largest rectangle: it gets no texel in a " +
                   std::to_string(opt.size) + "^2 atlas. Fix: " + fix);
}

}  // namespace

Layout compute_layout(const Mesh& mesh, const Skeleton& input, const LayoutOptions& opt) {
  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  if (!opt.weights.empty() && opt.weights.size() != input.edges.size())
    throw InputError("got " + std::to_string(opt.weights.size()) + " segment weights for " + std::to_string(input.edges.size()) +
                     " skeleton edges");
  for (double w : opt.weights)
    if (!(w > 0) || !std::isfinite(w)) throw InputError("segment weights must be positive");
  std::vector<int> origin;
  const Skeleton skeleton = split_long_segments(mesh, input, opt.split_ratio, &origin);
  const int ne = int(skeleton.edges.size());
  if (ne != int(input.edges.size()))
    say("cut long edges: " + std::to_string(input.edges.size()) + " skeleton edges -> " + std::to_string(ne) + " segments");
  say("assigning faces to " + std::to_string(ne) + " segments");
  // The rectangles are made for the radii assign_faces' second pass rated with (its first pass's
  // geometry): the shaders, given the layout, then choose the segments this assignment chose.
  std::vector<double> radius;
  std::vector<std::array<double, 2>> extension;
  const std::vector<int> fs = assign_faces(mesh, skeleton, &radius, true, &extension);
  const std::vector<SegmentGeometry> geo = segment_geometry(mesh, skeleton, fs, &radius);
  say("carrying frames along the skeleton");
  const std::vector<SegmentFrame> frames = segment_frames(mesh, skeleton, fs);

  Layout L;
  L.size = opt.size;
  L.margin = opt.margin;
  L.skeleton = skeleton;
  L.segments.resize(ne);
  std::vector<Eigen::Vector2d> sizes(ne);
  for (int s = 0; s < ne; ++s) {
    LayoutSegment& g = L.segments[s];
    g.edge = s;
    g.a = frames[s].a, g.b = frames[s].b;
    g.axis = frames[s].axis, g.e1 = frames[s].e1, g.e2 = frames[s].e2;
    g.radius = geo[s].radius, g.cap = geo[s].cap, g.length = geo[s].length, g.area = geo[s].area;
    g.weight = opt.weights.empty() ? 1.0 : opt.weights[origin[s]];
    const bool same = skeleton.edges[s][0] == g.a;  // the frame may run against the edge
    g.extend_a = extension[s][same ? 0 : 1], g.extend_b = extension[s][same ? 1 : 0];
    sizes[s] = g.weight * Eigen::Vector2d(capsule_length(g), 2 * M_PI * g.radius);
  }
  check_no_speck(mesh, L, sizes, opt);
  say("packing " + std::to_string(ne) + " rectangles into " + std::to_string(opt.size) + "^2 texels");
  const Packing p = pack_rectangles(sizes, opt.size, opt.margin, opt.max_anisotropy);
  L.scale = p.scale;
  L.coverage = p.coverage;
  L.coverage_inner = p.coverage_inner;
  std::vector<std::vector<int>> node_segments(skeleton.nodes.size());
  for (int s = 0; s < ne; ++s) {
    node_segments[L.segments[s].a].push_back(s);
    if (L.segments[s].b != L.segments[s].a) node_segments[L.segments[s].b].push_back(s);
  }
  for (int s = 0; s < ne; ++s) {
    LayoutSegment& g = L.segments[s];
    g.x = p.rects[s].x, g.y = p.rects[s].y, g.w = p.rects[s].w, g.h = p.rects[s].h, g.rotated = p.rects[s].rotated;
    // The caps keep their share of the rectangle's length (rounded to whole texels, maybe grown).
    g.d = std::min(g.w * g.cap / capsule_length(g), 0.5 * g.w);
    for (int o : node_segments[g.a])
      if (o != s) g.neighbours_a.push_back(o);
    for (int o : node_segments[g.b])
      if (o != s) g.neighbours_b.push_back(o);
  }
  // Layouts without extensions keep the rule older builds read.
  const bool extended = std::any_of(L.segments.begin(), L.segments.end(),
                                    [](const LayoutSegment& g) { return g.extend_a > 0 || g.extend_b > 0; });
  L.assignment = extended ? 3 : 2;
  return L;
}

}  // namespace sdm
