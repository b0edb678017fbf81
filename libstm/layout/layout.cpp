#include "libstm/layout/layout.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/json_int.h"
#include "libstm/core/limits.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/layout/pack_rectangles.h"
#include "libstm/layout/segment_frames.h"
#include "libstm/layout/segments.h"
#include "libstm/layout/split_segments.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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

CapsuleFrame capsule_frame(const Layout& L, int s) {
  const LayoutSegment& g = L.segments.at(s);
  const Eigen::Vector3d &a = L.skeleton.nodes.at(g.a), &b = L.skeleton.nodes.at(g.b);
  return {a - g.extend_a * g.radius * g.axis, b + g.extend_b * g.radius * g.axis, g.e1, g.e2};
}

double capsule_length(const LayoutSegment& g) { return g.length + (g.extend_a + g.extend_b) * g.radius + 2 * g.cap; }

std::vector<int> assign_faces(const Mesh& mesh, const Layout& L, const Skeleton& skeleton) {
  std::vector<double> radius;
  radius.reserve(L.segments.size());
  std::vector<std::array<double, 2>> extension;  // per edge, at edges[e][0] and edges[e][1]
  for (size_t s = 0; s < L.segments.size(); ++s) {
    const LayoutSegment& g = L.segments[s];
    radius.push_back(g.radius);
    const bool same = s >= skeleton.edges.size() || skeleton.edges[s][0] == g.a;
    if (L.assignment >= 3) extension.push_back({same ? g.extend_a : g.extend_b, same ? g.extend_b : g.extend_a});
  }
  return assign_faces_with_radii(mesh, skeleton, radius, L.assignment >= 2, extension);
}

std::vector<int> assign_faces(const Mesh& mesh, const Layout& L) { return assign_faces(mesh, L, L.skeleton); }

Eigen::Vector2d local_to_atlas(const LayoutSegment& g, double u, double v) {
  return g.rotated ? Eigen::Vector2d(g.x + u, g.y + v) : Eigen::Vector2d(g.x + v, g.y + u);
}

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

}  // namespace

nlohmann::json layout_to_json(const Layout& L) {
  nlohmann::json j;
  j["format"] = "sdm-layout";
  j["version"] = 1;
  j["size"] = L.size;
  j["margin"] = L.margin;
  j["scale"] = L.scale;
  j["coverage"] = L.coverage;
  j["coverage_inner"] = L.coverage_inner;
  j["assignment"] = L.assignment;
  j["skeleton"] = skeleton_to_json(L.skeleton);
  j["segments"] = nlohmann::json::array();
  for (const auto& g : L.segments) {
    nlohmann::json s;
    s["edge"] = g.edge;
    s["a"] = g.a;
    s["b"] = g.b;
    s["axis"] = vec(g.axis);
    s["e1"] = vec(g.e1);
    s["e2"] = vec(g.e2);
    s["radius"] = g.radius;
    s["cap"] = g.cap;
    s["length"] = g.length;
    s["area"] = g.area;
    s["weight"] = g.weight;
    s["rect"] = {g.x, g.y, g.w, g.h};
    s["rotated"] = g.rotated;
    s["d"] = g.d;
    if (g.extend_a > 0 || g.extend_b > 0) s["extend"] = {g.extend_a, g.extend_b};
    s["neighbours_a"] = g.neighbours_a;
    s["neighbours_b"] = g.neighbours_b;
    j["segments"].push_back(s);
  }
  return j;
}

namespace {

std::string segment_problem(const Layout& L, size_t s) {
  const LayoutSegment& g = L.segments[s];
  const auto& e = L.skeleton.edges[s];
  const int nn = int(L.skeleton.nodes.size()), ns = int(L.segments.size());
  const bool ends_ok = g.a >= 0 && g.a < nn && g.b >= 0 && g.b < nn && ((g.a == e[0] && g.b == e[1]) || (g.a == e[1] && g.b == e[0]));
  if (!ends_ok || g.edge != int(s)) return "does not match its skeleton edge";
  // 64-bit sums: a rectangle near INT_MAX must not wrap around into the atlas.
  const int64_t right = int64_t(g.x) + (g.rotated ? g.h : g.w), top = int64_t(g.y) + (g.rotated ? g.w : g.h);
  if (g.w <= 0 || g.h <= 0 || g.x < 0 || g.y < 0 || right > L.size || top > L.size) return "lies outside the atlas";
  for (const Eigen::Vector3d* v : {&g.axis, &g.e1, &g.e2})
    if (!v->allFinite() || std::abs(v->norm() - 1) > 1e-6) return "has a frame that is not made of unit vectors";
  if (std::abs(g.axis.dot(g.e1)) > 1e-6 || std::abs(g.axis.dot(g.e2)) > 1e-6 || std::abs(g.e1.dot(g.e2)) > 1e-6)
    return "has a frame that is not orthogonal";
  if (!(g.radius > 0) || !std::isfinite(g.radius)) return "has radius " + number(g.radius) + " (it must be positive)";
  if (!(g.cap >= 0) || !std::isfinite(g.cap) || !(g.length >= 0) || !std::isfinite(g.length))
    return "has a negative or non-finite cap or length";
  if (!(g.weight > 0) || !std::isfinite(g.weight)) return "has a weight that is not positive";
  if (!(g.d >= 0) || !(g.d <= 0.5 * g.w + 1e-9)) return "has a cap of " + number(g.d) + " texels outside 0..w/2";
  // The rectangle is the capsule at the layout's scale, grown by packing (measured 0.99-1.34x on
  // Spot and the capsule, 2.18x on a Spot with its head pushed into its body): a radius or length
  // tampered by 10x decoded a "closed 2-manifold" off by model units.
  if (!(g.extend_a >= 0 && g.extend_a <= kMaxCapExtension) || !(g.extend_b >= 0 && g.extend_b <= kMaxCapExtension))
    return "has capsule extensions " + number(g.extend_a) + ", " + number(g.extend_b) + " outside 0.." + number(kMaxCapExtension) + " radii";
  const double around = 2 * M_PI * g.radius * L.scale * g.weight, along = capsule_length(g) * L.scale * g.weight;
  if (g.h < 0.5 * around - 1 || g.h > 4 * around + 1 || g.w < 0.5 * along - 1 || g.w > 4 * along + 1)
    return "has a rectangle of " + std::to_string(g.w) + "x" + std::to_string(g.h) + " texels for a capsule of " + number(along) + "x" +
           number(around) + " at the layout's scale: its radius, length or scale was altered";
  // The axis runs from node a to node b (segment_frames.h).
  const Eigen::Vector3d ab = L.skeleton.nodes[g.b] - L.skeleton.nodes[g.a];
  if ((g.axis - ab / ab.norm()).norm() > 1e-6) return "has an axis that does not run from its node a to its node b";
  for (const auto* nb : {&g.neighbours_a, &g.neighbours_b})
    for (int o : *nb)
      if (o < 0 || o >= ns) return "names neighbour segment " + std::to_string(o) + " of " + std::to_string(ns);
  return "";
}

// Checks what compute_layout guarantees, so that a crafted file is refused before anything indexes
// the atlas with its numbers (see layout.h).
void check_layout(const Layout& L) {
  if (L.size < 1 || L.size > kMaxImageSide)
    throw InputError("not a valid sdm layout: atlas size " + std::to_string(L.size) + " is outside 1.." + std::to_string(kMaxImageSide));
  if (L.margin < 0 || L.margin > L.size)
    throw InputError("not a valid sdm layout: margin " + std::to_string(L.margin) + " is outside 0.." + std::to_string(L.size));
  if (!(L.scale > 0) || !std::isfinite(L.scale)) throw InputError("not a valid sdm layout: scale must be positive");
  if (L.segments.size() != L.skeleton.edges.size())
    throw InputError("not a valid sdm layout: " + std::to_string(L.segments.size()) + " segments for " +
                     std::to_string(L.skeleton.edges.size()) + " skeleton edges");
  for (size_t s = 0; s < L.segments.size(); ++s) {
    const std::string why = segment_problem(L, s);
    if (!why.empty()) throw InputError("not a valid sdm layout: segment " + std::to_string(s) + " " + why);
  }
}

}  // namespace

Layout layout_from_json(const nlohmann::json& j) {
  Layout L;
  try {
    if (j.value("format", std::string()) != "sdm-layout") throw InputError("not an sdm layout (format is not \"sdm-layout\")");
    if (json_int(j.at("version")) != 1)
      throw InputError("sdm layout version " + std::to_string(json_int(j.at("version"))) + " is not supported (this build reads 1)");
    L.size = json_int(j.at("size"));
    L.margin = json_int(j.at("margin"));
    L.scale = j.at("scale").get<double>();
    L.coverage = j.value("coverage", 0.0);
    L.coverage_inner = j.value("coverage_inner", 0.0);
    L.assignment = j.contains("assignment") ? json_int(j.at("assignment")) : 1;
    if (L.assignment < 1 || L.assignment > 3)
      throw InputError("layout assignment rule " + std::to_string(L.assignment) + " is not supported (this build knows 1 to 3)");
    L.skeleton = skeleton_from_json(j.at("skeleton"));
    for (const auto& s : j.at("segments")) {
      LayoutSegment g;
      g.edge = json_int(s.at("edge"));
      g.a = json_int(s.at("a"));
      g.b = json_int(s.at("b"));
      g.axis = vec(s.at("axis"));
      g.e1 = vec(s.at("e1"));
      g.e2 = vec(s.at("e2"));
      g.radius = s.at("radius").get<double>();
      g.cap = s.at("cap").get<double>();
      g.length = s.at("length").get<double>();
      g.area = s.value("area", 0.0);
      g.weight = s.value("weight", 1.0);
      const auto& r = s.at("rect");
      g.x = json_int(r.at(0)), g.y = json_int(r.at(1)), g.w = json_int(r.at(2)), g.h = json_int(r.at(3));
      g.rotated = s.at("rotated").get<bool>();
      g.d = s.at("d").get<double>();
      if (s.contains("extend")) {
        if (L.assignment < 3)
          throw InputError("segment " + std::to_string(L.segments.size()) + " has capsule extensions, which assignment rule " +
                           std::to_string(L.assignment) + " does not have");
        g.extend_a = s["extend"].at(0).get<double>(), g.extend_b = s["extend"].at(1).get<double>();
      }
      if (s.contains("neighbours_a")) g.neighbours_a = json_ints(s["neighbours_a"]);
      if (s.contains("neighbours_b")) g.neighbours_b = json_ints(s["neighbours_b"]);
      L.segments.push_back(g);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a valid sdm layout: ") + e.what());
  }
  check_layout(L);
  return L;
}

void write_layout_json(const Layout& L, const std::string& path) { write_text_file(path, layout_to_json(L).dump(1) + "\n"); }

Layout read_layout_json(const std::string& path, const ReadBudget& budget) {
  const nlohmann::json j = nlohmann::json::parse(read_input_file(path, "layout", kMaxJsonFileBytes, budget, kJsonBytesPerFileByte), nullptr, false);
  if (j.is_discarded()) throw InputError("cannot read layout " + path + ": not JSON");
  try {
    return layout_from_json(j);
  } catch (const InputError& e) {
    throw InputError("layout " + path + ": " + e.what());
  }
}

namespace {

// Local (u, v) of a face's corners, unwrapped across phi = 0 (see AtlasTriangle).
std::array<Eigen::Vector2d, 3> face_local(const Layout& L, int s, const std::array<Eigen::Vector3d, 3>& p, bool* seam) {
  const LayoutSegment& g = L.segments[s];
  const CapsuleFrame f = capsule_frame(L, s);
  const double h = g.h;
  std::array<CapsuleUV, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = capsule_uv(f, g.w, h, g.d, p[k]);
  // A corner on the axis (a pole) has no angle: it takes its neighbours'.
  const double eps = 1e-9 * std::max(g.radius + g.length, 1e-300);
  std::array<double, 3> u{c[0].u, c[1].u, c[2].u};
  std::vector<int> ok;
  for (int k = 0; k < 3; ++k)
    if (c[k].rho > eps) ok.push_back(k);
  if (!ok.empty()) {
    // Keep the largest circular gap outside the triangle.
    std::sort(ok.begin(), ok.end(), [&](int i, int j) { return u[i] < u[j]; });
    const int n = int(ok.size());
    int gap_after = n - 1;  // the gap from ok[n-1] around to ok[0]
    double gap = u[ok[0]] + h - u[ok[n - 1]];
    for (int i = 0; i + 1 < n; ++i)
      if (u[ok[i + 1]] - u[ok[i]] > gap) gap = u[ok[i + 1]] - u[ok[i]], gap_after = i;
    for (int i = 0; i <= gap_after && gap_after != n - 1; ++i) u[ok[i]] += h;
    double lo = u[ok[0]], hi = lo, mean = 0;
    for (int k : ok) lo = std::min(lo, u[k]), hi = std::max(hi, u[k]), mean += u[k];
    mean /= n;
    // Past h: either stay there or shift down by h, whichever leaves less outside [0, h].
    if (hi > h && h - lo < hi - h) {
      for (int k : ok) u[k] -= h;
      mean -= h;
      lo -= h, hi -= h;
    }
    for (int k = 0; k < 3; ++k)
      if (c[k].rho <= eps) u[k] = mean;
    if (seam) *seam = lo < 0 || hi > h;
  } else if (seam) {
    *seam = false;
  }
  return {Eigen::Vector2d(u[0], c[0].v), Eigen::Vector2d(u[1], c[1].v), Eigen::Vector2d(u[2], c[2].v)};
}

}  // namespace

std::vector<AtlasTriangle> atlas_triangles(const Mesh& mesh, const Layout& L, const std::vector<int>& fs) {
  if (fs.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");
  std::vector<AtlasTriangle> out;
  out.reserve(mesh.n_faces() + mesh.n_faces() / 8);
  for (auto f : mesh.faces()) {
    const int s = fs[f.idx()];
    if (s < 0 || s >= int(L.segments.size())) throw InputError("face " + std::to_string(f.idx()) + " names no segment of the layout");
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    bool seam = false;
    AtlasTriangle t;
    t.face = f.idx(), t.segment = s, t.copy = 0;
    t.local = face_local(L, s, p, &seam);
    const LayoutSegment& g = L.segments[s];
    for (int i = 0; i < 3; ++i) t.atlas[i] = local_to_atlas(g, t.local[i].x(), t.local[i].y());
    out.push_back(t);
    if (!seam) continue;
    double hi = t.local[0].x();
    for (const auto& q : t.local) hi = std::max(hi, q.x());
    const double shift = hi > g.h ? -double(g.h) : double(g.h);
    t.copy = 1;
    for (int i = 0; i < 3; ++i) {
      t.local[i].x() += shift;
      t.atlas[i] = local_to_atlas(g, t.local[i].x(), t.local[i].y());
    }
    out.push_back(t);
  }
  return out;
}

StmCoordinates stm_coordinates(const Mesh& mesh, const Layout& L, const std::vector<int>& face_segment) {
  StmCoordinates r;
  r.face_segment = face_segment.size() == mesh.n_faces() ? face_segment : assign_faces(mesh, L);
  r.mesh = mesh;
  r.mesh.request_halfedge_texcoords2D();
  const std::vector<AtlasTriangle> tris = atlas_triangles(mesh, L, r.face_segment);
  for (const auto& t : tris) {
    if (t.copy != 0) {
      ++r.seam_faces;
      continue;
    }
    const auto f = r.mesh.face_handle(t.face);
    // Corners in fv order, as atlas_triangles takes them.
    int k = 0;
    for (auto v : r.mesh.fv_range(f)) {
      for (auto h : r.mesh.fh_range(f))
        if (r.mesh.to_vertex_handle(h) == v)
          r.mesh.set_texcoord2D(h, Mesh::TexCoord2D(t.atlas[k].x() / L.size, t.atlas[k].y() / L.size));
      ++k;
    }
  }
  r.coverage = L.coverage;
  r.stretch = l2_stretch(r.mesh);
  return r;
}

double l2_stretch(const Mesh& mesh, const std::vector<int>& faces) {
  if (!mesh.has_halfedge_texcoords2D()) throw InputError("l2_stretch needs texture coordinates");
  std::vector<int> fl = faces;
  if (fl.empty())
    for (auto f : mesh.faces()) fl.push_back(f.idx());
  double A3 = 0, A2 = 0, sum = 0;
  for (int fi : fl) {
    const auto f = mesh.face_handle(fi);
    Eigen::Vector3d q[3];
    Eigen::Vector2d st[3];
    int k = 0;
    for (auto h : mesh.fh_range(f)) {
      q[k] = point(mesh, mesh.to_vertex_handle(h));
      const auto& t = mesh.texcoord2D(h);
      st[k] = {t[0], t[1]};
      ++k;
    }
    const double a3 = triangle_area(q[0], q[1], q[2]);
    const double a2 = 0.5 * ((st[1].x() - st[0].x()) * (st[2].y() - st[0].y()) - (st[2].x() - st[0].x()) * (st[1].y() - st[0].y()));
    A3 += a3;
    A2 += std::abs(a2);
    if (a2 == 0) continue;  // degenerate in the parameter domain: no finite stretch; skipped
    // Sander et al. 2001: Ss = dq/ds, St = dq/dt of the affine map (s, t) -> q.
    const Eigen::Vector3d Ss = (q[0] * (st[1].y() - st[2].y()) + q[1] * (st[2].y() - st[0].y()) + q[2] * (st[0].y() - st[1].y())) / (2 * a2);
    const Eigen::Vector3d St = (q[0] * (st[2].x() - st[1].x()) + q[1] * (st[0].x() - st[2].x()) + q[2] * (st[1].x() - st[0].x())) / (2 * a2);
    sum += a3 * 0.5 * (Ss.squaredNorm() + St.squaredNorm());
  }
  if (!(A3 > 0) || !(A2 > 0)) return 0;
  // Scaling the domain by k (area by k^2) divides the squared stretch by k^2: A2 k^2 = A3.
  return std::sqrt(sum / A3 * (A2 / A3));
}

}  // namespace sdm
