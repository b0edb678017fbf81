#pragma once
/// 8-bit and float images, PNG in/out, and image comparison (PSNR) for render-based checks.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace sdm {

/// 8 bits per channel, rows stored top to bottom, channels interleaved (4 = RGBA).
struct Image {
  int width = 0, height = 0, channels = 4;
  std::vector<uint8_t> pixels;  ///< width * height * channels

  Image() = default;
  Image(int w, int h, int c = 4, uint8_t fill = 0) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill) {}
  uint8_t* at(int x, int y) { return &pixels[(size_t(y) * width + x) * channels]; }
  const uint8_t* at(int x, int y) const { return &pixels[(size_t(y) * width + x) * channels]; }
};

/// 32-bit float per channel, same layout as Image; used for float render targets (positions,
/// displacement) read back from the GPU.
struct FloatImage {
  int width = 0, height = 0, channels = 4;
  std::vector<float> pixels;

  FloatImage() = default;
  FloatImage(int w, int h, int c = 4, float fill = 0.f) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill) {}
  float* at(int x, int y) { return &pixels[(size_t(y) * width + x) * channels]; }
  const float* at(int x, int y) const { return &pixels[(size_t(y) * width + x) * channels]; }
};

/// Called with the bytes an image's decoding will take (decode_image_bytes) once its header is read
/// and before any pixel is decoded; throws to refuse (the commands check their --max-memory).
using ImageBudget = std::function<void(double bytes, int width, int height)>;

/// Bytes decoding a width x height image of `file_bytes` takes at its peak: the file, stb's
/// decoded pixels (up to 16-bit RGBA, 8 bytes a pixel) and the RGBA8 copy (4).
double decode_image_bytes(int width, int height, size_t file_bytes);

/// Decodes an image file's bytes (PNG, JPEG or another format stb_image reads; grey, grey+alpha,
/// RGB, RGBA; 8 or 16 bit) to RGBA8, after its header: at most kMaxImageSide a side, no more pixels
/// than its bytes can hold (deflate's 1032:1 at one bit a pixel for PNG and the others, a bit for
/// each 8x8 block for JPEG), every PNG chunk within the bytes, and `budget` (when given) asked
/// before decoding. Throws InputError starting with `what` ("texture t.png") naming the problem.
Image decode_image(const unsigned char* bytes, size_t size, const std::string& what, const ImageBudget& budget = {});

/// Reads an image file (read_input_file: a regular file, within kMaxImageFileBytes) through
/// decode_image, so callers see one layout.
/// \throw InputError naming the file when it is missing,
/// not a regular file, not a readable image, or refused by the checks or the budget.
Image read_png(const std::string& path, const ImageBudget& budget = {});

/// Writes 1 to 4 channels as PNG, atomically (temporary name, then rename).
/// \throw std::runtime_error when the image is inconsistent or the file cannot be written.
void write_png(const Image& image, const std::string& path);

/// Peak signal-to-noise ratio in dB over the colour channels (the first min(channels, 3)),
/// counting only pixels where `mask` (width * height, nonzero = counted) is set, or all pixels
/// when mask is null. Identical images give +infinity.
/// \throw InputError when the sizes or
/// channel counts differ or the mask selects no pixel.
double psnr(const Image& a, const Image& b, const std::vector<uint8_t>* mask = nullptr);

/// Pixels set in either mask (both width * height): the region to compare two renders of the same
/// shape, so that a part drawn by only one of them counts as an error.
std::vector<uint8_t> mask_union(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);

/// Lays images out in a grid of `columns` columns (row-major, top-left first) separated by `gap`
/// pixels of `background` (RGBA); cells are as large as the largest image. The result is RGBA.
Image contact_sheet(const std::vector<Image>& images, int columns, int gap = 8,
                    const uint8_t background[4] = nullptr);

/// One row: contact_sheet with as many columns as images.
Image side_by_side(const std::vector<Image>& images, int gap = 8, const uint8_t background[4] = nullptr);

}  // namespace sdm
