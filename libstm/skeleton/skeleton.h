#pragma once
/// A curve skeleton: nodes, edges, and for every vertex of the mesh it came from, the node that
/// vertex collapsed into (the paper's one-to-many map between skeleton and surface).
#include "libstm/core/input_file.h"

#include <Eigen/Dense>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sdm {

struct Skeleton {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> vertex_node;  ///< size = mesh vertices; every node owns at least one vertex

  std::vector<std::vector<int>> adjacency() const;  ///< node -> neighbouring nodes
  std::vector<int> degrees() const;
  int components() const;          ///< connected parts of the graph
  int cycles() const;              ///< independent cycles: edges - nodes + components
  int branch_nodes() const;        ///< degree >= 3
  int end_nodes() const;           ///< degree == 1
};

/// JSON form: {"format": "sdm-skeleton", "version": 1, "nodes": [[x,y,z]...], "edges": [[a,b]...],
/// "vertex_node": [...]}. Doubles are written with round-trip precision. A pose's fields
/// (posed_skeleton.h) are read by posed_skeleton_from_json; this reader skips them.
nlohmann::json skeleton_to_json(const Skeleton& s);
/// \throw InputError naming the problem when the JSON is not a valid skeleton.
Skeleton skeleton_from_json(const nlohmann::json& j);
/// \throw InputError when a node is not finite or lies beyond kMaxCoordinate (limits.h), or an edge
/// joins a node to itself or two coincident nodes (a zero-length segment has no axis). The readers
/// call it; so does anything that takes node positions from outside.
void check_skeleton_geometry(const Skeleton& s);

/// Keeps the map of vertices 0..vertices-1 only (a skeleton extracted from a mesh with vertices added
/// after the input's, e.g. hole patches) and merges away the nodes left without a vertex: an end
/// node is removed with its edge (repeatedly, so a branch inside a patch goes), a node of degree 2
/// is replaced by an edge between its neighbours, a junction is merged into its nearest neighbour.
/// Returns the number of nodes removed.
int restrict_to_vertices(Skeleton& s, int vertices);

void write_skeleton_json(const Skeleton& s, const std::string& path);
/// Reads a skeleton written by write_skeleton_json; `budget` (when given) is asked first for the
/// bytes the parse will hold (kJsonBytesPerFileByte times the file's size).
/// \throw InputError naming the file: not a regular file, too large, refused by `budget`, not JSON,
/// not a valid skeleton.
Skeleton read_skeleton_json(const std::string& path, const ReadBudget& budget = {});
/// OBJ polyline (`v` and `l` lines) so that any viewer shows the skeleton.
void write_skeleton_obj(const Skeleton& s, const std::string& path);

}  // namespace sdm
