// Headless GL, PNG images, PSNR and the mesh renderer, checked against numbers derived from the
// camera geometry (30 degree field of view framing the bounding sphere).
#include "libstm/core/errors.h"
#include "libstm/render/gl_context.h"
#include "libstm/render/gl_objects.h"
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"
#include "libstm/render/render_mesh.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

namespace fs = std::filesystem;

namespace {

sdm::GlContext& gl() {
  static sdm::GlContext context;  // one per test run: creating contexts is the slow part
  return context;
}

// Unit square in the z = 0 plane, [-0.5, 0.5]^2, uv (0,0) at (-0.5,-0.5); split into n x n cells of
// two triangles each, so two tessellations of the same textured square can be compared.
sdm::Mesh square(int n = 1) {
  sdm::MeshSoup s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.points.emplace_back(double(i) / n - 0.5, double(j) / n - 0.5, 0.0);
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  auto uv = [&](int v) { return Eigen::Vector2d(s.points[v].x() + 0.5, s.points[v].y() + 0.5); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::array<int, 3> t1{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, t2{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      for (const auto& t : {t1, t2}) {
        s.triangles.push_back(t);
        for (int v : t) s.uv.push_back(uv(v));
      }
    }
  return sdm::build_mesh(s);
}

// Analytic half-width in pixels of the unit square seen face-on in an 800 px image: the bounding
// sphere (radius sqrt(1/2)) fills the 30 degree field of view, so the square's half-width in
// normalised device coordinates is 0.5 cos(15 deg) / sqrt(1/2).
const double kHalfWidthPx = 400.0 * 0.5 * std::cos(15.0 * M_PI / 180.0) / std::sqrt(0.5);  // 273.2

int run(const std::string& args) {
  const int status = std::system((std::string(SDM_BINARY) + " " + args + " 2>/dev/null >/dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sdm_test_render_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("EGL gives a headless GL 4.5 core context", "[render]") {
  sdm::GlContext& g = gl();
  INFO("renderer: " << g.renderer() << ", version: " << g.version() << ", platform: " << g.platform());
  CHECK(g.major_version() * 10 + g.minor_version() >= 45);
  CHECK(!g.renderer().empty());
  // The profile bit, not the version string: Mesa writes "4.5 (Core Profile) Mesa ..." but NVIDIA's
  // driver "4.5.0 NVIDIA 580.159.04".
  g.make_current();
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  CHECK((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0);
  // Programs from the embedded shaders compile and are cached.
  const unsigned p = g.program("mesh.vert.glsl", "mesh.frag.glsl");
  CHECK(p != 0);
  CHECK(g.program("mesh.vert.glsl", "mesh.frag.glsl") == p);
}

TEST_CASE("Framebuffer reads back cleared colour and float values", "[render]") {
  gl().make_current();
  const int samples = GENERATE(1, 4);  // multisampled targets resolve to the same values
  sdm::Framebuffer fb(7, 5, samples, true);
  fb.bind();
  const float c[4] = {0.2f, 0.4f, 0.6f, 1.0f}, f[4] = {-1.5f, 2.25f, 1e6f, 0.125f};
  fb.clear(c, f);
  const sdm::Image img = fb.read_rgba8();
  const sdm::FloatImage fi = fb.read_float();
  REQUIRE(img.width == 7);
  REQUIRE(img.height == 5);
  CHECK(int(img.at(6, 4)[0]) == 51);
  CHECK(int(img.at(0, 0)[1]) == 102);
  CHECK(int(img.at(3, 2)[2]) == 153);
  CHECK(fi.at(6, 4)[0] == -1.5f);
  CHECK(fi.at(0, 0)[2] == 1e6f);  // a float target keeps values an 8-bit one cannot
  CHECK(fi.at(2, 3)[3] == 0.125f);
}

TEST_CASE("GL object handles delete their object once and a move hands it over", "[render]") {
  gl().make_current();
  sdm::GlBuffer a = sdm::make_buffer(std::vector<float>{1, 2, 3});
  const GLuint name = a.get();
  REQUIRE(name != 0);
  CHECK(glIsBuffer(name) == GL_TRUE);
  sdm::GlBuffer b = std::move(a);
  CHECK(a.get() == 0);
  CHECK(b.get() == name);
  a.reset();  // owns nothing: deletes nothing
  CHECK(glIsBuffer(name) == GL_TRUE);
  b.reset();
  CHECK(b.get() == 0);
  CHECK(glIsBuffer(name) == GL_FALSE);
  // An empty vector still gets storage for one element.
  const sdm::GlBuffer empty = sdm::make_buffer(std::vector<float>{});
  GLint64 bytes = 0;
  glGetNamedBufferParameteri64v(empty.get(), GL_BUFFER_SIZE, &bytes);
  CHECK(bytes == GLint64(sizeof(float)));
  GLuint texture = 0, vao = 0;
  {
    const sdm::GlTexture t = sdm::make_texture(GL_TEXTURE_2D);
    const sdm::GlVertexArray v = sdm::make_vertex_array();
    texture = t.get();
    vao = v.get();
    CHECK(glIsTexture(texture) == GL_TRUE);
    CHECK(glIsVertexArray(vao) == GL_TRUE);
  }
  CHECK(glIsTexture(texture) == GL_FALSE);
  CHECK(glIsVertexArray(vao) == GL_FALSE);
  sdm::check_gl("gl object handles");
}

TEST_CASE("Unlit square facing the camera: exact colour inside, background outside, analytic extent", "[render]") {
  sdm::RenderOptions o;
  o.azimuth_deg = 0;
  o.elevation_deg = 0;
  o.unlit = true;
  o.color = Eigen::Vector3f(200.f / 255, 100.f / 255, 50.f / 255);
  o.background = {10, 20, 30, 255};
  std::vector<uint8_t> mask;
  const sdm::Image img = sdm::render_mesh(gl(), square(), o, &mask);
  REQUIRE(img.width == 800);
  REQUIRE(img.height == 800);
  auto rgb = [&](int x, int y) { return std::array<int, 3>{img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]}; };
  const std::array<int, 3> object{200, 100, 50}, background{10, 20, 30};
  for (int y = 390; y <= 410; ++y)
    for (int x = 390; x <= 410; ++x) REQUIRE(rgb(x, y) == object);
  for (auto [x, y] : {std::pair{0, 0}, {799, 0}, {0, 799}, {799, 799}}) CHECK(rgb(x, y) == background);
  // Edges where geometry says: the square spans [400 - 273.2, 400 + 273.2] in x and y.
  const int inner = int(std::ceil(400 - kHalfWidthPx)) + 1, outer = int(std::floor(400 - kHalfWidthPx)) - 1;
  CHECK(rgb(inner, 400) == object);
  CHECK(rgb(outer, 400) == background);
  CHECK(rgb(799 - inner, 400) == object);
  CHECK(rgb(799 - outer, 400) == background);
  CHECK(rgb(400, inner) == object);
  CHECK(rgb(400, outer) == background);
  // Covered area = (2 * 273.2)^2 pixels, up to the pixels the edges cut through.
  size_t covered = 0;
  for (uint8_t m : mask) covered += m ? 1 : 0;
  const double area = 4 * kHalfWidthPx * kHalfWidthPx;
  CHECK(std::abs(double(covered) - area) < 0.005 * area);
  CHECK(img.at(0, 0)[3] == 255);  // opaque output
}

TEST_CASE("Textured quad: each quadrant shows its texel, rows top to bottom, uv origin bottom left", "[render]") {
  sdm::Image tex(2, 2, 4);
  const uint8_t texels[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
  for (int i = 0; i < 4; ++i) std::copy(texels[i], texels[i] + 4, tex.at(i % 2, i / 2));
  sdm::RenderOptions o;
  o.azimuth_deg = 0;
  o.elevation_deg = 0;
  o.unlit = true;
  o.texture = &tex;
  const sdm::Image img = sdm::render_mesh(gl(), square(), o);
  const int d = int(kHalfWidthPx / 2);  // quadrant centres: uv 0.25 / 0.75, texel centres
  const int xs[2] = {400 - d, 399 + d}, ys[2] = {400 - d, 399 + d};
  for (int i = 0; i < 4; ++i) {
    const uint8_t* p = img.at(xs[i % 2], ys[i / 2]);
    INFO("quadrant " << i);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(int(p[k]) - int(texels[i][k])) <= 2);
  }
  // A texture needs uv.
  sdm::Mesh no_uv = square();
  no_uv.release_halfedge_texcoords2D();
  CHECK_THROWS_AS(sdm::render_mesh(gl(), no_uv, o), sdm::InputError);
}

TEST_CASE("Two tessellations of one textured square render the same pixels unlit", "[render]") {
  sdm::Image tex(8, 8, 4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      uint8_t* p = tex.at(x, y);
      p[0] = uint8_t(32 * x), p[1] = uint8_t(32 * y), p[2] = uint8_t((x + y) % 2 ? 255 : 0), p[3] = 255;
    }
  sdm::RenderOptions o;
  o.azimuth_deg = 25;
  o.elevation_deg = 35;
  o.unlit = true;
  o.texture = &tex;
  std::vector<uint8_t> m1, m4;
  const sdm::Image a = sdm::render_mesh(gl(), square(1), o, &m1);
  const sdm::Image b = sdm::render_mesh(gl(), square(4), o, &m4);
  const double p = sdm::psnr(a, b, &m1);
  INFO("PSNR 2 vs 32 triangles: " << p << " dB");
  CHECK(p > 45.0);  // only rasterisation rounding differs
  // A different texture on the same shape is clearly worse.
  sdm::Image shifted = tex;
  for (auto& v : shifted.pixels) v = uint8_t(255 - v);
  o.texture = &shifted;
  const sdm::Image c = sdm::render_mesh(gl(), square(4), o);
  CHECK(sdm::psnr(a, c, &m1) < 15.0);
}

TEST_CASE("Headlight shading: centre brightness follows the cosine of the viewing angle", "[render]") {
  sdm::RenderOptions o;
  o.elevation_deg = 0;
  o.color = Eigen::Vector3f(1, 1, 1);
  o.ambient = 0.25;
  o.background = {0, 0, 0, 255};
  for (double az : {0.0, 45.0, 70.0}) {
    o.azimuth_deg = az;
    const sdm::Image img = sdm::render_mesh(gl(), square(), o);
    // The centre pixel looks at the square's centre: Lambert factor cos(az).
    const double expected = 255.0 * (0.25 + 0.75 * std::cos(az * M_PI / 180.0));
    INFO("azimuth " << az);
    CHECK(std::abs(img.at(400, 400)[0] - expected) <= 2.0);
  }
}

TEST_CASE("Crease-aware normals keep a cube's faces flat", "[render]") {
  sdm::MeshSoup s;
  for (int i = 0; i < 8; ++i) s.points.emplace_back(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  const sdm::Mesh cube = sdm::build_mesh(s);
  sdm::RenderOptions o;
  o.azimuth_deg = 0;
  o.elevation_deg = 0;
  o.color = Eigen::Vector3f(1, 1, 1);
  o.background = {0, 0, 0, 255};
  // Pixel 640 on the middle row sees the front face (z = 0.5) at x = 0.458, 9.1 degrees off the
  // view axis from the eye at distance sqrt(3)/2 / sin(15 deg) from the centre: Lambert 0.987.
  const double d = std::sqrt(3.0) / 2 / std::sin(15.0 * M_PI / 180.0);
  const double x = 240.0 / 400.0 * (d - 0.5) * std::tan(15.0 * M_PI / 180.0);
  const double lambert = (d - 0.5) / std::hypot(x, d - 0.5);
  const double expected = 255.0 * (0.25 + 0.75 * lambert);
  const sdm::Image crease = sdm::render_mesh(gl(), cube, o);
  CHECK(std::abs(crease.at(640, 400)[0] - expected) <= 2.0);
  o.crease_angle_deg = 180;  // smooth everything: the normal near the edge tilts towards the side face
  const sdm::Image smooth = sdm::render_mesh(gl(), cube, o);
  INFO("crease " << int(crease.at(640, 400)[0]) << ", smooth " << int(smooth.at(640, 400)[0]));
  CHECK(smooth.at(640, 400)[0] < expected - 20);
}

TEST_CASE("frame_camera keeps the bounding box inside the image for any angle", "[render]") {
  const Eigen::Vector3d lo(-1, 2, 10), hi(3, 2.5, 14);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ang(-180, 180);
  for (int k = 0; k < 20; ++k) {
    for (bool ortho : {false, true}) {
      const sdm::Camera cam = sdm::frame_camera(lo, hi, ang(rng), ang(rng) / 2, 640, 480, ortho);
      const Eigen::Vector4d c = cam.projection * cam.view * Eigen::Vector4d(2.5 - 1.5, 2.25, 12, 1);
      CHECK(std::abs(c.x() / c.w()) < 1e-9);  // the box centre is the image centre
      CHECK(std::abs(c.y() / c.w()) < 1e-9);
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector4d p(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z(), 1);
        const Eigen::Vector4d q = cam.projection * cam.view * p;
        CHECK(std::abs(q.x() / q.w()) <= 1.0);
        CHECK(std::abs(q.y() / q.w()) <= 1.0);
        CHECK(std::abs(q.z() / q.w()) <= 1.0);  // between the near and far planes
      }
    }
  }
  CHECK_THROWS_AS(sdm::frame_camera(hi, lo, 0, 0, 10, 10), sdm::InputError);
  CHECK_THROWS_AS(sdm::frame_camera(lo, lo, 0, 0, 10, 10), sdm::InputError);
}

TEST_CASE("PSNR: infinite for equal images, hand-computed otherwise, masked", "[render]") {
  sdm::Image a(2, 2, 4, 100), b = a;
  CHECK(std::isinf(sdm::psnr(a, a)));
  b.at(1, 0)[1] = 110;  // one channel of one pixel off by 10
  // MSE over 4 pixels x 3 colour channels = 100 / 12.
  CHECK(sdm::psnr(a, b) == Approx(10 * std::log10(255.0 * 255.0 * 12 / 100)));
  const std::vector<uint8_t> with{0, 1, 1, 0}, without{1, 0, 0, 1}, none{0, 0, 0, 0};
  CHECK(sdm::psnr(a, b, &with) == Approx(10 * std::log10(255.0 * 255.0 * 6 / 100)));
  CHECK(std::isinf(sdm::psnr(a, b, &without)));
  b.at(0, 1)[3] = 0;  // alpha is not colour
  CHECK(std::isinf(sdm::psnr(a, b, &without)));
  CHECK_THROWS_AS(sdm::psnr(a, b, &none), sdm::InputError);
  CHECK_THROWS_AS(sdm::psnr(a, sdm::Image(3, 2, 4)), sdm::InputError);
  CHECK(sdm::mask_union(with, without) == std::vector<uint8_t>(4, 255));
}

TEST_CASE("PNG write/read round trip is exact; contact sheet places images", "[render]") {
  const fs::path dir = temp_dir("png");
  std::mt19937 rng(7);
  sdm::Image rgba(37, 23, 4), rgb(5, 3, 3);
  for (auto& v : rgba.pixels) v = uint8_t(rng());
  for (auto& v : rgb.pixels) v = uint8_t(rng());
  sdm::write_png(rgba, (dir / "a.png").string());
  sdm::write_png(rgb, (dir / "b.png").string());
  const sdm::Image ra = sdm::read_png((dir / "a.png").string());
  CHECK(ra.width == 37);
  CHECK(ra.height == 23);
  CHECK(ra.pixels == rgba.pixels);
  const sdm::Image rb = sdm::read_png((dir / "b.png").string());  // read back as RGBA
  REQUIRE(rb.channels == 4);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      for (int k = 0; k < 3; ++k) CHECK(rb.at(x, y)[k] == rgb.at(x, y)[k]);
      CHECK(rb.at(x, y)[3] == 255);
    }
  // Grey and grey with alpha come back as RGBA with the grey in every colour channel.
  for (int channels : {1, 2}) {
    sdm::Image grey(6, 4, channels);
    for (auto& v : grey.pixels) v = uint8_t(rng());
    const std::string path = (dir / ("g" + std::to_string(channels) + ".png")).string();
    sdm::write_png(grey, path);
    const sdm::Image rg = sdm::read_png(path);
    REQUIRE(rg.width == 6);
    REQUIRE(rg.height == 4);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 6; ++x) {
        for (int k = 0; k < 3; ++k) CHECK(rg.at(x, y)[k] == grey.at(x, y)[0]);
        CHECK(rg.at(x, y)[3] == (channels == 2 ? grey.at(x, y)[1] : 255));
      }
  }
  const std::string missing = (dir / "missing.png").string();
  try {
    sdm::read_png(missing);
    FAIL("no exception");
  } catch (const sdm::InputError& e) {
    CHECK(std::string(e.what()).find(missing) != std::string::npos);
  }
  // Two images side by side, 4 px apart: the second starts at x = 37 + 4.
  const sdm::Image sheet = sdm::side_by_side({rgba, rgb}, 4);
  CHECK(sheet.width == 37 + 4 + 37);
  CHECK(sheet.height == 23);
  CHECK(sheet.at(41, 2)[0] == rgb.at(0, 2)[0]);
  CHECK(sheet.at(38, 0)[0] == 255);  // gap
  const sdm::Image grid = sdm::contact_sheet({rgb, rgb, rgb}, 2, 1);
  CHECK(grid.width == 11);
  CHECK(grid.height == 7);
  CHECK(grid.at(0, 4)[2] == rgb.at(0, 0)[2]);  // third image starts the second row
  fs::remove_all(dir);
}

TEST_CASE("sdm render writes a PNG of a mesh; missing input exits 2 with no output", "[render]") {
  const fs::path dir = temp_dir("cli");
  {
    // Octahedron with outward faces.
    std::ofstream off(dir / "octa.off");
    off << "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
           "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
  }
  const std::string out = (dir / "view.png").string();
  REQUIRE(run("render " + (dir / "octa.off").string() + " -o " + out + " --width 160 --height 120") == 0);
  const sdm::Image img = sdm::read_png(out);
  CHECK(img.width == 160);
  CHECK(img.height == 120);
  auto is_white = [&](int x, int y) { return img.at(x, y)[0] == 255 && img.at(x, y)[1] == 255 && img.at(x, y)[2] == 255; };
  CHECK(!is_white(80, 60));  // the octahedron is at the centre
  CHECK(is_white(0, 0));
  CHECK(is_white(159, 119));
  // The octahedron's bounding sphere (radius sqrt 3) fills the height; the body (radius 1) covers
  // at least the disc of its inscribed sphere (radius 1/sqrt 3): 1/3 of the sphere's radius.
  const double r_px = 60.0 * (1.0 / std::sqrt(3.0)) / std::sqrt(3.0) * std::cos(15.0 * M_PI / 180.0);
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * M_PI * k / 16;
    CHECK(!is_white(int(80 + 0.9 * r_px * std::cos(a)), int(60 + 0.9 * r_px * std::sin(a))));
  }
  {
    // The same octahedron as a textured OBJ: the upper faces map into the texture's top row (red),
    // the lower faces into its bottom row (blue); the MTL names the texture.
    sdm::Image tex(2, 2, 4);
    const uint8_t red[4] = {255, 0, 0, 255}, blue[4] = {0, 0, 255, 255};
    for (int x = 0; x < 2; ++x) std::copy(red, red + 4, tex.at(x, 0)), std::copy(blue, blue + 4, tex.at(x, 1));
    sdm::write_png(tex, (dir / "tex.png").string());
    std::ofstream(dir / "octa.mtl") << "newmtl m\nmap_Kd tex.png\n";
    std::ofstream obj(dir / "octa.obj");
    obj << "mtllib octa.mtl\nv 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
           "vt 0.5 0.75\nvt 0.5 0.25\nusemtl m\n"
           "f 1/1 3/1 5/1\nf 3/1 2/1 5/1\nf 2/2 4/2 5/2\nf 4/2 1/2 5/2\n"
           "f 3/1 1/1 6/1\nf 2/1 3/1 6/1\nf 4/2 2/2 6/2\nf 1/2 4/2 6/2\n";
  }
  const std::string textured = (dir / "textured.png").string();
  REQUIRE(run("render " + (dir / "octa.obj").string() + " -o " + textured +
              " --width 160 --height 120 --unlit --azimuth 0 --elevation 0") == 0);
  const sdm::Image t = sdm::read_png(textured);
  CHECK((t.at(80, 50)[0] == 255 && t.at(80, 50)[2] == 0));  // above the equator: red
  CHECK((t.at(80, 70)[0] == 0 && t.at(80, 70)[2] == 255));  // below: blue
  const std::string out2 = (dir / "none.png").string();
  CHECK(run("render " + (dir / "missing.off").string() + " -o " + out2) == 2);
  CHECK(!fs::exists(out2));
  CHECK(run("render " + (dir / "octa.off").string() + " -o " + out2 + " --texture " + (dir / "t.png").string()) == 2);
  CHECK(!fs::exists(out2));
  fs::remove_all(dir);
}

namespace {

// A closed box with half extents h, turned by R about the origin and moved by t; every face cut
// into n x n cells so that the vertices spread over the surface.
sdm::Mesh box(const Eigen::Vector3d& h, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, int n = 4) {
  sdm::MeshSoup s;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int base = int(s.points.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          Eigen::Vector3d p;
          p[axis] = side * h[axis];
          p[u] = h[u] * (2.0 * i / n - 1), p[v] = h[v] * (2.0 * j / n - 1);
          s.points.push_back(R * p + t);
        }
      auto id = [&](int i, int j) { return base + j * (n + 1) + i; };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          std::array<int, 3> t1{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, t2{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
          if (side < 0) std::swap(t1[1], t1[2]), std::swap(t2[1], t2[2]);
          s.triangles.push_back(t1), s.triangles.push_back(t2);
        }
    }
  // Corners and edges are shared by two or three faces: weld equal points.
  std::vector<int> remap(s.points.size());
  sdm::MeshSoup w;
  for (size_t i = 0; i < s.points.size(); ++i) {
    int found = -1;
    for (size_t k = 0; k < w.points.size() && found < 0; ++k)
      if ((w.points[k] - s.points[i]).norm() < 1e-9) found = int(k);
    if (found < 0) found = int(w.points.size()), w.points.push_back(s.points[i]);
    remap[i] = found;
  }
  for (const auto& tri : s.triangles) w.triangles.push_back({remap[tri[0]], remap[tri[1]], remap[tri[2]]});
  return sdm::build_mesh(w);
}

// Width and height in pixels of the covered pixels' bounding box.
Eigen::Vector2i silhouette_size(const std::vector<uint8_t>& mask, int width, int height) {
  int x0 = width, x1 = -1, y0 = height, y1 = -1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (mask[size_t(y) * width + x]) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  return x1 < 0 ? Eigen::Vector2i(0, 0) : Eigen::Vector2i(x1 - x0 + 1, y1 - y0 + 1);
}

}  // namespace

// Silhouette (width, height) in pixels of `mesh` rendered orthographically, 400 x 400, from
// azimuth and elevation 0 in `frame`.
Eigen::Vector2i principal_silhouette(const sdm::Mesh& mesh, const Eigen::Matrix3d& frame) {
  sdm::RenderOptions o;
  o.width = o.height = 400;
  o.orthographic = true;
  o.samples = 1;
  o.azimuth_deg = o.elevation_deg = 0;
  o.frame = frame;
  std::vector<uint8_t> mask;
  sdm::render_mesh(gl(), mesh, o, &mask);
  return silhouette_size(mask, o.width, o.height);
}

// A box 4 long, 1 wide and 0.5 deep lying along z with its thin side along y (as TOSCA's people lie):
// seen in its principal frame it stands upright and shows its broad side, so (orthographic) its
// silhouette is 4 times as tall as wide; looked at along its middle axis it would be 8 times, along
// its long axis shorter than wide. The same for a copy turned about y and tilted 10 degrees. The
// default camera (world axes, +y up) sees the box foreshortened and wider than tall.
TEST_CASE("principal_view_frame stands a box lying along z upright and shows its broad side", "[render]") {
  const Eigen::Vector3d half(0.5, 0.25, 2.0);
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitX())).toRotationMatrix();
  for (const Eigen::Matrix3d& R : {Eigen::Matrix3d(Eigen::Matrix3d::Identity()), turn}) {
    const sdm::Mesh b = box(half, R, Eigen::Vector3d(3, -1, 7));
    const Eigen::Matrix3d F = sdm::principal_view_frame(b);
    CHECK((F.transpose() * F - Eigen::Matrix3d::Identity()).norm() < 1e-9);
    CHECK(std::abs(F.determinant() - 1) < 1e-9);
    CHECK(std::abs(F.col(1).dot(R.col(2))) > 1 - 1e-9);  // up: the long axis
    CHECK(std::abs(F.col(2).dot(R.col(1))) > 1 - 1e-9);  // looked along: the shortest axis
    const Eigen::Vector2i size = principal_silhouette(b, F);
    const double ratio = double(size.y()) / size.x();
    WARN("box along " << (R.isIdentity() ? "z" : "a turned axis") << ", principal view: silhouette " << size.x() << " x " << size.y()
                      << " px (height / width " << ratio << ")");
    CHECK(ratio > 3.8);
    CHECK(ratio < 4.2);
  }
  const sdm::Mesh b = box(half, Eigen::Matrix3d::Identity(), Eigen::Vector3d(3, -1, 7));
  CHECK(sdm::principal_view_frame(b).col(1).isApprox(Eigen::Vector3d(0, 0, 1)));  // the way of +z, the axis it lies along
  sdm::RenderOptions d;
  d.width = d.height = 400;
  d.samples = 1;
  std::vector<uint8_t> mask;
  sdm::render_mesh(gl(), b, d, &mask);
  const Eigen::Vector2i dsize = silhouette_size(mask, d.width, d.height);
  WARN("default view of the box along z: silhouette " << dsize.x() << " x " << dsize.y() << " px");
  CHECK(dsize.y() < dsize.x());
}

// The same box standing on its 1-wide side (y up, as Spot stands on its legs with its body along
// z): y is not its thinnest dimension, so the file's up is kept and the box is seen from its broad
// side, 4 times as wide as tall.
TEST_CASE("principal_view_frame keeps +y up for a model not lying flat", "[render]") {
  const sdm::Mesh b = box(Eigen::Vector3d(0.25, 0.5, 2.0), Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0));
  const Eigen::Matrix3d F = sdm::principal_view_frame(b);
  CHECK(F.col(1).isApprox(Eigen::Vector3d(0, 1, 0)));
  CHECK(std::abs(F.col(2).x()) > 1 - 1e-9);  // looked at along x, the thinnest axis
  const Eigen::Vector2i size = principal_silhouette(b, F);
  const double ratio = double(size.x()) / size.y();
  WARN("box standing along y, principal view: silhouette " << size.x() << " x " << size.y() << " px (width / height " << ratio << ")");
  CHECK(ratio > 3.8);
  CHECK(ratio < 4.2);
}

TEST_CASE("sdm render draws an OBJ's vertex colours (v x y z r g b), blended across faces", "[render]") {
  // A tetrahedron whose corners are red, green, blue and yellow: unlit, every pixel it covers
  // fully is a blend of those four (its red + green + blue stays within [255, 510]: each corner's
  // sum is 255 or 510) and none is the flat grey; --no-texture draws the flat grey instead.
  test_util::TempDir dir;
  test_util::write_file(dir / "tet.obj",
                        "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 1 1 0\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const auto colored = test_util::run_sdm("render " + (dir / "tet.obj") + " --unlit --width 200 --height 200 -o " + (dir / "c.png"));
  const auto flat = test_util::run_sdm("render " + (dir / "tet.obj") + " --unlit --no-texture --width 200 --height 200 -o " + (dir / "f.png"));
  INFO(colored.output << flat.output);
  REQUIRE(colored.exit_code == 0);
  REQUIRE(flat.exit_code == 0);
  const sdm::Image c = sdm::read_png(dir / "c.png"), f = sdm::read_png(dir / "f.png");
  long object = 0, blends = 0, reddest = 0, greenest = 0, bluest = 0, grey = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const auto p = c.at(x, y), q = f.at(x, y);
      if (p[0] == 255 && p[1] == 255 && p[2] == 255) continue;
      ++object;
      const int sum = p[0] + p[1] + p[2];
      blends += sum >= 250 && sum <= 515;
      reddest += p[0] > 200 && p[1] < 60 && p[2] < 60, greenest += p[1] > 200 && p[0] < 60 && p[2] < 60;
      bluest += p[2] > 200 && p[0] < 60 && p[1] < 60;
      grey += std::abs(q[0] - 199) <= 1 && std::abs(q[1] - 199) <= 1 && std::abs(q[2] - 204) <= 1;
    }
  INFO(object << " object pixels: " << blends << " blends of the corners, " << reddest << " red, " << greenest << " green, "
              << bluest << " blue; flat " << grey);
  CHECK(object > 5000);
  CHECK(blends > object * 95 / 100);
  CHECK((reddest > 0 || greenest > 0 || bluest > 0));
  CHECK(greenest + bluest > 0);
  CHECK(grey > object * 9 / 10);
}

TEST_CASE("sdm render --up shows a Z-up (or -Y-up) file as its Y-up original; a bad axis exits 2", "[render]") {
  // An irregular tetrahedron with coloured corners, written as it is (+y up), turned so that its
  // +y becomes +z (x, y, z) -> (x, -z, y), and turned upside down about z (x, y, z) -> (-x, -y, z).
  // up_view_frame is the rotation that undoes each, so the pictures are the original's.
  test_util::TempDir dir;
  const std::vector<Eigen::Vector3d> corners = {{0, 0, 0}, {1, 0.2, 0}, {0.1, 1.6, 0.3}, {0.2, 0.1, 0.9}};
  const std::string faces = "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  const char* colors[] = {" 1 0 0\n", " 0 1 0\n", " 0 0 1\n", " 1 1 0\n"};
  auto write = [&](const std::string& name, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& turn) {
    std::string text;
    for (size_t i = 0; i < corners.size(); ++i) {
      const Eigen::Vector3d p = turn(corners[i]);
      text += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + colors[i];
    }
    test_util::write_file(dir / name, text + faces);
  };
  write("y.obj", [](const Eigen::Vector3d& p) { return p; });
  write("z.obj", [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p.x(), -p.z(), p.y()); });
  write("-y.obj", [](const Eigen::Vector3d& p) { return Eigen::Vector3d(-p.x(), -p.y(), p.z()); });
  auto render = [&](const std::string& in, const std::string& up, const std::string& out) {
    const auto r = test_util::run_sdm("render " + (dir / in) + up + " --unlit --width 160 --height 160 -o " + (dir / out));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    return sdm::read_png(dir / out);
  };
  const sdm::Image original = render("y.obj", "", "y.png");
  const double z_up = sdm::psnr(original, render("z.obj", " --up z", "z.png"));
  const double minus_y = sdm::psnr(original, render("-y.obj", " --up -y", "-y.png"));
  const double lying = sdm::psnr(original, render("z.obj", "", "z-default.png"));
  WARN("PSNR against the +y original: --up z " << z_up << " dB, --up -y " << minus_y << " dB, the Z-up file without --up " << lying << " dB");
  CHECK(z_up > 40);
  CHECK(minus_y > 40);
  CHECK(lying < 25);
  const auto bad = test_util::run_sdm("render " + (dir / "y.obj") + " --up w -o " + (dir / "w.png"));
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("--up 'w'") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "w.png"));
}

TEST_CASE("sdm render draws a point cloud as disks: a sampled sphere's silhouette, analytic and without holes", "[render]") {
  const fs::path dir = temp_dir("cloud");
  // 4000 points on the unit sphere (a Fibonacci spiral), without normals (.xyz: estimated) and with
  // them (PLY). Seen orthographically, the bounding sphere of the box [-1, 1]^3 (radius sqrt 3)
  // fills the image, so the sphere's outline is a disc of radius (side / 2) / sqrt 3.
  const int n = 4000;
  std::ofstream xyz(dir / "sphere.xyz"), ply(dir / "sphere.ply");
  ply << "ply\nformat ascii 1.0\nelement vertex " << n
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n";
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z), a = i * M_PI * (3 - std::sqrt(5.0));
    const Eigen::Vector3d p(r * std::cos(a), r * std::sin(a), z);
    xyz << p.x() << " " << p.y() << " " << p.z() << "\n";
    ply << p.x() << " " << p.y() << " " << p.z() << " " << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  xyz.close(), ply.close();
  const int side = 300;
  const double radius_px = side / 2.0 / std::sqrt(3.0);
  for (const char* name : {"sphere.xyz", "sphere.ply"}) {
    INFO(name);
    const std::string out = (dir / (std::string(name) + ".png")).string();
    REQUIRE(run("render " + (dir / name).string() + " --orthographic --unlit --width 300 --height 300 -o " + out) == 0);
    const sdm::Image img = sdm::read_png(out);
    long covered = 0, holes = 0, outside = 0;
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {
        const bool object = img.at(x, y)[0] != 255;
        const double d = std::hypot(x + 0.5 - side / 2.0, y + 0.5 - side / 2.0);
        covered += object;
        holes += !object && d < 0.97 * radius_px;
        outside += object && d > 1.03 * radius_px;
      }
    CHECK(holes == 0);
    CHECK(outside == 0);
    CHECK(std::abs(double(covered) / (M_PI * radius_px * radius_px) - 1) < 0.03);
  }
  // The maps of a mesh are not drawn on points.
  CHECK(run("render " + (dir / "sphere.xyz").string() + " --checker --layout none.json -o " + (dir / "x.png").string()) == 2);
  CHECK(!fs::exists(dir / "x.png"));
  fs::remove_all(dir);
}
