#pragma once
/// The limits every reader and command enforces, in one place, so that a companion file (layout,
/// skeleton, SDM header) cannot ask for more than the command line would accept (DECISIONS 1, "Hostile input").
#include <cfloat>
#include <cstdint>

namespace sdm {

/// Largest atlas, SDM image or rendered image side in texels/pixels (--size, --width, --height).
constexpr int kMaxImageSide = 16384;

/// Largest coordinate magnitude accepted in a mesh or skeleton: mesh readers parse single
/// precision, so a coordinate beyond the float range cannot be represented faithfully.
constexpr double kMaxCoordinate = double(FLT_MAX);

/// Largest files the readers take, checked on the file's size before its first byte is read
/// (input_file.h): a mesh or a glTF buffer (read whole; 8 GB is a mesh of some 200 million
/// triangles), a companion JSON (layout, skeleton: parsed into a tree of about ten times its text),
/// a material library (MTL) and an image (stb_image decodes from memory with an int length).
constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t(8) << 30;
constexpr std::uint64_t kMaxJsonFileBytes = std::uint64_t(512) << 20;
constexpr std::uint64_t kMaxMaterialFileBytes = std::uint64_t(64) << 20;
constexpr std::uint64_t kMaxImageFileBytes = (std::uint64_t(1) << 31) - 1;

/// Bytes a companion JSON holds in memory per byte of its text while it is parsed: the text and
/// nlohmann::json's tree, with a margin over the worst case (a file of empty objects; numbers in
/// docs/BENCHMARKS.md), so a reader asks the memory budget for 32x the file's size before reading it.
constexpr double kJsonBytesPerFileByte = 32;

}  // namespace sdm
