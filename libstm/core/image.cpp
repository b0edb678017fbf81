#include "libstm/core/image.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"

#include <png.h>
#include <stb_image.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sdm {

double decode_image_bytes(int width, int height, size_t file_bytes) { return double(file_bytes) + 12.0 * double(width) * double(height); }

namespace {

// Refuses a PNG chunk that runs past the bytes: stb sizes its buffer by a chunk's stated length
// before reading it (a 2.4 KB image said 2 GB).
void check_png_chunks(const unsigned char* bytes, size_t size, const std::string& what) {
  for (size_t at = 8;;) {
    if (size - at < 12) throw InputError(what + ": the PNG is cut short (no IEND chunk)");
    const size_t length = size_t(bytes[at]) << 24 | size_t(bytes[at + 1]) << 16 | size_t(bytes[at + 2]) << 8 | bytes[at + 3];
    if (length > size - at - 12) throw InputError(what + ": a chunk of the PNG runs past the file's bytes");
    if (std::memcmp(bytes + at + 4, "IEND", 4) == 0) return;
    at += 12 + length;
  }
}

// Refuses a header that claims more pixels than kMaxImageSide a side or than `size` bytes of file
// can hold: deflate's 1032:1 on one bit a pixel, JPEG a bit per 8x8 block.
void check_claimed_size(double w, double h, size_t size, bool jpeg, const std::string& what) {
  const double per_byte = jpeg ? 1024.0 : 8256.0;
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide || w * h > per_byte * double(size) + double(1 << 20))
    throw InputError(what + ": its header claims " + std::to_string(long(w)) + " x " + std::to_string(long(h)) + " pixels in " +
                     std::to_string(size) + " bytes (at most " + std::to_string(kMaxImageSide) + " a side, and what the bytes can hold)");
}

uint32_t big_endian32(const unsigned char* b) { return uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 | b[3]; }

}  // namespace

Image decode_image(const unsigned char* bytes, size_t size, const std::string& what, const ImageBudget& budget) {
  const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
  const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
  if (png) check_png_chunks(bytes, size, what);
  // The IHDR's size first: stb_image's own limits would refuse a huge one as "not an image".
  if (png && size >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) check_claimed_size(big_endian32(bytes + 16), big_endian32(bytes + 20), size, false, what);
  int w = 0, h = 0, c = 0;
  if (size == 0 || size > size_t(INT_MAX) || !stbi_info_from_memory(bytes, int(size), &w, &h, &c)) {
    const char* why = stbi_failure_reason();
    throw InputError(what + ": not an image this reader takes (" + (why ? why : "unknown format") + "; PNG or JPEG)");
  }
  check_claimed_size(w, h, size, jpeg, what);
  if (budget) budget(decode_image_bytes(w, h, size), w, h);
  // Forcing 4 channels gives every caller the same RGBA8 layout whatever the file stores.
  stbi_uc* data = stbi_load_from_memory(bytes, int(size), &w, &h, &c, 4);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw InputError(what + ": the image cannot be decoded (" + (why ? why : "unknown error") + ")");
  }
  Image img(w, h, 4);
  std::memcpy(img.pixels.data(), data, img.pixels.size());
  stbi_image_free(data);
  return img;
}

Image read_png(const std::string& path, const ImageBudget& budget) {
  const std::string bytes = read_input_file(path, "image", kMaxImageFileBytes);
  return decode_image(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), "image " + path, budget);
}

namespace {

// PNG bytes of `image` through libpng: zlib level 3 and the Sub and Up row filters. Measured on a
// transfer's 1024^2 RGBA atlas and Spot's texture against stb_image_write (level 8, every filter
// tried per row): 0.94 MB and 93 KB against 1.24 MB and 109 KB, 4-5x faster (a 1024^2 atlas
// 440 -> 115-150 ms, the preview 125 -> 20-23 ms on the 2-core Xeon VM).
std::string encode_png(const Image& image, const std::string& path) {
  static const int kColorType[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGBA};
  std::string bytes;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("cannot encode PNG '" + path + "': out of memory");
  }
  // libpng reports failures by longjmp; nothing with a destructor is created past this point.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("cannot encode PNG '" + path + "'");
  }
  auto append = [](png_structp p, png_bytep data, png_size_t n) {
    static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<const char*>(data), n);
  };
  png_set_write_fn(png, &bytes, append, [](png_structp) {});
  png_set_compression_level(png, 3);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB | PNG_FILTER_UP);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, kColorType[image.channels], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const size_t stride = size_t(image.width) * size_t(image.channels);
  for (int y = 0; y < image.height; ++y) png_write_row(png, image.pixels.data() + size_t(y) * stride);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return bytes;
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != size_t(image.width) * image.height * image.channels)
    throw std::runtime_error("write_png: inconsistent image for '" + path + "'");
  if (image.width > kMaxImageSide || image.height > kMaxImageSide)
    throw InputError("cannot write PNG " + path + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " pixels, more than " + std::to_string(kMaxImageSide) + " a side");
  write_atomically(path, [&](const std::string& tmp) {
    const std::string bytes = encode_png(image, path);
    write_bytes_checked(tmp, bytes.data(), bytes.size(), path);
  });
}

double psnr(const Image& a, const Image& b, const std::vector<uint8_t>* mask) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw InputError("psnr: images differ in size or channels (" + std::to_string(a.width) + "x" +
                     std::to_string(a.height) + "x" + std::to_string(a.channels) + " vs " + std::to_string(b.width) +
                     "x" + std::to_string(b.height) + "x" + std::to_string(b.channels) + ")");
  const size_t n = size_t(a.width) * a.height;
  if (mask && mask->size() != n) throw InputError("psnr: mask size does not match the images");
  const int c = std::min(a.channels, 3);
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (mask && !(*mask)[i]) continue;
    ++count;
    for (int k = 0; k < c; ++k) {
      const double d = double(a.pixels[i * a.channels + k]) - double(b.pixels[i * b.channels + k]);
      sum += d * d;
    }
  }
  if (count == 0) throw InputError("psnr: the mask selects no pixel");
  if (sum == 0) return std::numeric_limits<double>::infinity();
  const double mse = sum / double(count * c);
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

std::vector<uint8_t> mask_union(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size()) throw InputError("mask_union: masks differ in size");
  std::vector<uint8_t> u(a.size());
  for (size_t i = 0; i < a.size(); ++i) u[i] = (a[i] || b[i]) ? 255 : 0;
  return u;
}

Image contact_sheet(const std::vector<Image>& images, int columns, int gap, const uint8_t background[4]) {
  static const uint8_t white[4] = {255, 255, 255, 255};
  if (!background) background = white;
  if (images.empty()) return Image();
  columns = std::max(1, std::min(columns, int(images.size())));
  const int rows = (int(images.size()) + columns - 1) / columns;
  int cw = 0, ch = 0;
  for (const auto& im : images) cw = std::max(cw, im.width), ch = std::max(ch, im.height);
  gap = std::max(0, gap);
  Image out(columns * cw + (columns - 1) * gap, rows * ch + (rows - 1) * gap, 4);
  for (size_t i = 0; i < out.pixels.size(); i += 4) std::copy(background, background + 4, &out.pixels[i]);
  for (size_t i = 0; i < images.size(); ++i) {
    const Image& im = images[i];
    const int x0 = int(i) % columns * (cw + gap), y0 = int(i) / columns * (ch + gap);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        const uint8_t* s = im.at(x, y);
        uint8_t* d = out.at(x0 + x, y0 + y);
        // Grey, grey+alpha, RGB and RGBA all become RGBA.
        if (im.channels >= 3) {
          d[0] = s[0], d[1] = s[1], d[2] = s[2];
        } else {
          d[0] = d[1] = d[2] = s[0];
        }
        d[3] = (im.channels == 4) ? s[3] : (im.channels == 2 ? s[1] : 255);
      }
  }
  return out;
}

Image side_by_side(const std::vector<Image>& images, int gap, const uint8_t background[4]) {
  return contact_sheet(images, int(std::max<size_t>(1, images.size())), gap, background);
}

}  // namespace sdm
