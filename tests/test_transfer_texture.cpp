// Texture transfer between models with the same skeleton branching (transfer_texture): the same
// shape tessellated anew gets the same picture (PSNR per view against the source), a colour band
// painted on one branch lands on the same branch of a bent and thickened target, and a target
// with another branching is refused with nothing written.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/transfer/transfer_texture.h"
#include "libstm/registration/correspondence_jumps.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/mesh/spatial_order.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/render/render_atlas.h"
#include "libstm/render/render_mesh.h"
#include "libstm/layout/segments.h"
#include "libstm/geometry/triangle_bvh.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

namespace {

const Eigen::Vector3d kArm = synth::kYpsilonArm;
using synth::mean_edge;
using synth::remeshed;

// A smooth colour over space (a few periods across the models), in [0, 1].
Eigen::Vector3d smooth_color(const Eigen::Vector3d& p) {
  return {0.5 + 0.35 * std::sin(3.1 * p.x() + 1.3 * p.z()), 0.5 + 0.35 * std::cos(2.7 * p.y() - 0.9 * p.x()),
          0.5 + 0.35 * std::sin(2.3 * p.z() + 1.9 * p.y() + 0.5)};
}

// The same plus a pure red band across the right arm (axial distance 0.6 to 0.8 along it).
Eigen::Vector3d band_color(const Eigen::Vector3d& p) {
  const double s = p.dot(kArm), off = (p - s * kArm).norm();
  if (s > 0.6 && s < 0.8 && off < 0.5) return {1, 0, 0};
  Eigen::Vector3d c = smooth_color(p);
  c.x() *= 0.6;  // keep the rest of the model clearly not red
  return c;
}

// Gives `mesh` uv (its own STM) and returns a texture in which color(p) is painted: the atlas of
// surface positions is rendered and every texel coloured from its position.
sdm::Image bake_texture(sdm::GlContext& gl, sdm::Mesh& mesh, const sdm::Skeleton& sk, Eigen::Vector3d (*color)(const Eigen::Vector3d&)) {
  sdm::LayoutOptions lo;
  lo.size = 1024;
  lo.margin = 6;
  const sdm::Layout layout = sdm::compute_layout(mesh, sk, lo);
  std::vector<Eigen::Vector4f> corners;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) {
      const Eigen::Vector3d p = sdm::point(mesh, v);
      corners.emplace_back(float(p.x()), float(p.y()), float(p.z()), 1.f);
    }
  const sdm::FloatImage pos = sdm::render_atlas_values(gl, mesh, layout, corners);
  sdm::Image tex(pos.width, pos.height, 4, 255);
  for (int y = 0; y < pos.height; ++y)
    for (int x = 0; x < pos.width; ++x) {
      const float* q = pos.at(x, y);
      const Eigen::Vector3d c = color(Eigen::Vector3d(q[0], q[1], q[2]));
      for (int k = 0; k < 3; ++k) tex.at(x, y)[k] = uint8_t(std::lround(255 * std::clamp(c[k], 0.0, 1.0)));
    }
  mesh = sdm::stm_coordinates(mesh, layout).mesh;
  return tex;
}

// What `sdm remesh --factor F` makes: the equilateral edge for the mesh's area and vertex count
// times F, 8 iterations, vertices projected onto the input, renumbered in spatial order.
sdm::Mesh remeshed_like_cli(const sdm::Mesh& mesh, double factor) {
  double area = 0;
  for (auto f : mesh.faces()) area += mesh.calc_face_area(f);
  const double edge = std::sqrt(2.0 * area / (std::sqrt(3.0) * double(mesh.n_vertices()))) * factor;
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(mesh), sdm::face_matrix(mesh));
  sdm::Mesh copy = mesh;
  copy.release_halfedge_texcoords2D();
  sdm::isotropic_remesh(copy, edge, 8, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  return sdm::spatially_ordered(copy);
}

std::string views_text(const std::vector<double>& p) {
  std::ostringstream o;
  o.precision(3);
  for (double x : p) o << " " << x;
  return o.str();
}

// Every view at least min_db (each view reported on failure).
void check_views(const std::vector<double>& p, double min_db) {
  for (size_t v = 0; v < p.size(); ++v) {
    INFO("view " << v << ": PSNR " << p[v] << " dB");
    CHECK(p[v] >= min_db);
  }
}

// The skeleton `sdm transfer` extracts.
sdm::Skeleton extracted(const sdm::Mesh& m) { return sdm::extract_skeleton(m, sdm::transfer_skeleton_options()); }

// PSNR per view between the source (own uv) and the target (transferred uv), unlit, over the
// pixels both cover.
std::vector<double> compare_views(sdm::GlContext& gl, const sdm::Mesh& a, const sdm::Image& ta, const sdm::Mesh& b,
                                  const sdm::Image& tb, const std::string& dump_name) {
  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  ro.elevation_deg = 15;
  sdm::bounding_box(a, ro.bbox_min, ro.bbox_max);
  std::vector<double> out;
  for (int view = 0; view < 8; ++view) {
    ro.azimuth_deg = 45.0 * view;
    std::vector<uint8_t> ma, mb;
    ro.texture = &ta;
    const sdm::Image ia = sdm::render_mesh(gl, a, ro, &ma);
    ro.texture = &tb;
    const sdm::Image ib = sdm::render_mesh(gl, b, ro, &mb);
    for (size_t i = 0; i < ma.size(); ++i) ma[i] = ma[i] && mb[i] ? 255 : 0;
    out.push_back(sdm::psnr(ia, ib, &ma));
    if (const char* dump = std::getenv("SDM_TEST_DUMP"))
      sdm::write_png(sdm::side_by_side({ia, ib}), std::string(dump) + "/" + dump_name + std::to_string(view) + ".png");
  }
  return out;
}

// Every vertex goes to the nearer end of its nearest skeleton edge (a hand-made skeleton's vertex map).
void assign_vertices(const sdm::Mesh& mesh, sdm::Skeleton& sk) {
  sk.vertex_node.clear();
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = sdm::point(mesh, v);
    double best = 1e300;
    int node = 0;
    for (const auto& e : sk.edges) {
      double t = 0;
      const double d = sdm::distance_to_segment(p, sk.nodes[e[0]], sk.nodes[e[1]], &t);
      if (d < best) best = d, node = t < 0.5 ? e[0] : e[1];
    }
    sk.vertex_node.push_back(node);
  }
}

// Every edge longer than `longer` cut into `pieces` straight pieces (the same polyline, more nodes).
sdm::Skeleton subdivided(const sdm::Skeleton& sk, double longer, int pieces) {
  sdm::Skeleton out;
  out.nodes = sk.nodes;
  for (const auto& e : sk.edges) {
    const Eigen::Vector3d a = sk.nodes[e[0]], b = sk.nodes[e[1]];
    if ((b - a).norm() <= longer) {
      out.edges.push_back(e);
      continue;
    }
    int prev = e[0];
    for (int k = 1; k < pieces; ++k) {
      out.nodes.push_back(a + (b - a) * (double(k) / pieces));
      out.edges.push_back({prev, int(out.nodes.size()) - 1});
      prev = int(out.nodes.size()) - 1;
    }
    out.edges.push_back({prev, e[1]});
  }
  return out;
}

// Spot's hand-made skeleton (as in test_render_stm).
sdm::Skeleton spot_skeleton(const sdm::Mesh& mesh, double cut_longer = 1e9) {
  sdm::Skeleton sk;
  sk.nodes = {{0, 0.0, 1.0},   {0, -0.1, 0.62},    {0, -0.05, 0.1},   {0, 0.3, -0.25},  {0, 0.5, -0.42},
              {0.2, -0.35, 0.07}, {-0.2, -0.35, 0.07}, {0.2, -0.65, 0.07}, {-0.2, -0.65, 0.07},
              {0.17, -0.35, 0.66}, {-0.17, -0.35, 0.66}, {0.17, -0.65, 0.66}, {-0.17, -0.65, 0.66},
              {0.17, 0.88, -0.27}, {-0.17, 0.88, -0.27}, {0.42, 0.68, -0.21}, {-0.42, 0.68, -0.21}};
  sk.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {2, 5}, {5, 7}, {2, 6}, {6, 8}, {1, 9}, {9, 11}, {1, 10}, {10, 12},
              {4, 13}, {4, 14}, {4, 15}, {4, 16}};
  sk = subdivided(sk, cut_longer, 3);
  assign_vertices(mesh, sk);
  return sk;
}

using synth::bend_ypsilon_arm;

// The ypsilon's ideal skeleton (junction at the origin, arms along the primitive's capsule axes),
// arm k cut into per_arm[k] edges, every node moved by `move`.
sdm::Skeleton ypsilon_skeleton(const sdm::Mesh& mesh, std::array<int, 3> per_arm,
                               const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& move = nullptr) {
  const Eigen::Vector3d ends[3] = {{0, -1.1, 0}, {-0.78, 0.78, 0}, {0.78, 0.78, 0}};
  sdm::Skeleton sk;
  sk.nodes.push_back(Eigen::Vector3d::Zero());
  for (int k = 0; k < 3; ++k) {
    int prev = 0;
    for (int i = 1; i <= per_arm[k]; ++i) {
      const Eigen::Vector3d p = ends[k] * (double(i) / per_arm[k]);
      sk.nodes.push_back(move ? move(p) : p);
      sk.edges.push_back({prev, int(sk.nodes.size()) - 1});
      prev = int(sk.nodes.size()) - 1;
    }
  }
  assign_vertices(mesh, sk);
  return sk;
}

}  // namespace

// The source with skeleton sa and a baked smooth texture, the target with skeleton sb: transfer, then
// compare 8 views.
// With carry false the given target skeleton is used as it is (what the resampling tests need);
// with carry true the transfer may replace it by the source's carried over, as `sdm transfer` does.
std::vector<double> transfer_round(sdm::GlContext& gl, sdm::Mesh a, const sdm::Skeleton& sa, const sdm::Mesh& b, const sdm::Skeleton& sb,
                                  sdm::TextureTransfer* out = nullptr, bool carry = false, const std::string& dump_name = "ypsilon_transfer_view") {
  const sdm::Image tex = bake_texture(gl, a, sa, smooth_color);
  sdm::TransferOptions to;
  to.size = 1024;
  to.carry_same_shape = carry;
  sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, sa, b, sb, to);
  const std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, dump_name);
  if (out) *out = std::move(r);
  return p;
}

// The acceptance as a user gets it: skeletons extracted from each tessellation, as `sdm transfer`
// does. The target is recognised as the source's shape and takes the source's skeleton carried
// over (its own extraction puts the junction elsewhere: 26-33 dB before, docs/DECISIONS.md, section 5).
TEST_CASE("transfer onto a new tessellation of the ypsilon with extracted skeletons reproduces the source", "[transfer_texture]") {
  sdm::GlContext gl;
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  const sdm::Mesh b = remeshed(a, 0.75);
  REQUIRE(b.n_vertices() != a.n_vertices());
  const sdm::Skeleton sa = extracted(a), sb = extracted(b);
  sdm::TextureTransfer r;
  const std::vector<double> p = transfer_round(gl, a, sa, b, sb, &r, true);
  CHECK(r.kind == sdm::CorrespondenceKind::carried);
  CHECK(r.registration.rms < 0.002);
  // Both skeletons share one graph; every shared node owns vertices in both models.
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.pruned_a.empty());
  CHECK(r.skeletons.pruned_b.empty());
  for (const auto* sk : {&r.skeletons.a, &r.skeletons.b}) {
    std::vector<int> count(sk->nodes.size(), 0);
    for (int x : sk->vertex_node) ++count[x];
    CHECK(*std::min_element(count.begin(), count.end()) >= 1);
  }
  WARN("ypsilon onto its remesh, extracted skeletons: registered to " << 100 * r.registration.rms << " % (RMS), PSNR per view" << views_text(p));
  check_views(p, 28.0);
}

// A copy turned, scaled and moved (and tessellated anew) is the same shape: registered from the
// principal axes, it takes the source's skeleton, and turned back it looks like the source.
TEST_CASE("transfer onto a turned, scaled and retessellated ypsilon carries the skeleton", "[transfer_texture]") {
  sdm::GlContext gl;
  sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  sdm::Similarity T;
  T.scale = 2.5;
  T.rotation = Eigen::AngleAxisd(100 * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation = {3, -1, 2};
  const sdm::Mesh b = synth::moved(remeshed(a, 0.8), [&](const Eigen::Vector3d& p) { return T(p); });
  const sdm::Skeleton sa = extracted(a), sb = extracted(b);
  const sdm::Image tex = bake_texture(gl, a, sa, smooth_color);
  sdm::TransferOptions to;
  to.size = 1024;
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, sa, b, sb, to);
  CHECK(r.kind == sdm::CorrespondenceKind::carried);
  CHECK(std::abs(r.registration.transform.scale / T.scale - 1) < 0.005);
  const sdm::Mesh back = synth::moved(r.target, [&](const Eigen::Vector3d& p) { return T.inverse()(p); });
  const std::vector<double> p = compare_views(gl, a, tex, back, r.atlas, "ypsilon_turned_view");
  WARN("ypsilon onto a turned copy: registered to " << 100 * r.registration.rms << " % (RMS), PSNR per view" << views_text(p));
  check_views(p, 28.0);
}

// A coarse real mesh (231 vertices, quads fan-triangulated) and its remesh: the remesh cuts the
// polyhedron's corners, so moved as a whole the two lie 0.5 % of the diagonal apart, hardly more
// than bent (0.4 %); it is still the same shape and takes the source's skeleton carried over.
TEST_CASE("transfer onto the remesh of a coarse genus-2 mesh carries the skeleton", "[transfer_texture]") {
  sdm::GlContext gl;
  const sdm::Mesh a = sdm::load_mesh(std::string(SDM_TEST_DATA) + "/double-torus-example.off").mesh;
  const sdm::Mesh b = remeshed_like_cli(a, 1.0);
  REQUIRE(b.n_vertices() != a.n_vertices());
  sdm::TextureTransfer r;
  const std::vector<double> p = transfer_round(gl, a, extracted(a), b, extracted(b), &r, true, "double_torus_view");
  CHECK(r.kind == sdm::CorrespondenceKind::carried);
  CHECK(r.skeletons.b.cycles() == 2);
  WARN("double torus onto its remesh: moved " << 100 * r.registration.rms << " %, bent " << 100 * r.fit_rms << " % (RMS), PSNR per view"
                                             << views_text(p));
  // The remesh is 0.5 % of the diagonal off the source's surface (its corners cut), which moves
  // silhouettes and the spatial colour itself: 21.7-26.5 dB carried, 21.2-26.2 bent, 8.0-8.4 with
  // the two extracted skeletons matched.
  check_views(p, 20.0);
}

// The resampling itself, with hand-made skeletons of other node counts on each arm.
TEST_CASE("transfer between hand-made ypsilon skeletons with other node counts shares one graph", "[transfer_texture]") {
  sdm::GlContext gl;
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  const sdm::Mesh b = remeshed(a, 0.75);
  const sdm::Skeleton sa = ypsilon_skeleton(a, {2, 2, 2}), sb = ypsilon_skeleton(b, {3, 1, 4});
  sdm::TextureTransfer r;
  const std::vector<double> p = transfer_round(gl, a, sa, b, sb, &r);
  // Both skeletons share one graph with every chain at the larger count (or more, by the split rule).
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.a.edges.size() >= 9);
  CHECK(r.skeletons.match.confidence > 0.3);
  // Matched segments' frames correspond (same pose, so the same directions).
  for (size_t s = 0; s < r.layout_a.segments.size(); ++s) {
    CHECK(r.layout_a.segments[s].e1.dot(r.layout_b.segments[s].e1) > 0.999);
    CHECK(r.layout_a.segments[s].axis.dot(r.layout_b.segments[s].axis) > 0.999);
  }
  check_views(p, 28.0);
}

// A ring skeleton around z (radius 1, in the plane z = 0) with n nodes, the first at angle `start`.
sdm::Skeleton ring_skeleton(const sdm::Mesh& mesh, int n, double start) {
  sdm::Skeleton sk;
  for (int i = 0; i < n; ++i) {
    const double t = start + 2 * M_PI * i / n;
    sk.nodes.emplace_back(std::cos(t), std::sin(t), 0);
    sk.edges.push_back({i, (i + 1) % n});
  }
  assign_vertices(mesh, sk);
  return sk;
}

TEST_CASE("transfer onto a new tessellation of the donut lines up the rings", "[transfer_texture]") {
  sdm::GlContext gl;
  const sdm::Mesh a = sdm::make_primitive("donut");
  const sdm::Mesh b = remeshed(a, 0.8);
  // Pure cycles: the rings' first nodes (their key nodes) lie at other angles.
  const sdm::Skeleton sa = ring_skeleton(a, 8, 0.0), sb = ring_skeleton(b, 11, 2.0);
  const std::vector<double> p = transfer_round(gl, a, sa, b, sb);
  check_views(p, 28.0);
}

TEST_CASE("transfer onto a new tessellation of Spot with hand-made skeletons reproduces its texture", "[transfer_texture]") {
  sdm::GlContext gl;
  std::string tex_path;
  sdm::LoadedMesh a_read = sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
  tex_path = std::move(a_read.texture);
  const sdm::Mesh a = std::move(a_read.mesh);
  REQUIRE(!tex_path.empty());
  const sdm::Image tex = sdm::read_png(tex_path);
  const sdm::Skeleton sa = spot_skeleton(a);
  const sdm::Mesh b = remeshed(a, 0.9);
  REQUIRE(b.n_vertices() != a.n_vertices());
  // The target's skeleton has the same branching with other node counts: the long edges cut in three.
  const sdm::Skeleton sb = spot_skeleton(b, 0.3);
  REQUIRE(sb.nodes.size() > sa.nodes.size());
  sdm::TransferOptions to;
  to.size = 2048;
  to.carry_same_shape = false;  // the hand-made target skeleton as it is
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, sa, b, sb, to);
  CHECK(r.kind != sdm::CorrespondenceKind::carried);
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.a.edges.size() >= sb.edges.size());
  const std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, "spot_transfer_view");
  check_views(p, 28.0);
}

// The acceptance as a user gets it, on the remesh of the demo (`sdm remesh --factor 1.2`). Spot's
// extraction depends on the tessellation (10 ends here, 8 on the remesh, which cannot be matched):
// the target is recognised as Spot's shape and takes Spot's skeleton carried over.
TEST_CASE("transfer onto a new tessellation of Spot with extracted skeletons reproduces its texture", "[transfer_texture]") {
  sdm::GlContext gl;
  std::string tex_path;
  sdm::LoadedMesh a_read = sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
  tex_path = std::move(a_read.texture);
  const sdm::Mesh a = std::move(a_read.mesh);
  REQUIRE(!tex_path.empty());
  const sdm::Image tex = sdm::read_png(tex_path);
  const sdm::Mesh b = remeshed_like_cli(a, 1.2);
  REQUIRE(b.n_vertices() != a.n_vertices());
  const sdm::Skeleton sa = extracted(a), sb = extracted(b);
  sdm::TransferOptions to;
  to.size = 2048;
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, sa, b, sb, to);
  CHECK(r.kind == sdm::CorrespondenceKind::carried);
  CHECK(r.registration.rms < 0.002);
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.pruned_a.size() + r.skeletons.pruned_b.size() == 0);
  CHECK(r.skeletons.match.a.keys.size() >= 12);  // legs, horns, ears, snout and the three junctions
  const std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, "spot_transfer_view");
  WARN("Spot onto its remesh (" << b.n_vertices() << " vertices), extracted skeletons (" << sa.end_nodes() << " and " << sb.end_nodes()
                                << " ends), registered to " << 100 * r.registration.rms << " % (RMS): PSNR per view" << views_text(p));
  check_views(p, 28.0);
}

// `a` (textured by `tex`) onto its own isotropic remesh with the commands' defaults: four unlit views
// framed alike (0, 90, 180, 270 degrees) at 31 dB or more on average, and no speck
// (correspondence_jumps: no target vertex whose source point lies over 5 % of the diagonal from most
// of its neighbours').
void check_onto_own_remesh(const sdm::Mesh& a, const sdm::Image& tex, const std::string& name) {
  sdm::GlContext gl;
  const sdm::Mesh b = remeshed_like_cli(a, 1.0);
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, extracted(a), b, extracted(b), sdm::TransferOptions{});
  const sdm::CorrespondenceJumps jumps = sdm::correspondence_jumps(a, b, r.correspondence, 0.05 * sdm::bounding_box_diagonal(a));
  std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, name + "_remesh_view");
  std::vector<double> four;
  for (size_t v = 0; v < p.size(); v += 2) four.push_back(p[v]);  // 0, 90, 180, 270 degrees
  double mean = 0;
  for (double x : four) mean += x / double(four.size());
  WARN(name << " onto its remesh (" << b.n_vertices() << " vertices, 1024 atlas): PSNR per view" << views_text(four) << ", mean " << mean
            << " dB; jumping share " << jumps.area_share << " (" << jumps.vertices << " vertices)");
  CHECK(jumps.area_share <= 0.001);
  CHECK(mean >= 31.0);
}

// What `sdm remesh` and `sdm transfer` do by default (the remesh's own edge length, a 1024 atlas).
TEST_CASE("Spot onto its own isotropic remesh with the command's defaults: no speck, 31 dB or more", "[transfer_texture]") {
  std::string tex_path;
  sdm::LoadedMesh a_read = sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
  tex_path = std::move(a_read.texture);
  const sdm::Mesh a = std::move(a_read.mesh);
  check_onto_own_remesh(a, sdm::read_png(tex_path), "spot");
}

// A second textured model for the remesh case: the Viewpoint cow of ../shared/models/wild (repaired on
// load: one pinched vertex) given a planar projection uv across its flank (continuous: no seam, so the
// picture has no jump that a remesh could not follow) and Spot's texture, transferred onto its own
// isotropic remesh with the command's defaults.
sdm::Mesh planar_projected(const sdm::Mesh& mesh) {
  Eigen::Vector3d lo, hi;
  sdm::bounding_box(mesh, lo, hi);
  const Eigen::Vector3d size = hi - lo;
  int thin = 0;  // project along the thinnest side of the box (the cow's width)
  for (int k = 1; k < 3; ++k)
    if (size[k] < size[thin]) thin = k;
  const int i = (thin + 1) % 3, j = (thin + 2) % 3;
  sdm::Mesh m = mesh;
  m.request_halfedge_texcoords2D();
  for (auto h : m.halfedges()) {
    const Eigen::Vector3d p = sdm::point(m, m.to_vertex_handle(h));
    m.set_texcoord2D(h, sdm::Mesh::TexCoord2D(float((p[i] - lo[i]) / size[i]), float((p[j] - lo[j]) / size[j])));
  }
  return m;
}

TEST_CASE("The cow with a planar projected uv onto its own isotropic remesh: no speck, 31 dB or more", "[transfer_texture]") {
  const std::string cow = std::string(SDM_TEST_DATA) + "/../../../shared/models/wild/cow.obj";
  if (!std::filesystem::exists(cow)) {
    WARN("../shared/models/wild is not beside the repository: skipped");
    return;
  }
  const sdm::Image tex = sdm::read_png(std::string(SDM_EXAMPLES) + "/spot/spot_texture.png");
  check_onto_own_remesh(planar_projected(sdm::load_mesh(cow, sdm::LoadOptions{}).mesh), tex, "cow");
}

// The band test with hand-made skeletons (the ideal ones, bent with the target) or extracted ones.
void check_band(bool extracted) {
  sdm::GlContext gl;
  sdm::Mesh a = sdm::make_primitive("ypsilon", 2000);
  const sdm::Skeleton sa = extracted ? sdm::extract_skeleton(a, sdm::transfer_skeleton_options()) : ypsilon_skeleton(a, {2, 2, 2});
  const sdm::Image tex = bake_texture(gl, a, sa, band_color);
  // Target: the right arm bent 50 degrees out of the plane and 40 % thicker, then tessellated anew. Faces of
  // the bent copy are labelled "arm" when their undeformed centroid lies past 0.3 along the arm;
  // the remeshed target's faces take the label of the nearest face of the bent copy.
  auto bend = [](const Eigen::Vector3d& p) { return bend_ypsilon_arm(p, 50, 0.4); };
  sdm::Mesh bent = sdm::make_primitive("ypsilon", 2000);
  for (auto v : bent.vertices()) {
    const Eigen::Vector3d q = bend(sdm::point(bent, v));
    bent.set_point(v, sdm::Mesh::Point(q.x(), q.y(), q.z()));
  }
  std::vector<char> bent_arm(bent.n_faces(), 0);
  for (auto f : a.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : a.fv_range(f)) c += sdm::point(a, v) / 3;
    bent_arm[f.idx()] = c.dot(kArm) > 0.3 && (c - c.dot(kArm) * kArm).norm() < 0.5;
  }
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(bent), sdm::face_matrix(bent));
  sdm::Mesh b = bent;
  sdm::isotropic_remesh(b, 0.8 * mean_edge(bent), 4, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  // Hand-made: the ideal skeleton bent the same way, with more nodes on the bent arm.
  const sdm::Skeleton sb = extracted ? sdm::extract_skeleton(b, sdm::transfer_skeleton_options()) : ypsilon_skeleton(b, {2, 3, 5}, bend);
  if (!extracted) REQUIRE(sdm::branching_difference(sa, sb).empty());
  sdm::TransferOptions to;
  to.size = 1024;
  to.carry_same_shape = extracted;  // hand-made skeletons as they are; extracted ones as `sdm transfer` takes them
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, a, tex, sa, b, sb, to);
  if (extracted) {
    CHECK(r.kind == sdm::CorrespondenceKind::bent);
    WARN("bent target: registered to " << 100 * r.registration.rms << " % (RMS), bent to " << 100 * r.fit_rms << " % (RMS), "
                                       << 100 * r.fit_p99 << " % (99th percentile): " << (r.kind == sdm::CorrespondenceKind::bent ? "source's skeleton bent" : "extracted skeleton"));
  }

  // Label texture: white on the left half, black on the right; arm faces sample the white half.
  sdm::Image label(64, 64, 4, 255);
  for (int y = 0; y < 64; ++y)
    for (int x = 32; x < 64; ++x)
      for (int k = 0; k < 3; ++k) label.at(x, y)[k] = 0;
  sdm::Mesh labelled = b;
  labelled.request_halfedge_texcoords2D();
  int arm_faces = 0;
  for (auto f : labelled.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : labelled.fv_range(f)) c += sdm::point(labelled, v) / 3;
    const bool arm = bent_arm[bvh.closest_point(c).face];
    arm_faces += arm;
    for (auto h : labelled.fh_range(f)) labelled.set_texcoord2D(h, sdm::Mesh::TexCoord2D(arm ? 0.25 : 0.75, 0.5));
  }
  REQUIRE(arm_faces > 0);

  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  ro.samples = 1;
  ro.background = {0, 0, 255, 255};  // neither band red nor label white
  // Views across the plane the arm bends in (direction (-1, 1, 0): azimuth -90, elevation 45), from
  // both sides, and one oblique.
  for (auto [az, el] : {std::pair<double, double>{-90, 45}, {90, -45}, {-60, 30}}) {
    ro.azimuth_deg = az;
    ro.elevation_deg = el;
    ro.texture = &r.atlas;
    const sdm::Image img = sdm::render_mesh(gl, r.target, ro);
    ro.texture = &label;
    const sdm::Image lab = sdm::render_mesh(gl, labelled, ro);
    long band = 0, on_arm = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const uint8_t* c = img.at(x, y);
        if (!(c[0] > 200 && c[1] < 50 && c[2] < 50)) continue;
        ++band;
        on_arm += lab.at(x, y)[0] > 128;
      }
    // The source's band from the same camera: the target's is as wide along the arm and about 1.4
    // times as thick, so it covers somewhat more pixels, never several times more or less.
    ro.texture = &tex;
    const sdm::Image src = sdm::render_mesh(gl, a, ro);
    long band_source = 0;
    for (int y = 0; y < src.height; ++y)
      for (int x = 0; x < src.width; ++x) band_source += src.at(x, y)[0] > 200 && src.at(x, y)[1] < 50 && src.at(x, y)[2] < 50;
    INFO("azimuth " << az << " elevation " << el << ": " << band << " band pixels, " << on_arm << " on the bent arm; " << band_source << " in the source");
    CHECK(band > 500);
    CHECK(on_arm >= 0.98 * band);
    CHECK(band > 0.9 * band_source);
    CHECK(band < 2.0 * band_source);
    if (const char* dump = std::getenv("SDM_TEST_DUMP"))
      sdm::write_png(sdm::side_by_side({src, img, lab}), std::string(dump) + "/band_az" + std::to_string(int(az)) + "_el" +
                                                           std::to_string(int(el)) + ".png");
  }
}

TEST_CASE("a band painted on one branch lands on the same branch of a bent and thickened target", "[transfer_texture]") {
  check_band(false);
}

// The acceptance as a user gets it: skeletons extracted from each model, as `sdm transfer` does.
// The source's skeleton is bent onto the target (fit_skeleton), whatever the target's own
// extraction found (it depends on the tessellation and on float rounding).
TEST_CASE("with extracted skeletons a band lands on the same branch of a bent and thickened target", "[transfer_texture]") {
  check_band(true);
}

namespace {

// Writes the ypsilon with a baked smooth texture as OBJ + MTL + PNG into `dir`; returns the OBJ path.
std::string write_textured_ypsilon(sdm::GlContext& gl, const test_util::TempDir& dir, sdm::Mesh* mesh = nullptr,
                                   sdm::Image* texture = nullptr) {
  sdm::Mesh a = sdm::make_primitive("ypsilon", 1200);
  const sdm::Image tex = bake_texture(gl, a, ypsilon_skeleton(a, {2, 2, 2}), smooth_color);
  sdm::write_png(tex, dir / "source.png");
  sdm::write_mesh(a, dir / "source.obj", dir / "source.png");
  if (mesh) *mesh = a;
  if (texture) *texture = tex;
  return dir / "source.obj";
}

}  // namespace

TEST_CASE("sdm transfer writes the target with uv and its atlas and preview", "[transfer_texture]") {
  sdm::GlContext gl;
  test_util::TempDir dir;
  sdm::Mesh a;
  sdm::Image tex;
  const std::string src = write_textured_ypsilon(gl, dir, &a, &tex);
  const sdm::Mesh b = remeshed(a, 0.8);
  sdm::write_mesh(b, dir / "target.obj");
  // Skeletons given as files (used as they are), or extracted by the command (the target then takes
  // the source's, carried over, since it is the same shape).
  const bool given = GENERATE(true, false);
  sdm::write_skeleton_json(ypsilon_skeleton(a, {2, 2, 2}), dir / "source.json");
  sdm::write_skeleton_json(ypsilon_skeleton(b, {1, 3, 2}), dir / "target.json");
  const std::string skeletons = given ? " --source-skeleton " + (dir / "source.json") + " --target-skeleton " + (dir / "target.json") : "";
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.obj") + " -o " + (dir / "out.obj") +
                                      skeletons + " --size 1024 --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const auto j = nlohmann::json::parse(res.output.substr(res.output.find("{\n")));
  CHECK(j.at("chains").size() == 3);
  CHECK(j.at("keys").size() == 4);
  CHECK(j.at("confidence").get<double>() > 0);
  CHECK(j.at("target_skeleton") == (given ? "given" : "carried"));
  if (!given) CHECK(j.at("registration_rms").get<double>() < 0.002);
  CHECK(std::filesystem::exists(dir / "out_atlas.png"));
  CHECK(std::filesystem::exists(dir / "out_preview.png"));
  CHECK(std::filesystem::exists(dir / "out.mtl"));
  std::string atlas_path;
  sdm::LoadedMesh out_read = sdm::load_mesh(dir / "out.obj");
  atlas_path = std::move(out_read.texture);
  const sdm::Mesh out = std::move(out_read.mesh);
  REQUIRE(out.has_halfedge_texcoords2D());
  REQUIRE(std::filesystem::equivalent(atlas_path, dir / "out_atlas.png"));
  const sdm::Image atlas = sdm::read_png(atlas_path);
  // The written target, with the written atlas, looks like the source.
  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  sdm::bounding_box(a, ro.bbox_min, ro.bbox_max);
  for (double az : {0.0, 135.0}) {
    ro.azimuth_deg = az;
    std::vector<uint8_t> ma, mb;
    ro.texture = &tex;
    const sdm::Image ia = sdm::render_mesh(gl, a, ro, &ma);
    ro.texture = &atlas;
    const sdm::Image ib = sdm::render_mesh(gl, out, ro, &mb);
    for (size_t i = 0; i < ma.size(); ++i) ma[i] = ma[i] && mb[i] ? 255 : 0;
    const double p = sdm::psnr(ia, ib, &ma);
    INFO("azimuth " << az << ": PSNR " << p);
    CHECK(p >= 28.0);
  }
}

namespace {

// The vertex count and the red/green/blue properties of a PLY file's header.
bool ply_has_uchar_colors(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = text.substr(0, text.find("end_header"));
  return text.find("property uchar red") != std::string::npos && text.find("property uchar green") != std::string::npos &&
         text.find("property uchar blue") != std::string::npos;
}

size_t files_in(const test_util::TempDir& dir) {
  return size_t(std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator()));
}

}  // namespace

// A textured source (the ypsilon with smooth_color baked into its STM texture) onto its remesh:
// the target's vertex colours are the texture at each vertex's source point, so they follow
// smooth_color at the target's own positions, to the baked texture's and the registration's
// accuracy and the 8-bit steps.
TEST_CASE("sdm transfer --vertex-colors writes the target's vertices coloured from the source's texture", "[transfer_texture]") {
  sdm::GlContext gl;
  test_util::TempDir dir;
  sdm::Mesh a;
  const std::string src = write_textured_ypsilon(gl, dir, &a);
  const sdm::Mesh b = remeshed(a, 0.8);
  sdm::write_mesh(b, dir / "target.off");
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.off") + " -o " + (dir / "out.obj") +
                                      " --size 1024 --vertex-colors " + (dir / "colors.ply") + " --correspondence " + (dir / "c.txt") + " --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const auto j = nlohmann::json::parse(res.output.substr(res.output.find("{\n")));
  CHECK(j.at("vertex_colors_from") == "texture");
  CHECK(ply_has_uchar_colors(dir / "colors.ply"));
  std::vector<Eigen::Vector3f> colors;
  sdm::LoadedMesh out_read = sdm::load_mesh(dir / "colors.ply");
  colors = std::move(out_read.colors);
  const sdm::Mesh out = std::move(out_read.mesh);
  REQUIRE(out.n_vertices() == b.n_vertices());
  REQUIRE(colors.size() == b.n_vertices());
  double worst = 0, sum = 0;
  size_t far = 0;
  for (auto v : out.vertices()) {
    const double e = (colors[v.idx()].cast<double>() - smooth_color(sdm::point(out, v))).cwiseAbs().maxCoeff();
    worst = std::max(worst, e), sum += e;
    far += e > 8.0 / 255;
  }
  // Measured: mean 0.5/255; one vertex (of 1981) off by 75/255, at the pole of an arm's capsule
  // where the baked texture itself is off (the STM's uv degenerate there).
  WARN("--vertex-colors from the texture: colour error mean " << 255 * sum / out.n_vertices() << ", largest " << 255 * worst
                                                              << " (of 255); " << far << " of " << out.n_vertices() << " vertices over 8/255");
  CHECK(sum / out.n_vertices() < 1.5 / 255);
  CHECK(far <= out.n_vertices() / 1000);
}

// What transfer writes twice, the target textured (OBJ and atlas) and coloured per vertex (PLY),
// drawn by sdm render (unlit, four views): the same pictures but for the colours' blending across
// faces, where the texture varies within them.
TEST_CASE("sdm render draws the PLY of transfer --vertex-colors as the textured OBJ of the same transfer", "[transfer_texture][render]") {
  sdm::GlContext gl;
  test_util::TempDir dir;
  sdm::Mesh a;
  const std::string src = write_textured_ypsilon(gl, dir, &a);
  sdm::write_mesh(remeshed(a, 0.8), dir / "target.off");
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.off") + " -o " + (dir / "out.obj") +
                                      " --size 1024 --vertex-colors " + (dir / "colors.ply"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const std::string views = " --unlit --views 4 --width 320 --height 320 -o ";
  const auto textured = test_util::run_sdm("render " + (dir / "out.obj") + views + (dir / "textured.png"));
  const auto colored = test_util::run_sdm("render " + (dir / "colors.ply") + views + (dir / "colored.png"));
  const auto flat = test_util::run_sdm("render " + (dir / "colors.ply") + " --no-texture" + views + (dir / "flat.png"));
  INFO(textured.output << colored.output << flat.output);
  REQUIRE((textured.exit_code == 0 && colored.exit_code == 0 && flat.exit_code == 0));
  const sdm::Image t = sdm::read_png(dir / "textured.png"), c = sdm::read_png(dir / "colored.png"), f = sdm::read_png(dir / "flat.png");
  REQUIRE(t.pixels.size() == c.pixels.size());
  // Over the pixels either picture covers (the background is white in both).
  std::vector<uint8_t> object(size_t(t.width) * size_t(t.height), 0);
  long covered = 0;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      bool any = false;
      for (int k = 0; k < 3; ++k) any |= t.at(x, y)[k] != 255 || c.at(x, y)[k] != 255;
      object[size_t(y) * size_t(t.width) + size_t(x)] = any, covered += any;
    }
  const double colors_db = sdm::psnr(t, c, &object), flat_db = sdm::psnr(t, f, &object);
  WARN("render of the vertex colours against the textured render: " << colors_db << " dB over " << covered
                                                                      << " pixels (flat grey: " << flat_db << " dB)");
  CHECK(covered > 20000);
  CHECK(colors_db >= 30);
  CHECK(flat_db < 20);  // the colours are what makes the match
}

// A source with vertex colours and no texture (PLY): its colour encodes its position. The target
// (its remesh) is textured from the colours painted into the source's STM, and its vertex colours
// are the source's blended at each vertex's source point: decoded, they give back the target's
// positions to the 8-bit steps (half a step per axis of the box) plus the registration's distance.
TEST_CASE("sdm transfer from a source with PLY vertex colours gives the target's positions back", "[transfer_texture]") {
  test_util::TempDir dir;
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1200);
  Eigen::Vector3d lo, hi;
  sdm::bounding_box(a, lo, hi);
  std::vector<Eigen::Vector3f> source_colors;
  for (auto v : a.vertices()) source_colors.push_back(((sdm::point(a, v) - lo).cwiseQuotient(hi - lo)).cast<float>());
  sdm::write_colored_ply(a, source_colors, dir / "source.ply");
  const sdm::Mesh b = remeshed(a, 0.8);
  sdm::write_mesh(b, dir / "target.obj");
  const auto res = test_util::run_sdm("transfer --source " + (dir / "source.ply") + " --target " + (dir / "target.obj") + " -o " +
                                      (dir / "out.obj") + " --size 1024 --vertex-colors " + (dir / "colors.ply"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  CHECK(res.output.find("from the source's vertex colours") != std::string::npos);
  CHECK(std::filesystem::exists(dir / "out_atlas.png"));
  std::vector<Eigen::Vector3f> colors;
  sdm::LoadedMesh out_read = sdm::load_mesh(dir / "colors.ply");
  colors = std::move(out_read.colors);
  const sdm::Mesh out = std::move(out_read.mesh);
  REQUIRE(colors.size() == b.n_vertices());
  const double steps = 0.5 / 255 * (hi - lo).norm(), diag = (hi - lo).norm();
  double worst = 0, sum = 0;
  for (auto v : out.vertices()) {
    const Eigen::Vector3d p = lo + colors[v.idx()].cast<double>().cwiseProduct(hi - lo);
    const double e = (p - sdm::point(out, v)).norm();
    worst = std::max(worst, e), sum += e;
  }
  WARN("--vertex-colors from PLY colours: decoded position error mean " << 100 * sum / out.n_vertices() / diag << " %, largest "
                                                                        << 100 * worst / diag << " % of the diagonal (8-bit steps "
                                                                        << 100 * steps / diag << " %)");
  CHECK(sum / out.n_vertices() < steps + 0.002 * diag);
  CHECK(worst < steps + 0.01 * diag);
}

TEST_CASE("sdm transfer --vertex-colors refuses a non-PLY path or a target without correspondence, writing nothing", "[transfer_texture]") {
  sdm::GlContext gl;
  test_util::TempDir dir;
  sdm::Mesh a;
  const std::string src = write_textured_ypsilon(gl, dir, &a);
  const sdm::Mesh b = remeshed(a, 0.8);
  sdm::write_mesh(b, dir / "target.obj");
  sdm::write_skeleton_json(ypsilon_skeleton(b, {1, 3, 2}), dir / "target.json");
  const size_t before = files_in(dir);
  const std::string base = "transfer --source " + src + " --target " + (dir / "target.obj") + " -o " + (dir / "out.obj") + " --size 256";
  auto res = test_util::run_sdm(base + " --vertex-colors " + (dir / "colors.obj"));
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("--vertex-colors must name a .ply file") != std::string::npos);
  // A given target skeleton: matched by skeleton alone, no correspondence to carry colours through.
  res = test_util::run_sdm(base + " --vertex-colors " + (dir / "colors.ply") + " --target-skeleton " + (dir / "target.json"));
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("no point correspondence") != std::string::npos);
  CHECK(files_in(dir) == before);
  CHECK(!std::filesystem::exists(dir / "colors.ply"));
  CHECK(!std::filesystem::exists(dir / "out.obj"));
}

TEST_CASE("sdm transfer refuses a target with another branching and writes nothing", "[transfer_texture]") {
  sdm::GlContext gl;
  test_util::TempDir dir;
  const std::string src = write_textured_ypsilon(gl, dir);
  sdm::write_mesh(sdm::make_primitive("crossed-cylinders", 1200), dir / "target.obj");
  const auto before = std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator());
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.obj") + " -o " + (dir / "out.obj"));
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("branchings differ") != std::string::npos);
  CHECK(res.output.find("ends ") != std::string::npos);
  const auto after = std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator());
  CHECK(after == before);
  CHECK(!std::filesystem::exists(dir / "out.obj"));
  CHECK(!std::filesystem::exists(dir / "out_atlas.png"));
}

TEST_CASE("an SDM decodes around a target skeleton with the same branching and other node counts", "[transfer_texture]") {
  const sdm::Mesh y = sdm::make_primitive("ypsilon");
  // The ideal skeleton lies in the plane z = 0, so turning it about z turns every frame with it
  // (decode carries e1 by the minimal rotation between old and new axes).
  sdm::LayoutOptions lo;
  lo.size = 256;
  lo.split_ratio = 0;
  const sdm::Layout layout = sdm::compute_layout(y, ypsilon_skeleton(y, {2, 2, 2}), lo);
  const sdm::SdmImage im = sdm::encode_sdm(y, layout);
  const sdm::Skeleton& graph = layout.skeleton;
  // Target: the map's skeleton turned 30 degrees about z, every edge cut at its middle, nodes listed
  // in reverse order; the same polylines, so the resampled nodes are the turned originals.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  sdm::Skeleton target;
  const int n = int(graph.nodes.size());
  for (int i = n - 1; i >= 0; --i) target.nodes.push_back(R * graph.nodes[i]);
  for (const auto& e : graph.edges) {
    const int mid = int(target.nodes.size());
    target.nodes.push_back(R * 0.5 * (graph.nodes[e[0]] + graph.nodes[e[1]]));
    target.edges.push_back({n - 1 - e[0], mid});
    target.edges.push_back({mid, n - 1 - e[1]});
  }
  sdm::SkeletonMatch m;
  const sdm::Skeleton moved = sdm::skeleton_onto_graph(graph, target, {}, &m);
  REQUIRE(moved.edges == graph.edges);
  double node_error = 0;
  for (int i = 0; i < n; ++i) node_error = std::max(node_error, (moved.nodes[i] - R * graph.nodes[i]).norm());
  CHECK(node_error < 1e-9);
  sdm::DecodeOptions d;
  d.level = 2;
  const sdm::Mesh plain = sdm::decode_sdm(im, d);
  d.skeleton = moved;
  const sdm::Mesh turned = sdm::decode_sdm(im, d);
  REQUIRE(turned.n_vertices() == plain.n_vertices());
  double err = 0;
  for (auto v : plain.vertices()) err = std::max(err, (sdm::point(turned, v) - R * sdm::point(plain, v)).norm());
  INFO("largest distance to the turned decode " << err);
  CHECK(err < 1e-6 * sdm::bounding_box_diagonal(plain));

  // The command line does the same from files; another branching is refused.
  test_util::TempDir dir;
  sdm::write_sdm_exr(im, dir / "map.exr");
  sdm::write_skeleton_json(target, dir / "target.json");
  auto res = test_util::run_sdm("transfer --sdm " + (dir / "map.exr") + " --target-skeleton " + (dir / "target.json") + " --lod 2 -o " +
                                (dir / "out.obj"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  CHECK(sdm::load_mesh(dir / "out.obj").mesh.n_vertices() == plain.n_vertices());
  target.nodes.push_back(Eigen::Vector3d(5, 5, 5));
  target.edges.push_back({n, int(target.nodes.size()) - 1});  // a middle node becomes a junction
  sdm::write_skeleton_json(target, dir / "other.json");
  res = test_util::run_sdm("transfer --sdm " + (dir / "map.exr") + " --target-skeleton " + (dir / "other.json") + " -o " + (dir / "other.obj"));
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("branchings differ") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "other.obj"));
}

