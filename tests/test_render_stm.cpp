// Rendering with coordinates computed in the shaders (render_stm): the STM render of Spot matches
// the render with its own uv, the seam at phi = 0 leaves no trace, and the shaders' coordinates
// agree with the CPU capsule mapping.
#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/render/render_atlas.h"
#include "libstm/render/render_mesh.h"
#include "libstm/render/render_stm.h"
#include "libstm/layout/segments.h"
#include "stm_test_scenes.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace {

struct SpotScene {
  sdm::Mesh mesh;  // with uv
  sdm::Image texture;
  sdm::Layout layout;
  sdm::Image atlas;
};

// Skeleton, layout (2048 atlas) and atlas of Spot, made once for the tests below.
const SpotScene& spot(sdm::GlContext& gl) {
  static std::unique_ptr<SpotScene> sc;
  if (!sc) {
    sc = std::make_unique<SpotScene>();
    std::string tex;
    sdm::LoadedMesh mesh_read = sdm::load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj");
    tex = std::move(mesh_read.texture);
    sc->mesh = std::move(mesh_read.mesh);
    REQUIRE(!tex.empty());
    sc->texture = sdm::read_png(tex);
    const sdm::Skeleton sk = sdm::extract_skeleton(sc->mesh);  // the skeleton a user gets
    sdm::LayoutOptions lo;
    lo.size = 2048;
    lo.margin = 8;
    sc->layout = sdm::compute_layout(sc->mesh, sk, lo);
    sc->atlas = sdm::render_atlas(gl, sc->mesh, sc->layout, sc->texture);
  }
  return *sc;
}

// Pixels the probe saw a face in, and among them those whose segment is not the face's in `fs`.
struct SegmentAgreement {
  int pixels = 0, other_segment = 0;
};
SegmentAgreement segment_agreement(const sdm::StmRenderProbe& probe, const std::vector<int>& fs) {
  SegmentAgreement a;
  for (size_t i = 0; i < probe.positions.pixels.size() / 4; ++i) {
    const float* c = &probe.coordinates.pixels[i * 4];
    if (probe.positions.pixels[i * 4 + 3] == 0) continue;
    ++a.pixels;
    if (fs[int(c[3])] != int(c[2])) ++a.other_segment;
  }
  return a;
}

}  // namespace

TEST_CASE("Spot from its STM without uv matches Spot with its own uv", "[render_stm]") {
  sdm::GlContext gl;
  const SpotScene& sc = spot(gl);
  sdm::Mesh bare = sc.mesh;
  bare.release_halfedge_texcoords2D();
  REQUIRE(!bare.has_halfedge_texcoords2D());
  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.unlit = true;
  ro.elevation_deg = 15;
  for (int view = 0; view < 8; ++view) {
    ro.azimuth_deg = 45.0 * view;
    std::vector<uint8_t> m_uv, m_stm;
    ro.texture = &sc.texture;
    const sdm::Image a = sdm::render_mesh(gl, sc.mesh, ro, &m_uv);
    ro.texture = nullptr;
    const sdm::Image b = sdm::render_stm(gl, bare, sc.layout, sc.atlas, ro, &m_stm);
    const std::vector<uint8_t> mask = sdm::mask_union(m_uv, m_stm);
    const double p = sdm::psnr(a, b, &mask);
    INFO("view " << view << " azimuth " << ro.azimuth_deg << ": PSNR " << p << " dB");
    std::printf("spot view %d: PSNR %.2f dB\n", view, p);
    CHECK(p >= 30.0);

    // SDM_TEST_DUMP=FOLDER keeps the pairs (own uv left, STM right) for looking at.
    if (const char* dump = std::getenv("SDM_TEST_DUMP"))
      sdm::write_png(sdm::side_by_side({a, b}), std::string(dump) + "/spot_view" + std::to_string(view) + ".png");
  }
}

namespace {

// Renders `layout` on Spot and compares the shaders' STM coordinates and segments with the CPU's
// (capsule_uv, assign_faces), pixel by pixel.
void check_shaders_match_cpu(sdm::GlContext& gl, const sdm::Mesh& mesh, const sdm::Layout& layout, const sdm::Image& atlas) {
  sdm::RenderOptions ro;
  ro.width = ro.height = 256;
  ro.azimuth_deg = 60;
  sdm::StmRenderProbe probe;
  sdm::render_stm(gl, mesh, layout, atlas, ro, nullptr, &probe);
  const std::vector<int> fs = sdm::assign_faces(mesh, layout);
  int n = 0, near_pole = 0, other_segment = 0;
  double worst = 0;
  for (int i = 0; i < ro.width * ro.height; ++i) {
    const float* p = &probe.positions.pixels[size_t(i) * 4];
    const float* c = &probe.coordinates.pixels[size_t(i) * 4];
    if (p[3] == 0) continue;
    const int s = int(c[2]), face = int(c[3]);
    REQUIRE(s >= 0);
    REQUIRE(s < int(layout.segments.size()));
    REQUIRE(face >= 0);
    REQUIRE(face < int(mesh.n_faces()));
    if (fs[face] != s) ++other_segment;
    const sdm::LayoutSegment& g = layout.segments[s];
    const sdm::CapsuleUV cpu = sdm::capsule_uv(sdm::capsule_frame(layout, s), g.w, g.h, g.d, Eigen::Vector3d(p[0], p[1], p[2]));
    // Within a thousandth of the radius of the axis the angle is ill-conditioned in float.
    if (cpu.rho < 1e-3 * g.radius) {
      ++near_pole;
      continue;
    }
    const Eigen::Vector2d want = sdm::local_to_atlas(g, cpu.u, cpu.v);
    Eigen::Vector2d d = Eigen::Vector2d(c[0], c[1]) - want;
    // u = 0 and u = h are the same point: compare around the axis modulo h.
    double& du = g.rotated ? d.x() : d.y();
    du -= g.h * std::round(du / g.h);
    worst = std::max(worst, d.cwiseAbs().maxCoeff());
    ++n;
  }
  INFO("pixels " << n << ", near a pole " << near_pole << ", segment differs from assign_faces " << other_segment
                 << ", worst difference " << worst << " texels");
  CHECK(n > 10000);
  CHECK(near_pole <= n / 1000);
  CHECK(worst < 0.01);
  CHECK(other_segment <= n / 100);  // float ties only
}

}  // namespace

TEST_CASE("the shaders' STM coordinates match the CPU capsule mapping", "[render_stm]") {
  sdm::GlContext gl;
  const SpotScene& sc = spot(gl);
  check_shaders_match_cpu(gl, sc.mesh, sc.layout, sc.atlas);
}

TEST_CASE("extended capsules map and assign alike on the GPU and the CPU", "[render_stm]") {
  // Spot needs no extension; every joint's segment ends are extended here, as layouts of
  // bunny00-like shapes have them (assignment rule 3).
  sdm::GlContext gl;
  const SpotScene& sc = spot(gl);
  nlohmann::json j = sdm::layout_to_json(sc.layout);
  REQUIRE(j.at("assignment") == 2);
  std::vector<int> degree(sc.layout.skeleton.nodes.size(), 0);
  for (const auto& e : sc.layout.skeleton.edges) ++degree[e[0]], ++degree[e[1]];
  j["assignment"] = 3;
  for (auto& s : j["segments"])
    s["extend"] = {degree[s["a"].get<int>()] >= 2 ? sdm::kCapExtension : 0.0, degree[s["b"].get<int>()] >= 2 ? sdm::kCapExtension : 0.0};
  const sdm::Layout extended = sdm::layout_from_json(j);
  REQUIRE(extended.assignment == 3);
  // The extensions change what the second pass chooses and where the points map.
  const std::vector<int> fs2 = sdm::assign_faces(sc.mesh, sc.layout), fs3 = sdm::assign_faces(sc.mesh, extended);
  int moved = 0;
  for (size_t f = 0; f < fs2.size(); ++f) moved += fs2[f] != fs3[f];
  INFO("faces the extensions move on Spot: " << moved);
  CHECK(moved > 0);
  check_shaders_match_cpu(gl, sc.mesh, extended, sc.atlas);
  // Written without the rule, the extensions are refused by name.
  j["assignment"] = 2;
  CHECK_THROWS_WITH(sdm::layout_from_json(j), Catch::Contains("capsule extensions"));
}

TEST_CASE("the shader chooses the segments of assign_faces on a mesh wound inside out", "[render_stm]") {
  sdm::GlContext gl;
  const SpotScene& sc = spot(gl);
  sdm::MeshSoup soup = sdm::mesh_to_soup(sc.mesh);
  soup.uv.clear();
  for (auto& t : soup.triangles) std::swap(t[1], t[2]);
  const sdm::Mesh inverted = sdm::build_mesh(soup);
  REQUIRE(inverted.n_faces() == sc.mesh.n_faces());
  // Made outward per part, the rule does not see the winding.
  const std::vector<int> fs = sdm::assign_faces(inverted, sc.layout);
  CHECK(fs == sdm::assign_faces(sc.mesh, sc.layout));
  sdm::RenderOptions ro;
  ro.width = ro.height = 256;
  ro.azimuth_deg = 240;
  sdm::StmRenderProbe probe;
  sdm::render_stm(gl, inverted, sc.layout, sc.atlas, ro, nullptr, &probe);
  const SegmentAgreement a = segment_agreement(probe, fs);
  INFO("pixels " << a.pixels << ", segment differs from assign_faces " << a.other_segment);
  CHECK(a.pixels > 10000);
  CHECK(a.other_segment <= a.pixels / 100);
}

TEST_CASE("a layout written before the second pass is assigned with the first pass alone, on the GPU too", "[render_stm]") {
  sdm::GlContext gl;
  const SpotScene& sc = spot(gl);
  nlohmann::json j = sdm::layout_to_json(sc.layout);
  CHECK(j.at("assignment") == 2);
  j.erase("assignment");  // as layouts were written before it
  const sdm::Layout old = sdm::layout_from_json(j);
  REQUIRE(old.assignment == 1);
  const std::vector<int> fs1 = sdm::assign_faces(sc.mesh, old), fs2 = sdm::assign_faces(sc.mesh, sc.layout);
  int moved = 0;
  for (size_t f = 0; f < fs1.size(); ++f) moved += fs1[f] != fs2[f];
  INFO("faces the second pass moves on Spot: " << moved);
  CHECK(moved > 0);
  CHECK(moved < int(fs1.size()) / 10);
  // The first pass leaves Spot's layout more stretched (1.93 against 1.19 measured).
  CHECK(sdm::stm_coordinates(sc.mesh, old).stretch > sdm::stm_coordinates(sc.mesh, sc.layout).stretch + 0.2);
  sdm::RenderOptions ro;
  ro.width = ro.height = 256;
  ro.azimuth_deg = 60;
  sdm::StmRenderProbe probe;
  sdm::render_stm(gl, sc.mesh, old, sc.atlas, ro, nullptr, &probe);
  const SegmentAgreement a = segment_agreement(probe, fs1);
  INFO("pixels " << a.pixels << ", segment differs from the first pass " << a.other_segment);
  CHECK(a.pixels > 10000);
  CHECK(a.other_segment <= a.pixels / 100);
}

TEST_CASE("no seam line where the STM wraps around the axis", "[render_stm]") {
  const stm_test::CylinderScene sc = stm_test::cylinder_scene(1024, 8);
  const sdm::Image source = stm_test::procedural_image(512, 256);
  sdm::GlContext gl;
  const sdm::Image atlas = sdm::render_atlas(gl, sc.mesh, sc.layout, source);
  sdm::Mesh bare = sc.mesh;
  bare.release_halfedge_texcoords2D();
  // Look at the seam (phi = 0, direction e1) from a few azimuths close to it, so that it falls both
  // between and inside the 2x2 pixel quads the derivatives come from; the probe tells which
  // neighbouring pixels lie on either side of it.
  const sdm::LayoutSegment& g = sc.layout.segments[0];
  const Eigen::Vector3d e1 = g.e1;
  REQUIRE(std::abs(e1.y()) < 1e-9);
  for (double offset : {0.0, 1.0, 2.0, 3.0}) {
    sdm::RenderOptions ro;
    ro.width = ro.height = 256;
    ro.unlit = true;
    ro.samples = 1;
    ro.elevation_deg = 0;
    ro.texture = nullptr;
    ro.azimuth_deg = std::atan2(e1.x(), e1.z()) * 180 / M_PI + offset;
    std::vector<uint8_t> mask, uv_mask;
    sdm::StmRenderProbe probe;
    const sdm::Image img = sdm::render_stm(gl, bare, sc.layout, atlas, ro, &mask, &probe);
    ro.texture = &source;
    const sdm::Image uv_img = sdm::render_mesh(gl, sc.mesh, ro, &uv_mask);
    int x0 = ro.width, x1 = 0, y0 = ro.height, y1 = 0;
    for (int y = 0; y < ro.height; ++y)
      for (int x = 0; x < ro.width; ++x)
        if (mask[size_t(y) * ro.width + x]) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    // Rows well inside the side (away from the rims), columns in the middle half of the object.
    const int quarter = (x1 - x0) / 4, cx = (x0 + x1) / 2;
    const int ya = y0 + (y1 - y0) / 6, yb = y1 - (y1 - y0) / 6;
    auto around = [&](int x, int y) {  // atlas coordinate around the axis
      const float* c = probe.coordinates.at(x, y);
      return g.rotated ? c[0] : c[1];
    };
    double seam = 0, elsewhere = 0;
    int seam_pairs = 0;
    for (int y = ya; y < yb; ++y)
      for (int x = cx - quarter; x < cx + quarter; ++x) {
        if (!mask[size_t(y) * ro.width + x] || !mask[size_t(y) * ro.width + x + 1]) continue;
        double j = 0;
        for (int k = 0; k < 3; ++k) j = std::max(j, std::abs(double(img.at(x + 1, y)[k]) - img.at(x, y)[k]));
        // The pair across the seam and the pairs next to it (a quad straddling the seam).
        bool near_seam = false;
        for (int dx = -2; dx <= 2; ++dx)
          near_seam |= x + dx >= 0 && x + dx + 1 < ro.width && std::abs(around(x + dx + 1, y) - around(x + dx, y)) > 0.5 * g.h;
        if (std::abs(around(x + 1, y) - around(x, y)) > 0.5 * g.h) ++seam_pairs;
        (near_seam ? seam : elsewhere) = std::max(near_seam ? seam : elsewhere, j);
      }
    const std::vector<uint8_t> both = sdm::mask_union(mask, uv_mask);
    const double p = sdm::psnr(uv_img, img, &both);
    INFO("azimuth offset " << offset << ": " << seam_pairs << " pixel pairs across the seam, largest jump there " << seam
                           << ", elsewhere " << elsewhere << "; PSNR against own uv " << p << " dB");
    CHECK(seam_pairs >= (yb - ya) / 2);
    CHECK(seam <= elsewhere);
    CHECK(elsewhere < 20);  // the texture is smooth at this scale: the comparison is meaningful
    CHECK(p > 35);
  }
}

TEST_CASE("sdm remap and sdm render --stm --compare-uv round trip", "[render_stm]") {
  test_util::TempDir dir;
  const stm_test::CylinderScene sc = stm_test::cylinder_scene(512, 8);
  sdm::write_mesh(sc.mesh, dir / "cyl.obj", dir / "tex.png");
  sdm::write_png(stm_test::procedural_image(256, 128), dir / "tex.png");
  sdm::write_layout_json(sc.layout, dir / "layout.json");
  auto r = test_util::run_sdm("remap " + (dir / "cyl.obj") + " -o " + (dir / "atlas.png") + " --layout " + (dir / "layout.json"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  REQUIRE(!std::filesystem::exists(dir / "atlas.json"));  // a given layout is not written again
  const sdm::Image atlas = sdm::read_png(dir / "atlas.png");
  CHECK(atlas.width == 512);
  r = test_util::run_sdm("render " + (dir / "cyl.obj") + " -o " + (dir / "cmp.png") + " --stm " + (dir / "atlas.png") +
                         " --layout " + (dir / "layout.json") + " --compare-uv --unlit --views 4 --width 128 --height 128 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  REQUIRE(j.at("psnr").at("views").size() == 4);
  CHECK(j.at("psnr").at("min").get<double>() > 30);
  // Missing layout: input error.
  r = test_util::run_sdm("render " + (dir / "cyl.obj") + " -o " + (dir / "x.png") + " --stm " + (dir / "atlas.png"));
  CHECK(r.exit_code == 2);
}
