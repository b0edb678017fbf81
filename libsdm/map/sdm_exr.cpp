#include "libsdm/map/sdm_exr.h"

#include "libsdm/map/base_mesh_blob.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

namespace sdm {
namespace {

const char* kLayoutAttribute = "sdm_layout";
const char* kVersionAttribute = "sdm_format_version";
const char* kBaseMeshAttribute = "sdm_base_mesh";
const char* kBitsAttribute = "sdm_bits";
const char* kQuantumAttribute = "sdm_quantum";

bool unread(const SdmImage& im, size_t i) { return !im.foot.empty() && std::isnan(im.foot[i]); }

// Channels Y and A as written: D (0 where no base face reads the texel), or the quantised
// residual's code (k + 2^(b-1)) / 2^b with k = round((D - foot) / quantum), |k| < 2^(b-1); the
// mask, 0 where no base face reads the texel.
struct StoredD {
  std::vector<float> y, mask;
  double quantum = 0;
};
StoredD stored_displacement(const SdmImage& im, SdmPrecision p) {
  StoredD out;
  out.y.assign(im.D.size(), 0.0f);
  out.mask = im.A;
  for (size_t i = 0; i < im.A.size(); ++i)
    if (unread(im, i)) out.mask[i] = 0.0f;
  if (p.kind != SdmPrecision::quantized) {
    for (size_t i = 0; i < im.D.size(); ++i) out.y[i] = unread(im, i) ? 0.0f : im.D[i];
    return out;
  }
  if (im.foot.size() != im.D.size()) throw std::invalid_argument("write_sdm_exr: a quantised map needs the encoder's prediction");
  double largest = 0;
  for (size_t i = 0; i < im.D.size(); ++i)
    if (!unread(im, i)) largest = std::max(largest, std::abs(double(im.D[i]) - im.foot[i]));
  const int half_range = (1 << (p.bits - 1)) - 1;
  out.quantum = largest > 0 ? largest / half_range : 1.0;
  for (size_t i = 0; i < im.D.size(); ++i) {
    if (unread(im, i)) continue;
    const long k = std::clamp(std::lround((double(im.D[i]) - im.foot[i]) / out.quantum), -long(half_range), long(half_range));
    out.y[i] = float(double(k + (1 << (p.bits - 1))) / double(1 << p.bits));
  }
  return out;
}

// The residual a quantised texel holds (the inverse of stored_displacement); NaN for a texel left
// out (code 0).
float quantised_residual(float y, int bits, double quantum) {
  const double half = double(1 << (bits - 1));
  const double code = std::isfinite(y) ? std::clamp(std::nearbyint(double(y) * (1 << bits)), 0.0, 2 * half - 1) : 0.0;
  return code == 0 ? NAN : float((code - half) * quantum);
}

// Format 3 leaves texels no base face reads out (D and A both 0); the reader marks them NaN.
void mark_left_out(SdmImage& im) {
  for (size_t i = 0; i < im.D.size(); ++i)
    if (im.D[i] == 0.0f && im.A[i] == 0.0f) im.D[i] = NAN;
}

void check_size(const SdmImage& im) {
  const size_t n = size_t(im.width) * size_t(im.height);
  if (im.width <= 0 || im.height <= 0 || im.D.size() != n || im.A.size() != n)
    throw std::invalid_argument("write_sdm_exr: channel sizes do not match the image size");
  const bool vec = !im.X.empty();
  if (vec && (im.X.size() != n || im.Y.size() != n || im.Z.size() != n))
    throw std::invalid_argument("write_sdm_exr: vector channels do not match the image size");
}

// The data window is checked before any pixel memory is allocated, so that a patched window
// cannot make the reader allocate gigabytes: at (0, 0), at most kMaxImageSide a side, and no more
// float pixels than the file can hold compressed (deflate, which every EXR compression but the
// lossy ones uses or undercuts, shrinks data by at most 1032:1).
void check_window(const std::string& path, const Imath::Box2i& dw, int channels) {
  const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
  const std::string window = "SDM " + path + " has a data window of " + std::to_string(w) + "x" + std::to_string(h) + " at (" +
                             std::to_string(dw.min.x) + ", " + std::to_string(dw.min.y) + ")";
  if (dw.min.x != 0 || dw.min.y != 0 || w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    throw InputError(window + ": an SDM starts at (0, 0) and has at most " + std::to_string(kMaxImageSide) + " texels a side");
  std::error_code ec;
  const double file = double(std::filesystem::file_size(path, ec));
  const double raw = double(w) * double(h) * channels * sizeof(float);
  if (!ec && raw > 1100.0 * file + (1 << 20))
    throw InputError(window + ": " + std::to_string(int64_t(raw / (1 << 20))) + " MB of pixels cannot fit compressed in its " +
                     std::to_string(int64_t(file)) + " bytes; the header was altered");
}

// A little-endian 32-bit integer of the OpenEXR header; `bad` makes the error for a cut-short file.
template <class Bad>
int32_t read_le_i32(std::istream& in, const Bad& bad) {
  unsigned char b[4];
  if (!in.read(reinterpret_cast<char*>(b), 4)) throw bad("the header is cut short");
  return int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24);
}

// OpenEXR reads a known attribute type by its own size, not by the size field before it (a box2i
// is 16 bytes whatever the field says, a channel list runs to its empty name), and allocates
// other values at the size they claim. So the walk below checks that the two agree, type by
// type: fixed-size types must say their size, a channel list must end exactly at its size with
// at most 8 channels, the data window must be one an SDM can have (check_window) before OpenEXR
// sizes its buffers by it, and the types OpenEXR sizes by their content (preview images, vectors,
// manifests) are refused: an SDM holds none.
template <class Bad>
void check_attribute_value(std::istream& in, const std::string& name, const std::string& type, int64_t size,
                           const std::string& attribute, const Bad& bad) {
  static const std::map<std::string, int> fixed = {
      {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"double", 8}, {"envmap", 1}, {"float", 4},
      {"int", 4}, {"keycode", 28}, {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"rational", 8},
      {"tiledesc", 9}, {"timecode", 8}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24},
      {"deepImageState", 1}};
  const auto f = fixed.find(type);
  if (f != fixed.end() && size != f->second)
    throw bad(attribute + " says " + std::to_string(size) + " bytes; its type has " + std::to_string(f->second));
  if (type == "preview" || type == "stringvector" || type == "floatvector" || type == "idmanifest")
    throw bad(attribute + ": an SDM holds no attribute of this type");
  auto i32 = [&]() { return read_le_i32(in, bad); };
  if (name == "dataWindow" && type == "box2i") {
    Imath::Box2i dw;
    dw.min.x = i32(), dw.min.y = i32(), dw.max.x = i32(), dw.max.y = i32();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    if (dw.min.x != 0 || dw.min.y != 0 || w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
      throw bad("it has a data window of " + std::to_string(w) + "x" + std::to_string(h) + " at (" + std::to_string(dw.min.x) + ", " +
                std::to_string(dw.min.y) + "); an SDM starts at (0, 0) and has at most " + std::to_string(kMaxImageSide) + " texels a side");
  }
  if (type != "chlist") return;
  // Every byte of the list, its closing NUL included, within the size: OpenEXR reads the list to
  // that NUL whatever the size says (a fuzzed list one byte short of its NUL let the walk end the
  // header there while OpenEXR read on into a 1.7 GB attribute).
  int64_t used = 0;
  auto next = [&]() {
    char c;
    if (used >= size || !in.get(c)) throw bad(attribute + " runs past the " + std::to_string(size) + " bytes it says it has");
    ++used;
    return c;
  };
  for (int channels = 0;; ++channels) {
    std::string channel;
    for (char c = next(); c != '\0'; c = next())
      if (channel.size() < 256) channel.push_back(c);
    if (channel.empty()) break;
    if (channels >= 8 || channel.size() > 255) throw bad(attribute + ": more than 8 channels or a name over 255 bytes");
    if (used + 16 > size) throw bad(attribute + " runs past the " + std::to_string(size) + " bytes it says it has");
    in.seekg(16, std::ios::cur);  // pixel type, pLinear, 3 reserved, x and y sampling
    used += 16;
  }
  if (used != size) throw bad(attribute + " says " + std::to_string(size) + " bytes; its channels take " + std::to_string(used));
}

// OpenEXR allocates an attribute's value at the size its header claims before reading it (a
// crafted attribute of an unknown type claimed 1.6 GB; found by libFuzzer). The header is walked
// here first: name, type, 32-bit size, value, until an empty name; every size must fit in what
// is left of the file. Only single-part scanline files get here (the flags are checked too).
void check_exr_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const int64_t bytes = int64_t(std::filesystem::file_size(path, ec));
  auto bad = [&](const std::string& why) { return InputError("SDM " + path + ": " + why + " (the file is damaged or not an SDM)"); };
  unsigned char head[8];
  if (!in.read(reinterpret_cast<char*>(head), 8)) throw bad("the OpenEXR header is cut short");
  if (head[5] & 0x1e) throw bad("it is a tiled, deep or multi-part OpenEXR file; an SDM is one scanline image");
  // Names end with a NUL within 32 bytes (31 characters; longer names need the long-names flag,
  // refused above). OpenEXR reads a name without its NUL on into the next field, so a file with
  // one is refused here rather than walked differently from OpenEXR (fuzzed names of 32 bytes
  // made OpenEXR allocate 1.6-1.9 GB for an attribute this walk never saw).
  auto read_name = [&](std::string& out) {
    out.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return;
      if (out.size() == 31) throw bad("the header holds a name of 32 bytes or more without the long-names flag");
      out.push_back(c);
    }
    throw bad("the header is cut short");
  };
  for (std::string name, type;;) {
    read_name(name);
    if (name.empty()) return;
    read_name(type);
    const int64_t size = read_le_i32(in, bad);
    const int64_t at = int64_t(in.tellg()), left = bytes - at;
    const std::string attribute = "the header's attribute '" + name.substr(0, 40) + "' (" + type.substr(0, 20) + ")";
    if (size < 0 || size > left)
      throw bad(attribute + " claims " + std::to_string(size) + " bytes, " + std::to_string(left) + " are left in the file");
    check_attribute_value(in, name, type, size, attribute, bad);
    in.clear();
    in.seekg(at + size);
  }
}

// The channel names of each format version: displacement, mask, vector x, y, z.
struct ChannelNames {
  const char *D, *A, *X, *Y, *Z;
};
ChannelNames channel_names(int version) {
  if (version == 1) return {"D", "A", "X", "Y", "Z"};
  return {"Y", "A", "vector.X", "vector.Y", "vector.Z"};
}

}  // namespace

SdmPrecision SdmPrecision::parse(const std::string& text) {
  if (text == "float") return {float32};
  if (text == "half") return {half16};
  int bits = 0;
  size_t used = 0;
  try {
    bits = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || used == 0 || bits < 4 || bits > 11)
    throw InputError("precision '" + text + "' is not float, half or a number of bits from 4 to 11");
  return {quantized, bits};
}

std::string SdmPrecision::name() const {
  return kind == float32 ? "float" : kind == half16 ? "half" : std::to_string(bits);
}

void write_sdm_exr(const SdmImage& im, const std::string& path, SdmPrecision precision) {
  check_size(im);
  if (precision.kind == SdmPrecision::quantized && (precision.bits < 4 || precision.bits > 11 || !im.X.empty()))
    throw std::invalid_argument("write_sdm_exr: quantised maps take 4 to 11 bits and no vector channels");
  const ChannelNames names = channel_names(kSdmFormatVersion);
  const Imf::PixelType stored = precision.kind == SdmPrecision::float32 ? Imf::FLOAT : Imf::HALF;
  const StoredD y = stored_displacement(im, precision);
  nlohmann::json layout = im.layout;
  std::string base_mesh;
  const int version = layout.contains("base_mesh") && layout["base_mesh"].contains("flat_faces") ? 4 : 3;
  if (layout.contains("base_mesh")) base_mesh = pack_base_mesh(layout.at("base_mesh")), layout.erase("base_mesh");
  // The input's vertex -> node map (10 KB of Spot's 19 KB layout) describes a mesh the map does not
  // hold; a decoded mesh has its own vertices.
  if (layout.contains("skeleton") && layout["skeleton"].contains("vertex_node")) layout["skeleton"]["vertex_node"] = nlohmann::json::array();
  write_atomically(path, [&](const std::string& tmp) {
    Imf::Header header(im.width, im.height);
    header.compression() = Imf::ZIP_COMPRESSION;  // measured against PIZ, PXR24, ZIPS, RLE: BENCHMARKS
    header.insert(kLayoutAttribute, Imf::StringAttribute(layout.dump()));
    header.insert(kVersionAttribute, Imf::IntAttribute(version));
    if (!base_mesh.empty()) header.insert(kBaseMeshAttribute, Imf::StringAttribute(base_mesh));
    if (precision.kind == SdmPrecision::quantized) {
      header.insert(kBitsAttribute, Imf::IntAttribute(precision.bits));
      header.insert(kQuantumAttribute, Imf::DoubleAttribute(y.quantum));
    }
    struct Out {
      const char* name;
      const std::vector<float>* data;
      Imf::PixelType type;
    };
    std::vector<Out> channels = {{names.D, &y.y, stored}, {names.A, &y.mask, Imf::HALF}};
    if (!im.X.empty()) channels.insert(channels.end(), {{names.X, &im.X, stored}, {names.Y, &im.Y, stored}, {names.Z, &im.Z, stored}});
    Imf::FrameBuffer fb;
    std::vector<std::vector<half>> halves;  // the frame buffer's type must be the file's
    halves.reserve(channels.size());
    for (const Out& c : channels) {
      header.channels().insert(c.name, Imf::Channel(c.type));
      if (c.type == Imf::FLOAT) {
        fb.insert(c.name, Imf::Slice(Imf::FLOAT, (char*)c.data->data(), sizeof(float), sizeof(float) * im.width));
        continue;
      }
      halves.emplace_back(c.data->begin(), c.data->end());
      fb.insert(c.name, Imf::Slice(Imf::HALF, (char*)halves.back().data(), sizeof(half), sizeof(half) * im.width));
    }
    try {
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(im.height);
    } catch (const std::exception& e) {
      throw std::runtime_error("cannot write " + path + ": " + e.what());
    }
  });
}

SdmImage as_stored(SdmImage im, SdmPrecision precision) {
  StoredD y = stored_displacement(im, precision);
  for (size_t i = 0; i < im.D.size(); ++i) {
    if (precision.kind == SdmPrecision::quantized)
      im.D[i] = quantised_residual(y.y[i], precision.bits, y.quantum);
    else
      im.D[i] = precision.kind == SdmPrecision::half16 ? float(half(y.y[i])) : y.y[i];
  }
  im.A = std::move(y.mask);
  if (precision.kind != SdmPrecision::quantized) mark_left_out(im);
  im.residual = precision.kind == SdmPrecision::quantized;
  if (im.layout.contains("base_mesh")) im.layout["base_mesh"] = unpack_base_mesh(pack_base_mesh(im.layout.at("base_mesh")));
  im.foot.clear();
  return im;
}

SdmImage read_sdm_exr(const std::string& path) {
  check_input_file(path, "SDM");  // missing, a folder, a named pipe or a device: refused before anything opens it
  if (!Imf::isOpenExrFile(path.c_str()))
    throw InputError("cannot read SDM " + path + ": not an OpenEXR file (write one with 'sdm encode')");
  check_exr_header(path);
  SdmImage im;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const auto* version = h.findTypedAttribute<Imf::IntAttribute>(kVersionAttribute);
    const auto* layout = h.findTypedAttribute<Imf::StringAttribute>(kLayoutAttribute);
    if (!layout || !version)
      throw InputError("SDM " + path + " is an OpenEXR image without the sdm layout header (attribute '" +
                       std::string(kLayoutAttribute) + "'): it was not written by 'sdm encode'");
    if (version->value() < 1 || version->value() > kSdmFormatVersion)
      throw InputError("SDM " + path + " has format version " + std::to_string(version->value()) +
                       ", this sdm reads versions 1 to " + std::to_string(kSdmFormatVersion) + ": re-encode it with this sdm");
    const ChannelNames names = channel_names(version->value());
    im.layout = nlohmann::json::parse(layout->value(), nullptr, false);
    if (im.layout.is_discarded() || !im.layout.is_object())
      throw InputError("SDM " + path + " has an invalid layout header: not a JSON object");
    if (const auto* base = h.findTypedAttribute<Imf::StringAttribute>(kBaseMeshAttribute))
      im.layout["base_mesh"] = unpack_base_mesh(base->value());
    const auto* bits = h.findTypedAttribute<Imf::IntAttribute>(kBitsAttribute);
    const auto* quantum = h.findTypedAttribute<Imf::DoubleAttribute>(kQuantumAttribute);
    if (bool(bits) != bool(quantum) || (bits && (bits->value() < 4 || bits->value() > 11 || !std::isfinite(quantum->value()) ||
                                                 !(quantum->value() > 0))))
      throw InputError("SDM " + path + " has an invalid quantisation (attributes " + kBitsAttribute + " and " + kQuantumAttribute +
                       ": 4 to 11 bits and a positive step)");
    const Imath::Box2i dw = h.dataWindow();
    int channels = 0;
    for (auto c = h.channels().begin(); c != h.channels().end(); ++c) ++channels;
    check_window(path, dw, channels);
    im.width = dw.max.x + 1;
    im.height = dw.max.y + 1;
    const size_t n = size_t(im.width) * size_t(im.height);
    for (const char* c : {names.D, names.A})
      if (!h.channels().findChannel(c))
        throw InputError("SDM " + path + " lacks channel '" + std::string(c) + "' (format version " + std::to_string(version->value()) +
                         " needs " + names.D + " and " + names.A + ")");
    const bool vec = h.channels().findChannel(names.X) && h.channels().findChannel(names.Y) && h.channels().findChannel(names.Z);
    Imf::FrameBuffer fb;
    auto slice = [&](const char* name, std::vector<float>& data) {
      data.assign(n, 0.0f);
      char* base = (char*)(data.data() - dw.min.x - size_t(dw.min.y) * im.width);
      fb.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * im.width));
    };
    slice(names.D, im.D);
    slice(names.A, im.A);
    if (vec) slice(names.X, im.X), slice(names.Y, im.Y), slice(names.Z, im.Z);
    file.setFrameBuffer(fb);
    if (!file.isComplete())
      throw InputError("SDM " + path + " is truncated: some pixel data is missing (copy the file again)");
    file.readPixels(dw.min.y, dw.max.y);
    if (bits) {
      for (float& d : im.D) d = quantised_residual(d, bits->value(), quantum->value());
      im.residual = true;
    } else if (version->value() >= 3) {
      mark_left_out(im);
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read SDM " + path + ": " + e.what() + " (the file is damaged or truncated)");
  }
  return im;
}

}  // namespace sdm
