#pragma once
/// Validation shared by every command: what is wrong with an input mesh, how often, one example
/// of each problem, and whether the pipeline can take it. Works on the raw soup, before topology
/// is built, so that problems the halfedge structure cannot even represent are counted too.
#include "libstm/mesh/edge_table.h"
#include "libstm/mesh/mesh.h"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

struct Finding {
  std::string id;       ///< short identifier, e.g. "non_manifold_edges" (what --strict and programs match)
  std::string kind;     ///< what it is, in words, e.g. "non-manifold edges"
  long count = 0;
  std::string example;  ///< one offending element, e.g. "edge (12, 40) used by 3 faces"
  bool fatal = false;   ///< the pipeline refuses the mesh
  std::string fix;      ///< how to fix it
};

struct MeshReport {
  long vertices = 0, faces = 0;        ///< as read (faces after fan-triangulation)
  long edges = 0;
  int parts = 0;                       ///< edge-connected components of faces
  std::vector<int> genus_per_part;     ///< of the closed surface each part is with its holes capped
  std::vector<int> boundary_loops_per_part;  ///< 0 for a closed part
  std::vector<int> faces_per_part;
  int boundary_loops = 0;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  std::vector<int> face_part;          ///< part of each triangle
  std::vector<double> part_volume;     ///< signed, holes capped; empty when some face is in no part
  std::vector<Finding> findings;
  double speck_min_part = 0;           ///< the --min-part that drops every flat part and keeps the solid ones, or 0

  bool usable() const;                          ///< no fatal finding
  std::string refusal(const std::string& path) const;  ///< the message for a refused input
  nlohmann::json to_json() const;
};

/// Counts: NaN/Inf coordinates, invalid faces (repeated or out-of-range vertex), duplicated faces,
/// boundary edges and loops, non-manifold edges and vertices, inconsistent orientation, degenerate
/// (zero-area) faces, isolated vertices; connected parts and genus per part.
/// `table`, when given, receives the soup's edge table (edge_table.h) when every face has valid
/// corners (else it is left empty), for build_mesh to link the halfedges from.
MeshReport validate_mesh(const MeshSoup& soup, EdgeTable* table = nullptr);

/// The first half of validate_mesh: coordinates, face corners, edges (borders, crowded edges,
/// orientation) and vertex fans, everything repair_soup mends; enough to tell whether repair is
/// needed before the rest (duplicates, degenerate faces, parts, genus, volumes) is measured.
struct TopologyScan {
  MeshReport report;                     ///< the findings so far (counts, box, edges; no parts yet)
  EdgeTable table;                       ///< of the faces with valid corners
  std::vector<char> face_ok;             ///< per face: its corners are in range and distinct
  std::vector<int> nonmanifold_vertices; ///< the vertices where more than one fan of faces meets
  long bad_coordinates = 0;              ///< points with NaN or infinite coordinates
  bool edges_not_closed_2_manifold = false;  ///< some edge is a border, crowded, or between inconsistently oriented faces
  size_t findings_before_duplicates = 0;     ///< where finish_validation puts the duplicated faces' finding
  /// Whether repair_may_help will say yes whatever the rest finds (a fatal finding or a border).
  bool repair_needed() const;
};
TopologyScan scan_topology(const MeshSoup& soup);

/// The rest of validate_mesh on the scan of the same soup: validate_mesh(soup, table) equals
/// finish_validation(soup, scan_topology(soup), table).
MeshReport finish_validation(const MeshSoup& soup, TopologyScan&& scan, EdgeTable* table = nullptr);

/// Flips every closed part whose signed volume is negative, so that all normals point outwards.
/// Adds an informational finding when it does. Requires a usable report of the same soup. Returns
/// the number of faces flipped.
long orient_outward(MeshSoup& soup, MeshReport& report);

}  // namespace sdm
