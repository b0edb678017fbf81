#pragma once
/// Fast readers for the plain majority of text meshes (in place of OpenMesh's OBJ reader and a
/// double-precision rescan of the coordinates; docs/BENCHMARKS.md). They parse with
/// std::from_chars over the whole file in memory and take only what the pipeline reads from such
/// files: positions and polygons. Anything else (OBJ uv, materials, vertex colours, a fourth
/// coordinate, lines or points; OFF variants with colours or normals, comments inside the counts;
/// indices out of range; NaN or infinite coordinates; a count the file does not hold) makes them
/// return false, and the caller reads the file through OpenMesh as before, with its checks and
/// messages unchanged.
#include <Eigen/Dense>

#include <string>
#include <vector>

namespace sdm {

/// OBJ with `v x y z` and `f a b c ...` lines (corner tokens `a`, `a/t`, `a//n`, `a/t/n`; negative
/// indices count back from the last vertex), comments, and `vn`, `o`, `g`, `s` lines (ignored).
bool read_plain_obj(const std::string& text, std::vector<Eigen::Vector3d>& points, std::vector<std::vector<int>>& polygons);

/// ASCII OFF: `OFF`, the counts, one `x y z` line per vertex, one `n i1 ... in` line per face;
/// `#` comments and blank lines anywhere.
bool read_plain_off(const std::string& text, std::vector<Eigen::Vector3d>& points, std::vector<std::vector<int>>& polygons);

}  // namespace sdm
