// The SDM file format: round trip, and a clear error for each kind of wrong file.
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/errors.h"
#include "tests/test_util.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <catch2/catch.hpp>
#include <filesystem>

using namespace sdm;

namespace {

SdmImage ramp(int w, int h) {
  SdmImage im;
  im.width = w;
  im.height = h;
  for (int i = 0; i < w * h; ++i) {
    im.D.push_back(0.001f * float(i) + 1.0f / 3.0f);
    im.A.push_back(float(i % 3 == 0));
  }
  im.layout = {{"format", "sdm-layout"}, {"version", 1}, {"size", w}};
  return im;
}

void write_raw_exr(const std::string& path, const std::vector<std::string>& channels, const std::string* layout, int version) {
  Imf::Header header(4, 4);
  if (layout) header.insert("sdm_layout", Imf::StringAttribute(*layout));
  if (version) header.insert("sdm_format_version", Imf::IntAttribute(version));
  std::vector<float> data(16, 0.5f);
  Imf::FrameBuffer fb;
  for (const auto& c : channels) {
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    fb.insert(c, Imf::Slice(Imf::FLOAT, (char*)data.data(), sizeof(float), 4 * sizeof(float)));
  }
  Imf::OutputFile f(path.c_str(), header);
  f.setFrameBuffer(fb);
  f.writePixels(4);
}

std::string error_of(const std::string& path) {
  try {
    read_sdm_exr(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("SDM EXR round trip is exact in float32 and keeps the layout", "[sdm_exr]") {
  test_util::TempDir dir;
  SdmImage im = ramp(37, 21);
  write_sdm_exr(im, dir / "a.exr");
  SdmImage r = read_sdm_exr(dir / "a.exr");
  CHECK(r.width == 37);
  CHECK(r.height == 21);
  CHECK(r.D == im.D);
  CHECK(r.A == im.A);
  CHECK(r.X.empty());
  CHECK(r.layout == im.layout);
}

TEST_CASE("Wrong SDM files get a message that names the problem", "[sdm_exr]") {
  test_util::TempDir dir;
  const std::string layout = R"({"format":"sdm-layout"})";
  CHECK(error_of(dir / "missing.exr").find("no such file") != std::string::npos);
  test_util::write_file(dir / "text.exr", "hello, I am not an image");
  CHECK(error_of(dir / "text.exr").find("not an OpenEXR file") != std::string::npos);

  write_sdm_exr(ramp(64, 64), dir / "full.exr");
  const auto size = std::filesystem::file_size(dir / "full.exr");
  std::filesystem::copy_file(dir / "full.exr", dir / "cut.exr");
  std::filesystem::resize_file(dir / "cut.exr", size * 2 / 3);
  const std::string cut = error_of(dir / "cut.exr");
  CHECK((cut.find("truncated") != std::string::npos || cut.find("damaged") != std::string::npos));

  write_raw_exr(dir / "nolayout.exr", {"A", "D"}, nullptr, 0);
  CHECK(error_of(dir / "nolayout.exr").find("without the sdm layout") != std::string::npos);
  write_raw_exr(dir / "nochan.exr", {"A"}, &layout, 1);
  CHECK(error_of(dir / "nochan.exr").find("lacks channel 'D'") != std::string::npos);
  const std::string bad = "{not json";
  write_raw_exr(dir / "badjson.exr", {"A", "D"}, &bad, 1);
  CHECK(error_of(dir / "badjson.exr").find("invalid layout") != std::string::npos);
  write_raw_exr(dir / "v99.exr", {"A", "D"}, &layout, 99);
  CHECK(error_of(dir / "v99.exr").find("format version 99") != std::string::npos);
  // An attribute whose size field claims 1.6 GB: OpenEXR allocated it before reading (libFuzzer).
  std::string big("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  big += std::string("junk\0opaque\0", 12) + std::string("\x00\x00\x60\x61", 4) + "0123456789";
  test_util::write_file(dir / "big.exr", big);
  CHECK(error_of(dir / "big.exr").find("claims 1633681408 bytes") != std::string::npos);
}

TEST_CASE("Format 2 stores the displacement as luminance Y and the mask as alpha: RGBA readers see the map", "[sdm_exr]") {
  test_util::TempDir dir;
  const SdmImage im = ramp(16, 8);
  write_sdm_exr(im, dir / "m.exr");
  Imf::RgbaInputFile file((dir / "m.exr").c_str());
  CHECK((file.channels() & Imf::WRITE_Y));
  CHECK((file.channels() & Imf::WRITE_A));
  std::vector<Imf::Rgba> px(16 * 8);
  file.setFrameBuffer(px.data(), 1, 16);
  file.readPixels(0, 7);
  for (int i = 0; i < 16 * 8; ++i) {
    // A luminance-only image reads back as grey: r = g = b = Y = D (half precision in Rgba).
    CHECK(float(px[i].r) == Approx(im.D[i]).epsilon(1e-3));
    CHECK(float(px[i].g) == Approx(im.D[i]).epsilon(1e-3));
    CHECK(float(px[i].a) == im.A[i]);
  }
}

TEST_CASE("Half precision keeps 11 significant bits of D and an exact mask, in a smaller file", "[sdm_exr]") {
  test_util::TempDir dir;
  const SdmImage im = ramp(64, 64);
  write_sdm_exr(im, dir / "f.exr");
  write_sdm_exr(im, dir / "h.exr", SdmPrecision::half16);
  const SdmImage r = read_sdm_exr(dir / "h.exr");
  for (size_t i = 0; i < im.D.size(); ++i) {
    CHECK(std::abs(r.D[i] - im.D[i]) <= std::ldexp(std::abs(im.D[i]), -11));  // half: 10 stored bits + 1 implied
    CHECK(r.A[i] == im.A[i]);
  }
  CHECK(std::filesystem::file_size(dir / "h.exr") < std::filesystem::file_size(dir / "f.exr"));
}

TEST_CASE("Format 1 files (channels D and A) still read", "[sdm_exr]") {
  test_util::TempDir dir;
  const std::string layout = R"({"format":"sdm-layout"})";
  write_raw_exr(dir / "v1.exr", {"A", "D"}, &layout, 1);
  const SdmImage r = read_sdm_exr(dir / "v1.exr");
  CHECK(r.width == 4);
  CHECK(r.D == std::vector<float>(16, 0.5f));
  CHECK(r.A == std::vector<float>(16, 0.5f));
  // A version 2 file needs its own names: D and A alone are not a version 2 map.
  write_raw_exr(dir / "v2.exr", {"A", "D"}, &layout, 2);
  CHECK(error_of(dir / "v2.exr").find("lacks channel 'Y'") != std::string::npos);
}
