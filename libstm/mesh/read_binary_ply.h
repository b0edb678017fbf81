#pragma once
/// A fast reader for the plain majority of binary PLY meshes (OpenMesh's PLY reader reads a value
/// at a time through a stream; docs/BENCHMARKS.md). It walks the file in
/// memory with the offsets the header gives and takes what the pipeline reads from such files:
/// positions (float or double, kept in double where the file has it; OpenMesh's reader rounds to
/// float) and, when the file has them as bytes, vertex colours. ASCII PLY of the same shape is read
/// here too, a line per element, every integer type taken for the corner list (OpenMesh's ASCII
/// reader refused a uint, uint32, ushort or short count or index). Anything else (elements
/// other than vertex and face, face properties besides the corner list, colours in another type,
/// a file shorter than its counts, a corner out of range) makes it return false, and the caller
/// reads the file through check_mesh_file and OpenMesh as before, with their checks and messages.
#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace sdm {

struct BinaryPly {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;  ///< the faces, when every one is a triangle
  std::vector<std::vector<int>> polygons;     ///< else every face here (triangles empty), in file order
  std::vector<Eigen::Vector3f> colors;        ///< per point, RGB in [0, 1]; empty when the file has none
};

/// Parses `bytes`, a whole PLY file (binary_little_endian or binary_big_endian 1.0). Returns
/// false, with `out` unspecified, for anything the reader does not take (see above).
bool read_binary_ply(const std::string& bytes, BinaryPly& out);

}  // namespace sdm
