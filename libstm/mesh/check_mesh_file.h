#pragma once
/// Reads a mesh file's header and text before any library reader sees it, and refuses what would
/// make a reader run away, abort or report the wrong problem (DECISIONS 1, "Hostile input"): OpenMesh's readers trust
/// the counts in a header (an OFF saying -5 or 2e9 vertices reserves or loops without end), assert
/// on an OBJ corner without a vertex index (`f /1 /2 /3` aborts the process), parse coordinates in
/// single precision (a coordinate beyond the float range drops its line) and merge STL corners by
/// position (a NaN becomes "non-manifold"). Reads the text once; keeps nothing but counters.
#include <cstdint>
#include <string>

namespace sdm {

/// `text` is the whole file `path` (its UTF-8 byte-order mark, if any, removed), `ext` the lower-case
/// extension with its dot (".obj", ".off", ".ply", ".stl"). Throws InputError naming the file, the line and the problem:
///  - OFF and PLY: negative or non-integer counts; counts more than the file's size can hold (at
///    least 6 bytes per ASCII OFF vertex, 2 per face; PLY by its property types); an ASCII file that
///    ends before the announced elements ("truncated at line N"); OFF face lines whose corner count
///    or indices are not integers;
///  - OBJ: a face corner without a vertex index, a zero or out-of-range vertex or texture index, a
///    vertex line with fewer than three numbers;
///  - STL: a binary file whose size disagrees with its triangle count and that is not ASCII STL;
///  - all text formats and binary STL: NaN or infinite coordinates (counted, with the first one's
///    line or triangle), and coordinates beyond the single-precision range (+-3.4e38).
/// Formats it does not know in detail (binary OFF, nOFF, 4OFF) pass through unchecked.
void check_mesh_file(const std::string& path, const std::string& text, const std::string& ext);

/// The extension of `path`, dot included, lower-cased: how readers and writers pick a format.
std::string lower_extension(const std::string& path);

}  // namespace sdm
