#pragma once
/// Repair of a triangle soup before validation: the defects every mesh tool mends without asking
/// (DECISIONS 1, "Mesh repair"). Each step is a topological decision made on the soup, never a move
/// of a point, so the repaired surface is the input surface:
///  1. coincident vertices welded: exactly equal coordinates first (a soup OBJ, an exporter's split
///     normals), then boundary vertices within a tolerance relative to the model's diagonal (a
///     crack left by rounding);
///  2. faces that lost a corner to the weld (a repeated vertex) and duplicated faces (the same three
///     vertices, either orientation) dropped, the first of each duplicate kept;
///  3. every edge's faces glued in pairs: two faces always; more than two paired around the edge by
///     angle, each back-facing face with the next front-facing one (the pairs that enclose a
///     volume between them), the faces left over peeled off into a sheet of their own;
///  4. every part oriented consistently (a breadth-first walk over the glued pairs, the majority's
///     direction kept; an edge that cannot be made consistent, in a one-sided part, is cut);
///  5. every vertex split into one copy per fan of faces glued around it (non-manifold vertices,
///     and the ends of the edges cut in 3 and 4);
///  6. points no face uses dropped.
/// Outward orientation (the sign of each part's volume) stays validation's (orient_outward).
#include "libstm/mesh/edge_table.h"
#include "libstm/mesh/mesh.h"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

/// The default of RepairOptions::weld_tolerance: a millionth of the diagonal, far below any
/// edge of a mesh the pipeline can map (the atlas's texel at 16384 is 6e-5 of it).
constexpr double kDefaultWeldTolerance = 1e-6;

struct RepairOptions {
  double weld_tolerance = kDefaultWeldTolerance;  ///< boundary vertices closer than this fraction of the diagonal are welded; 0: exact only
};

/// One kind of repair, with how many elements it touched and one example.
struct RepairStep {
  std::string kind;     ///< e.g. "coincident vertices welded (exact)"
  long count = 0;
  std::string example;  ///< e.g. "vertex 12 onto vertex 3"
};

struct RepairReport {
  std::vector<RepairStep> steps;   ///< only the steps that changed something, in the order above
  std::vector<int> face_source;    ///< per output triangle, the input triangle it is
  std::vector<int> point_source;   ///< per output point, the input point it is a copy of
  double weld_distance = 0;        ///< the tolerance in model units
  bool changed() const { return !steps.empty(); }
  long count(const std::string& kind) const;  ///< the count of a step, 0 when it did not happen
  long faces_dropped() const;                 ///< input triangles that are not in the output
  nlohmann::json to_json() const;             ///< {"changed", "weld_distance", "steps": [{kind, count, example}]}
};

/// What validation already knows of the soup (scan_topology), so that repair runs only the steps
/// its findings call for, and splits only the vertices it names (DECISIONS 1, "Mesh repair"). The
/// default, no hints, runs every step everywhere.
struct RepairHints {
  const EdgeTable* table = nullptr;            ///< the soup's edge table, every face in it; null: made anew
  bool borders = true;                         ///< some edge has one face: welds may close it
  bool crowded_or_inconsistent = true;         ///< some edge has more than two faces, or two that disagree
  bool duplicated = true;                      ///< validation found duplicated faces
  const std::vector<int>* pinched = nullptr;   ///< the non-manifold vertices; null: every vertex looked at
};

/// Repairs `soup` in place (points, triangles, uv and colours alike) and says what it did.
/// Soups with non-finite coordinates or out-of-range corners are left as they are, for validation
/// to name. Linear in the soup's size but for two sorts (the points by coordinates, each edge's
/// faces by angle).
/// With `hints`, the result is the same as without them whenever the hints are true of the soup.
RepairReport repair_soup(MeshSoup& soup, const RepairOptions& options = {}, const RepairHints& hints = {});

}  // namespace sdm
