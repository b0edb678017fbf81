#pragma once
/// The one road from a file to the pipeline, every command's (DECISIONS 1, "Mesh repair"): read the soup,
/// drop specks (--min-part), validate; when validation finds what repair mends (welds, duplicated
/// or collapsed faces, non-manifold edges and vertices, inconsistent orientation), repair and
/// validate again; orient every part outward; build the halfedge mesh.
#include "libstm/mesh/edge_table.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/repair_soup.h"
#include "libstm/mesh/validate_mesh.h"

#include <string>
#include <vector>

namespace sdm {

struct LoadOptions {
  double min_part = 0;   ///< drop parts smaller than this fraction of the diagonal first (drop_small_parts.h); 0: none
  bool repair = true;    ///< false: refuse what validation refuses, as it is in the file (`--no-repair`, `--strict`)
  bool report_as_read = false;  ///< validate the file as read in full before repairing it (`info`); else only what repair needs (scan_topology)
  RepairOptions repair_options;
};

/// What happened on the way: the specks dropped, the repairs, and the validation the pipeline
/// went on with (of the repaired soup when it was repaired).
struct LoadReport {
  std::vector<std::string> dropped;  ///< one line per part --min-part dropped (flat fragments: in `repair`)
  RepairReport repair;               ///< empty steps when nothing was repaired (or repair was off)
  MeshReport validation;
  double repair_seconds = 0;         ///< the time repair_soup took (0 when it did not run)
  MeshReport as_read;                ///< the validation of the soup as read (before repair; its topology alone, without parts, unless report_as_read)
};

/// Whether repair_soup would change what validation of this report refuses or reports: fatal
/// findings, holes (a crack may weld shut), duplicated faces.
bool repair_may_help(const MeshReport& report);

/// What a scan of the soup (scan_topology) tells repair_soup: its table, whether it has borders,
/// crowded or inconsistent edges, and its non-manifold vertices (pointers into `scan`).
RepairHints repair_hints(const TopologyScan& scan);

/// The road above up to validation, on `soup` (modified in place: specks dropped, repaired); never
/// throws for the soup's defects: the report's `validation` says whether the pipeline can take it.
LoadReport repair_and_validate(MeshSoup& soup, const LoadOptions& options, EdgeTable* table = nullptr);

/// Runs the road above on `soup` (modified in place: repaired and oriented) and returns its report.
/// \throw InputError with the validation's refusal, naming `what`, when the result is still
/// unusable. `table`, when given, receives the final soup's edge table (or an empty one).
LoadReport prepare_soup(MeshSoup& soup, const std::string& what, const LoadOptions& options, EdgeTable* table = nullptr);

/// A mesh as read from a file, with what came with it.
struct LoadedMesh {
  Mesh mesh;
  std::string texture;                 ///< the material's texture path, or empty
  std::vector<Eigen::Vector3f> colors; ///< per vertex of `mesh` (RGB in [0, 1]) when the file has colours
  Image texture_image;                 ///< the texture a glTF embeds, or empty
  LoadReport report;
};

/// Reads `path` (read_mesh_soup), prepares it (prepare_soup: repaired when options.repair, its
/// specks under options.min_part dropped) and builds the mesh; `colors` in the built mesh's vertex
/// order.
/// \throw InputError when the file is missing, empty, unreadable or of an unknown format, or with
/// the validation's refusal when the mesh cannot go through the pipeline even repaired (NaN, empty,
/// flat).
LoadedMesh load_mesh(const std::string& path, const LoadOptions& options = {});

/// One line per repair step for stderr ("repaired: 12 coincident vertices welded (exact), e.g. ...").
std::vector<std::string> repair_lines(const RepairReport& report);

}  // namespace sdm
