#pragma once
/// Small extra parts (DECISIONS 5, "Small separate parts"): a closed part far smaller than the model it comes
/// with (a blob of six vertices inside a scanned body's pelvis, a floating speck) gets its own
/// skeleton component, and the skeletons' branchings then differ ("connected parts 1 vs 2"), which
/// refused the whole pair. Such parts are left out of the matching: the correspondence is computed
/// between the main parts, and a left-out target vertex takes the source point of the main part's
/// vertex nearest it.
#include "libstm/core/progress.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"

#include <string>
#include <vector>

namespace sdm {

/// A part is small when its area is under area_fraction of the largest part's and its bounding box's
/// diagonal under size_fraction of the whole mesh's.
struct SmallPartOptions {
  double area_fraction = 0.01, size_fraction = 0.2;
};

struct MainParts {
  Mesh mesh;                          // the input without its small parts (uv kept); the input when none
  std::vector<int> vertex_of;         // per vertex of `mesh`, its vertex in the input
  std::vector<int> face_of;           // per face of `mesh`, its face in the input
  std::vector<std::string> left_out;  // per part left out, one line: vertices, area share, place
  bool reduced() const { return !left_out.empty(); }
};

/// The mesh without its small parts (SmallPartOptions); every vertex and face in the order of the
/// input. The largest part always stays.
MainParts without_small_parts(const Mesh& mesh, const SmallPartOptions& options = {});

/// without_small_parts for a command's input: each part left out named on `progress` as a warning
/// (`what` names the model, e.g. its path); with `strict` an InputError naming the first instead.
MainParts main_parts(const Mesh& mesh, const std::string& what, bool strict, const Progress& progress);

/// A correspondence onto `source.mesh` (per target vertex, a face of it) as points of the input
/// source: faces renumbered, barycentric weights in the input face's corner order.
std::vector<SourcePoint> onto_input_source(const MainParts& source, const Mesh& input_source, std::vector<SourcePoint> points);

/// A correspondence of `target.mesh`'s vertices extended to every vertex of `input_target`: a vertex
/// of a left-out part takes the source point of the nearest kept vertex (straight-line distance).
std::vector<SourcePoint> onto_input_target(const MainParts& target, const Mesh& input_target, const std::vector<SourcePoint>& points);

}  // namespace sdm
