// Compact maps (format 3): the base mesh in binary, texels no base face reads left out,
// the residual against the decoder's prediction quantised; old files still decode.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/base_mesh.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/base_mesh_blob.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/mesh/validate_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "tests/test_util.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace sdm;

namespace {

struct Encoded {
  Mesh mesh;
  SdmImage image;
};

Encoded encode(const Mesh& mesh, int size) {
  LayoutOptions lo;
  lo.size = size;
  return {mesh, encode_sdm(mesh, compute_layout(mesh, extract_skeleton(mesh), lo))};
}

double rms_of(const Mesh& a, const Mesh& b) {
  const SurfaceDistance d = surface_distance(a, b, 100000);
  return d.rms / d.diagonal;
}

// A format 2 file as the previous sdm wrote it: float Y and half A, the base mesh (without corner
// displacements) in the layout JSON, every texel as encoded.
void write_format_2(const SdmImage& im, const std::string& path) {
  nlohmann::json layout = im.layout;
  layout["base_mesh"].erase("corner_d");
  Imf::Header header(im.width, im.height);
  header.insert("sdm_layout", Imf::StringAttribute(layout.dump()));
  header.insert("sdm_format_version", Imf::IntAttribute(2));
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  header.channels().insert("A", Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  fb.insert("Y", Imf::Slice(Imf::FLOAT, (char*)im.D.data(), sizeof(float), sizeof(float) * im.width));
  fb.insert("A", Imf::Slice(Imf::FLOAT, (char*)im.A.data(), sizeof(float), sizeof(float) * im.width));
  Imf::OutputFile f(path.c_str(), header);
  f.setFrameBuffer(fb);
  f.writePixels(im.height);
}

}  // namespace

TEST_CASE("The base mesh packs to binary and back within float rounding, in a fraction of its JSON", "[compact]") {
  const Encoded e = encode(make_primitive("ypsilon"), 256);
  const nlohmann::json& j = e.image.layout.at("base_mesh");
  const std::string packed = pack_base_mesh(j);
  const nlohmann::json back = unpack_base_mesh(packed);
  CHECK(back.at("triangles") == j.at("triangles"));
  CHECK(back.at("face_segment") == j.at("face_segment"));
  for (const char* key : {"corner_uv", "corner_d"}) {
    const auto a = j.at(key).get<std::vector<double>>(), b = back.at(key).get<std::vector<double>>();
    REQUIRE(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) CHECK(std::abs(a[i] - b[i]) <= 1e-7 * (1 + std::abs(a[i])));
  }
  std::printf("base mesh: %zu bytes of JSON, %zu packed\n", j.dump().size(), packed.size());
  CHECK(packed.size() * 4 < j.dump().size());
  // Damaged bytes are refused by name, never a crash or an allocation of what they claim.
  std::string claim = packed;
  claim[5] = '\x7f';  // an inflated size of petabytes
  CHECK_THROWS_WITH(unpack_base_mesh(claim), Catch::Contains("inflated from"));
  std::string cut = packed.substr(0, packed.size() / 2);
  CHECK_THROWS_AS(unpack_base_mesh(cut), InputError);
  CHECK_THROWS_AS(unpack_base_mesh("tiny"), InputError);
}

TEST_CASE("A quantised map stores the residual within half a step and leaves unread texels out", "[compact]") {
  test_util::TempDir dir;
  const Encoded e = encode(make_primitive("bottle"), 256);
  const SdmImage& im = e.image;
  for (int bits : {6, 8, 11}) {
    const std::string path = dir / ("q" + std::to_string(bits) + ".exr");
    write_sdm_exr(im, path, SdmPrecision(SdmPrecision::quantized, bits));
    const SdmImage r = read_sdm_exr(path);
    CHECK(r.residual);
    double largest = 0;
    for (size_t i = 0; i < im.D.size(); ++i)
      if (!std::isnan(im.foot[i])) largest = std::max(largest, std::abs(double(im.D[i]) - im.foot[i]));
    const double step = largest / ((1 << (bits - 1)) - 1);
    long read = 0, out = 0;
    for (size_t i = 0; i < im.D.size(); ++i) {
      if (std::isnan(im.foot[i])) {
        CHECK(std::isnan(r.D[i]));
        CHECK(r.A[i] == 0.0f);
        ++out;
        continue;
      }
      ++read;
      CHECK(std::abs(double(r.D[i]) - (double(im.D[i]) - im.foot[i])) <= 0.5 * step * (1 + 1e-6) + 1e-7);
    }
    CHECK(read > 0);
    CHECK(out > 0);
    // What the encoder checks is what a reader gets.
    const SdmImage s = as_stored(im, SdmPrecision(SdmPrecision::quantized, bits));
    for (size_t i = 0; i < im.D.size(); ++i) CHECK((std::isnan(s.D[i]) ? std::isnan(r.D[i]) : s.D[i] == r.D[i]));
  }
  // An RGBA reader (OpenEXR's own interface, as viewers use it) sees a grey image in (0, 1) with
  // non-zero luminance wherever the texel sees its own surface.
  {
    Imf::RgbaInputFile rgba((dir / "q8.exr").c_str());
    const Imath::Box2i dw = rgba.dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::vector<Imf::Rgba> px(size_t(w) * size_t(h));
    rgba.setFrameBuffer(px.data(), 1, size_t(w));
    rgba.readPixels(dw.min.y, dw.max.y);
    long own = 0;
    for (size_t i = 0; i < px.size(); ++i) {
      if (float(px[i].a) != 1.0f) continue;
      ++own;
      CHECK(float(px[i].r) > 0.0f);
      CHECK(float(px[i].r) < 1.0f);
      CHECK(float(px[i].g) == float(px[i].r));
    }
    CHECK(own > 0);
  }
  CHECK_THROWS_AS(SdmPrecision::parse("3"), InputError);
  CHECK_THROWS_AS(SdmPrecision::parse("12"), InputError);
  CHECK_THROWS_AS(SdmPrecision::parse("8bits"), InputError);
  CHECK(SdmPrecision::parse("9").bits == 9);
}

TEST_CASE("Every precision of format 3 decodes within the float map's error; format 2 files still decode", "[compact]") {
  test_util::TempDir dir;
  const Encoded e = encode(make_primitive("ypsilon"), 512);
  const double exact = rms_of(e.mesh, decode_sdm(e.image));
  for (const char* p : {"float", "half", "10", "8"}) {
    const std::string path = dir / (std::string(p) + ".exr");
    write_sdm_exr(e.image, path, SdmPrecision::parse(p));
    const Mesh out = decode_sdm(read_sdm_exr(path));
    const double rms = rms_of(e.mesh, out);
    std::printf("ypsilon 512, %s: %ju bytes, RMS %.5f %% (in memory %.5f %%)\n", p, std::filesystem::file_size(path), 100 * rms,
                100 * exact);
    CHECK(rms <= 1.5 * exact + 2e-5);
    CHECK(validate_mesh(mesh_to_soup(out)).usable());
  }
  write_format_2(e.image, dir / "v2.exr");
  const Mesh old = decode_sdm(read_sdm_exr(dir / "v2.exr"));
  CHECK(rms_of(e.mesh, old) <= 1.5 * exact + 2e-5);
}

TEST_CASE("Spot at level 3 within 0.02 % RMS in a map of at most 150 KB", "[compact]") {
  test_util::TempDir dir;
  const Encoded e = encode(load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj").mesh, 512);
  const std::string path = dir / "spot.exr";
  write_sdm_exr(e.image, path, SdmPrecision::parse("8"));
  const auto bytes = std::filesystem::file_size(path);
  const Mesh out = decode_sdm(read_sdm_exr(path));
  const SurfaceDistance d = surface_distance(e.mesh, out, 100000);
  std::printf("Spot 512, 8 bits: %ju bytes, level 3 RMS %.4f %%, Hausdorff %.3f %%\n", uintmax_t(bytes), 100 * d.rms / d.diagonal,
              100 * d.hausdorff / d.diagonal);
  CHECK(bytes <= 150000);
  CHECK(d.rms / d.diagonal <= 0.0002);
  CHECK(d.hausdorff / d.diagonal <= 0.01);
}

TEST_CASE("sdm roundtrip goes through the file, reports its bytes and where the worst error is, and draws it", "[compact]") {
  test_util::TempDir dir;
  const std::string mesh = dir / "bottle.obj", png = dir / "error.png";
  REQUIRE(test_util::run_sdm("primitive bottle -o " + mesh).exit_code == 0);
  const auto r = test_util::run_sdm("roundtrip " + mesh + " --size 512 --json --png " + png);
  REQUIRE(r.exit_code == 0);
  const auto j = test_util::last_json(r);
  CHECK(j["precision"] == "10");
  CHECK(j["map_bytes"].get<double>() > 1000);
  CHECK(j["map_bytes"].get<double>() < 512 * 512 * 2);  // under one half per texel
  const auto& worst = j["worst"];
  CHECK(worst["segment"].get<int>() >= 0);
  CHECK(worst["segment"].get<int>() < j["segments"].get<int>());
  CHECK(worst["base_face"].get<int>() >= 0);
  // The reported point is where the Hausdorff distance is: that far from the input when the decoded
  // surface strays there, on the input otherwise.
  const Mesh input = load_mesh(mesh).mesh;
  const auto p = worst["position"].get<std::vector<double>>();
  const double off = TriangleBvh(vertex_matrix(input), face_matrix(input)).closest_point(Eigen::Vector3d(p[0], p[1], p[2])).distance;
  const double diag = bounding_box_diagonal(input);
  if (worst["where"] == "decoded surface off the input")
    CHECK(off == Approx(j["hausdorff"].get<double>() * diag).epsilon(1e-6));
  else
    CHECK(off <= 1e-9 * diag);
  const Image picture = read_png(png);
  CHECK(picture.width == 2 * 512 + 8);
  CHECK(picture.height == 2 * 512 + 8);
  CHECK(test_util::run_sdm("roundtrip " + mesh + " --precision 12").exit_code == 2);
}

// Format 4: base faces the map cannot carry are placed on their flat triangle. A capsule
// in a 20^2 atlas has a few texels per rectangle; the encoder's check places the faces it carries
// poorly flat. The file says version 4 only when the map has flat faces (a version 3 reader would
// decode them on their rays), they survive the file, and they bring the decode closer.
TEST_CASE("Flat base faces travel in format 4 and bring the decode closer", "[compact]") {
  test_util::TempDir dir;
  const Mesh mesh = make_primitive("capsule");
  LayoutOptions lo;
  lo.size = 20;
  const Layout layout = compute_layout(mesh, extract_skeleton(mesh), lo);
  const SdmImage checked = encode_sdm(mesh, layout);
  EncodeOptions off;
  off.flat_above = 0;
  const SdmImage plain = encode_sdm(mesh, layout, off);
  const std::vector<int> flat = checked.layout.at("base_mesh").at("flat_faces").get<std::vector<int>>();
  CHECK(flat.size() > 0);
  CHECK(!plain.layout.at("base_mesh").contains("flat_faces"));
  auto version_of = [](const std::string& path) {
    Imf::InputFile f(path.c_str());
    return f.header().findTypedAttribute<Imf::IntAttribute>("sdm_format_version")->value();
  };
  write_sdm_exr(checked, dir / "flat.exr");
  write_sdm_exr(plain, dir / "plain.exr");
  CHECK(version_of(dir / "flat.exr") == 4);
  CHECK(version_of(dir / "plain.exr") == 3);
  const SdmImage back = read_sdm_exr(dir / "flat.exr");
  CHECK(back.layout.at("base_mesh").at("flat_faces").get<std::vector<int>>() == flat);
  const double with = rms_of(mesh, decode_sdm(back)), without = rms_of(mesh, decode_sdm(read_sdm_exr(dir / "plain.exr")));
  std::printf("capsule at 20^2: %zu flat faces, RMS %.4f %% (without %.4f %%)\n", flat.size(), 100 * with, 100 * without);
  CHECK(with < 0.5 * without);
  // A flat face out of range or out of order is refused by name.
  for (const auto& bad : {std::vector<int>{int(checked.layout["base_mesh"]["face_segment"].size())}, std::vector<int>{3, 2}}) {
    SdmImage broken = checked;
    broken.layout["base_mesh"]["flat_faces"] = bad;
    try {
      decode_sdm(broken);
      FAIL("accepted flat faces " << nlohmann::json(bad).dump());
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("flat face") != std::string::npos);
    }
  }
}
