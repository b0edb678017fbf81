// Texture transfer between models with the same skeleton branching (transfer_texture): the same
// shape tessellated anew gets the same picture (PSNR per view against the source), a colour band
// painted on one branch lands on the same branch of a bent and thickened target, and a target
// with another branching is refused with nothing written.
#include "libsdm/transfer_texture.h"
#include "libstm/extract_skeleton.h"
#include "libstm/gl_context.h"
#include "libstm/isotropic_remesh.h"
#include "libstm/primitives.h"
#include "libstm/render_atlas.h"
#include "libstm/render_mesh.h"
#include "libstm/segments.h"
#include "libstm/split_segments.h"
#include "libstm/triangle_bvh.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace {

// The right arm of the ypsilon primitive (primitives.cpp): from the origin towards (0.78, 0.78, 0).
const Eigen::Vector3d kArm = Eigen::Vector3d(1, 1, 0).normalized();

// A smooth colour over space (a few periods across the models), in [0, 1].
Eigen::Vector3d smooth_colour(const Eigen::Vector3d& p) {
  return {0.5 + 0.35 * std::sin(3.1 * p.x() + 1.3 * p.z()), 0.5 + 0.35 * std::cos(2.7 * p.y() - 0.9 * p.x()),
          0.5 + 0.35 * std::sin(2.3 * p.z() + 1.9 * p.y() + 0.5)};
}

// The same plus a pure red band across the right arm (axial distance 0.6 to 0.8 along it).
Eigen::Vector3d band_colour(const Eigen::Vector3d& p) {
  const double s = p.dot(kArm), off = (p - s * kArm).norm();
  if (s > 0.6 && s < 0.8 && off < 0.5) return {1, 0, 0};
  Eigen::Vector3d c = smooth_colour(p);
  c.x() *= 0.6;  // keep the rest of the model clearly not red
  return c;
}

// Gives `mesh` uv (its own STM) and returns a texture in which colour(p) is painted: the atlas of
// surface positions is rendered and every texel coloured from its position.
stm::Image bake_texture(stm::GlContext& gl, stm::Mesh& mesh, const stm::Skeleton& sk, Eigen::Vector3d (*colour)(const Eigen::Vector3d&)) {
  stm::LayoutOptions lo;
  lo.size = 1024;
  lo.margin = 6;
  const stm::Layout layout = stm::compute_layout(mesh, sk, lo);
  std::vector<Eigen::Vector4f> corners;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) {
      const Eigen::Vector3d p = stm::point(mesh, v);
      corners.emplace_back(float(p.x()), float(p.y()), float(p.z()), 1.f);
    }
  const stm::FloatImage pos = stm::render_atlas_values(gl, mesh, layout, corners);
  stm::Image tex(pos.width, pos.height, 4, 255);
  for (int y = 0; y < pos.height; ++y)
    for (int x = 0; x < pos.width; ++x) {
      const float* q = pos.at(x, y);
      const Eigen::Vector3d c = colour(Eigen::Vector3d(q[0], q[1], q[2]));
      for (int k = 0; k < 3; ++k) tex.at(x, y)[k] = uint8_t(std::lround(255 * std::clamp(c[k], 0.0, 1.0)));
    }
  mesh = stm::stm_coordinates(mesh, layout).mesh;
  return tex;
}

double mean_edge(const stm::Mesh& m) {
  double s = 0;
  for (auto e : m.edges()) s += m.calc_edge_length(e);
  return s / double(m.n_edges());
}

// A copy of `mesh` with another tessellation, its vertices on the original surface.
stm::Mesh remeshed(const stm::Mesh& mesh, double edge_factor) {
  const stm::TriangleBvh bvh(stm::vertex_matrix(mesh), stm::face_matrix(mesh));
  stm::Mesh copy = mesh;
  copy.release_halfedge_texcoords2D();
  stm::isotropic_remesh(copy, edge_factor * mean_edge(mesh), 4, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  return copy;
}

// PSNR per view between the source (own uv) and the target (transferred uv), unlit, over the
// pixels both cover.
std::vector<double> compare_views(stm::GlContext& gl, const stm::Mesh& a, const stm::Image& ta, const stm::Mesh& b,
                                  const stm::Image& tb, const std::string& dump_name) {
  stm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  ro.elevation_deg = 15;
  stm::bounding_box(a, ro.bbox_min, ro.bbox_max);
  std::vector<double> out;
  for (int view = 0; view < 8; ++view) {
    ro.azimuth_deg = 45.0 * view;
    std::vector<uint8_t> ma, mb;
    ro.texture = &ta;
    const stm::Image ia = stm::render_mesh(gl, a, ro, &ma);
    ro.texture = &tb;
    const stm::Image ib = stm::render_mesh(gl, b, ro, &mb);
    for (size_t i = 0; i < ma.size(); ++i) ma[i] = ma[i] && mb[i] ? 255 : 0;
    out.push_back(stm::psnr(ia, ib, &ma));
    if (const char* dump = std::getenv("SDM_TEST_DUMP"))
      stm::write_png(stm::side_by_side({ia, ib}), std::string(dump) + "/" + dump_name + std::to_string(view) + ".png");
  }
  return out;
}

// Spot's hand-made skeleton (as in test_render_stm): every vertex to the nearer end of its nearest segment.
stm::Skeleton spot_skeleton(const stm::Mesh& mesh) {
  stm::Skeleton sk;
  sk.nodes = {{0, 0.0, 1.0},   {0, -0.1, 0.62},    {0, -0.05, 0.1},   {0, 0.3, -0.25},  {0, 0.5, -0.42},
              {0.2, -0.35, 0.07}, {-0.2, -0.35, 0.07}, {0.2, -0.65, 0.07}, {-0.2, -0.65, 0.07},
              {0.17, -0.35, 0.66}, {-0.17, -0.35, 0.66}, {0.17, -0.65, 0.66}, {-0.17, -0.65, 0.66},
              {0.17, 0.88, -0.27}, {-0.17, 0.88, -0.27}, {0.42, 0.68, -0.21}, {-0.42, 0.68, -0.21}};
  sk.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {2, 5}, {5, 7}, {2, 6}, {6, 8}, {1, 9}, {9, 11}, {1, 10}, {10, 12},
              {4, 13}, {4, 14}, {4, 15}, {4, 16}};
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = stm::point(mesh, v);
    double best = 1e300;
    int node = 0;
    for (const auto& e : sk.edges) {
      double t = 0;
      const double d = stm::distance_to_segment(p, sk.nodes[e[0]], sk.nodes[e[1]], &t);
      if (d < best) best = d, node = t < 0.5 ? e[0] : e[1];
    }
    sk.vertex_node.push_back(node);
  }
  return sk;
}

// The ypsilon with its right arm bent by `degrees` around z (progressively, from 0.3 along the arm
// on) and thickened by `thicken` (radially, same ramp).
stm::Mesh bent_ypsilon(const stm::Mesh& y, double degrees, double thicken) {
  stm::Mesh m = y;
  const Eigen::Vector3d pivot = 0.3 * kArm;
  for (auto v : m.vertices()) {
    const Eigen::Vector3d p = stm::point(m, v);
    const double s = (p - pivot).dot(kArm);
    if (s <= 0) continue;
    const double w = std::min(1.0, s / 0.4);
    const Eigen::Vector3d radial = (p - pivot) - s * kArm;
    const Eigen::Vector3d q = s * kArm + (1 + thicken * w) * radial;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(-degrees * M_PI / 180 * w, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d out = pivot + R * q;
    m.set_point(v, stm::Mesh::Point(out.x(), out.y(), out.z()));
  }
  return m;
}

}  // namespace

TEST_CASE("transfer onto a new tessellation of the ypsilon reproduces the source", "[transfer_texture]") {
  stm::GlContext gl;
  stm::Mesh a = stm::make_primitive("ypsilon", 2000);
  const stm::Skeleton sa = stm::extract_skeleton(a);
  const stm::Image tex = bake_texture(gl, a, sa, smooth_colour);
  const stm::Mesh b = remeshed(a, 0.75);
  REQUIRE(b.n_vertices() != a.n_vertices());
  const stm::Skeleton sb = stm::extract_skeleton(b);
  REQUIRE(stm::branching_difference(sa, sb).empty());
  stm::TransferOptions to;
  to.size = 1024;
  const stm::TextureTransfer r = stm::transfer_texture(gl, a, tex, sa, b, sb, to);
  // Both skeletons share one graph; the match is the identity up to the Y's symmetry, and confident.
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.match.confidence > 0.3);
  std::vector<int> count(r.skeletons.b.nodes.size(), 0);
  for (int x : r.skeletons.b.vertex_node) ++count[x];
  CHECK(*std::min_element(count.begin(), count.end()) >= 1);
  const std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, "ypsilon_transfer_view");
  for (size_t v = 0; v < p.size(); ++v) {
    INFO("view " << v << ": PSNR " << p[v] << " dB");
    CHECK(p[v] >= 28.0);
  }
  WARN("ypsilon remeshed: PSNR per view " << p[0] << " " << p[1] << " " << p[2] << " " << p[3] << " " << p[4] << " " << p[5] << " "
                                          << p[6] << " " << p[7]);
}

TEST_CASE("transfer onto a new tessellation of Spot reproduces its texture", "[transfer_texture]") {
  stm::GlContext gl;
  std::string tex_path;
  const stm::Mesh a = stm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj", &tex_path);
  REQUIRE(!tex_path.empty());
  const stm::Image tex = stm::read_png(tex_path);
  const stm::Skeleton sa = spot_skeleton(a);
  const stm::Mesh b = remeshed(a, 1.3);
  REQUIRE(b.n_vertices() != a.n_vertices());
  // The target's skeleton has the same branching with other node counts: the long edges cut.
  const stm::Skeleton sb = stm::split_long_segments(b, spot_skeleton(b), 1.0);
  REQUIRE(sb.nodes.size() > sa.nodes.size());
  stm::TransferOptions to;
  to.size = 2048;
  const stm::TextureTransfer r = stm::transfer_texture(gl, a, tex, sa, b, sb, to);
  CHECK(r.skeletons.a.edges == r.skeletons.b.edges);
  CHECK(r.skeletons.a.edges.size() >= sb.edges.size());
  const std::vector<double> p = compare_views(gl, a, tex, r.target, r.atlas, "spot_transfer_view");
  for (size_t v = 0; v < p.size(); ++v) {
    INFO("view " << v << ": PSNR " << p[v] << " dB");
    CHECK(p[v] >= 28.0);
  }
  WARN("Spot remeshed: PSNR per view " << p[0] << " " << p[1] << " " << p[2] << " " << p[3] << " " << p[4] << " " << p[5] << " "
                                       << p[6] << " " << p[7]);
}

TEST_CASE("a band painted on one branch lands on the same branch of a bent and thickened target", "[transfer_texture]") {
  stm::GlContext gl;
  stm::Mesh a = stm::make_primitive("ypsilon", 2000);
  const stm::Skeleton sa = stm::extract_skeleton(a);
  const stm::Image tex = bake_texture(gl, a, sa, band_colour);
  // Target: the right arm bent down by 50 degrees and 40 % thicker, then tessellated anew. Faces of
  // the bent copy are labelled "arm" when their undeformed centroid lies past 0.3 along the arm;
  // the remeshed target's faces take the label of the nearest face of the bent copy.
  const stm::Mesh bent = bent_ypsilon(stm::make_primitive("ypsilon", 2000), 50, 0.4);
  std::vector<char> bent_arm(bent.n_faces(), 0);
  for (auto f : a.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : a.fv_range(f)) c += stm::point(a, v) / 3;
    bent_arm[f.idx()] = c.dot(kArm) > 0.3 && (c - c.dot(kArm) * kArm).norm() < 0.5;
  }
  const stm::TriangleBvh bvh(stm::vertex_matrix(bent), stm::face_matrix(bent));
  stm::Mesh b = bent;
  stm::isotropic_remesh(b, 0.8 * mean_edge(bent), 4, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  const stm::Skeleton sb = stm::extract_skeleton(b);
  REQUIRE(stm::branching_difference(sa, sb).empty());
  stm::TransferOptions to;
  to.size = 1024;
  const stm::TextureTransfer r = stm::transfer_texture(gl, a, tex, sa, b, sb, to);

  // Label texture: white on the left half, black on the right; arm faces sample the white half.
  stm::Image label(64, 64, 4, 255);
  for (int y = 0; y < 64; ++y)
    for (int x = 32; x < 64; ++x)
      for (int k = 0; k < 3; ++k) label.at(x, y)[k] = 0;
  stm::Mesh labelled = b;
  labelled.request_halfedge_texcoords2D();
  int arm_faces = 0;
  for (auto f : labelled.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : labelled.fv_range(f)) c += stm::point(labelled, v) / 3;
    const bool arm = bent_arm[bvh.closest_point(c).face];
    arm_faces += arm;
    for (auto h : labelled.fh_range(f)) labelled.set_texcoord2D(h, stm::Mesh::TexCoord2D(arm ? 0.25 : 0.75, 0.5));
  }
  REQUIRE(arm_faces > 0);

  stm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  ro.samples = 1;
  long band_total = 0;
  for (double az : {0.0, 40.0, 180.0}) {
    ro.azimuth_deg = az;
    ro.elevation_deg = az == 40.0 ? 30 : 0;
    ro.texture = &r.atlas;
    const stm::Image img = stm::render_mesh(gl, r.target, ro);
    ro.texture = &label;
    const stm::Image lab = stm::render_mesh(gl, labelled, ro);
    long band = 0, on_arm = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const uint8_t* c = img.at(x, y);
        if (!(c[0] > 200 && c[1] < 50 && c[2] < 50)) continue;
        ++band;
        on_arm += lab.at(x, y)[0] > 128;
      }
    INFO("azimuth " << az << ": " << band << " band pixels, " << on_arm << " on the bent arm");
    CHECK(band > 500);
    CHECK(on_arm >= 0.98 * band);
    band_total += band;
    if (const char* dump = std::getenv("SDM_TEST_DUMP"))
      stm::write_png(stm::side_by_side({img, lab}), std::string(dump) + "/band_az" + std::to_string(int(az)) + ".png");
  }
  WARN("band: " << band_total << " band pixels over 3 views");
}

namespace {

// Writes the ypsilon with a baked smooth texture as OBJ + MTL + PNG into `dir`; returns the OBJ path.
std::string write_textured_ypsilon(stm::GlContext& gl, const test_util::TempDir& dir, stm::Mesh* mesh = nullptr,
                                   stm::Image* texture = nullptr) {
  stm::Mesh a = stm::make_primitive("ypsilon", 1200);
  const stm::Image tex = bake_texture(gl, a, stm::extract_skeleton(a), smooth_colour);
  stm::write_png(tex, dir / "source.png");
  stm::write_mesh(a, dir / "source.obj", dir / "source.png");
  if (mesh) *mesh = a;
  if (texture) *texture = tex;
  return dir / "source.obj";
}

}  // namespace

TEST_CASE("sdm transfer writes the target with uv and its atlas and preview", "[transfer_texture]") {
  stm::GlContext gl;
  test_util::TempDir dir;
  stm::Mesh a;
  stm::Image tex;
  const std::string src = write_textured_ypsilon(gl, dir, &a, &tex);
  stm::write_mesh(remeshed(a, 0.8), dir / "target.obj");
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.obj") + " -o " + (dir / "out.obj") +
                                      " --size 1024 --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const auto j = nlohmann::json::parse(res.output.substr(res.output.find("{\n")));
  CHECK(j.at("chains").size() == 3);
  CHECK(j.at("keys").size() == 4);
  CHECK(j.at("confidence").get<double>() > 0);
  CHECK(std::filesystem::exists(dir / "out_atlas.png"));
  CHECK(std::filesystem::exists(dir / "out_preview.png"));
  CHECK(std::filesystem::exists(dir / "out.mtl"));
  std::string atlas_path;
  const stm::Mesh out = stm::load_mesh(dir / "out.obj", &atlas_path);
  REQUIRE(out.has_halfedge_texcoords2D());
  REQUIRE(std::filesystem::equivalent(atlas_path, dir / "out_atlas.png"));
  const stm::Image atlas = stm::read_png(atlas_path);
  // The written target, with the written atlas, looks like the source.
  stm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  stm::bounding_box(a, ro.bbox_min, ro.bbox_max);
  for (double az : {0.0, 135.0}) {
    ro.azimuth_deg = az;
    std::vector<uint8_t> ma, mb;
    ro.texture = &tex;
    const stm::Image ia = stm::render_mesh(gl, a, ro, &ma);
    ro.texture = &atlas;
    const stm::Image ib = stm::render_mesh(gl, out, ro, &mb);
    for (size_t i = 0; i < ma.size(); ++i) ma[i] = ma[i] && mb[i] ? 255 : 0;
    const double p = stm::psnr(ia, ib, &ma);
    INFO("azimuth " << az << ": PSNR " << p);
    CHECK(p >= 28.0);
  }
}

TEST_CASE("sdm transfer refuses a target with another branching and writes nothing", "[transfer_texture]") {
  stm::GlContext gl;
  test_util::TempDir dir;
  const std::string src = write_textured_ypsilon(gl, dir);
  stm::write_mesh(stm::make_primitive("crossed-cylinders", 1200), dir / "target.obj");
  const auto before = std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator());
  const auto res = test_util::run_sdm("transfer --source " + src + " --target " + (dir / "target.obj") + " -o " + (dir / "out.obj"));
  INFO(res.output);
  CHECK(res.exit_code == 2);
  CHECK(res.output.find("branching differs") != std::string::npos);
  CHECK(res.output.find("ends 3 vs 4") != std::string::npos);
  const auto after = std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator());
  CHECK(after == before);
  CHECK(!std::filesystem::exists(dir / "out.obj"));
  CHECK(!std::filesystem::exists(dir / "out_atlas.png"));
}
