#pragma once
/// A pose of a skeleton (DESIGN 3.3): the rest skeleton's graph with moved nodes, and optionally per
/// node its rotation and per edge a factor on the surface's distance from the edge's axis. What
/// libsdm/pose turns into bones (pose_skeleton.h) and what 'sdm pose' / 'sdm decode --skeleton' read.
#include "libstm/core/input_file.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sdm {

/// The skeleton part (nodes, edges, vertex_node) is the posed skeleton itself: a Skeleton is a pose
/// with no rotation given and every radius as encoded.
struct PosedSkeleton : Skeleton {
  PosedSkeleton(Skeleton skeleton = {}) : Skeleton(std::move(skeleton)) {}  // NOLINT: a skeleton is a pose
  /// Per node, the rotation of its frame from the rest skeleton's (absent: derived from the moved
  /// nodes, pose_skeleton.h); empty when none is given.
  std::vector<std::optional<Eigen::Quaterniond>> node_rotations;
  /// Per edge, a factor on the surface's distance from the edge's axis (1: as encoded); empty: all 1.
  std::vector<double> segment_radius_scale;
};

/// JSON form: a skeleton's (skeleton_to_json) with the optional fields "node_rotations": one per
/// node, a unit quaternion [x, y, z, w] (glTF order) or null (derived); "segment_radius_scale": one
/// factor > 0 per edge. Each written only when set.
nlohmann::json posed_skeleton_to_json(const PosedSkeleton& s);
/// \throw InputError naming the problem when the JSON is not a valid skeleton (skeleton_from_json)
/// or a pose field is not: a count other than the nodes' or edges', a quaternion whose norm is not
/// 1 within 1e-3 (it is normalised), a scale that is not a finite number in (0, 1e6].
PosedSkeleton posed_skeleton_from_json(const nlohmann::json& j);
/// Written atomically (write_text_file, atomic_file.h).
void write_posed_skeleton_json(const PosedSkeleton& s, const std::string& path);
/// Reads a posed skeleton written by write_posed_skeleton_json (or any skeleton file); `budget` as
/// for read_skeleton_json.
/// \throw InputError naming the file: not a regular file, too large, refused by `budget`, not JSON,
/// not a valid posed skeleton.
PosedSkeleton read_posed_skeleton_json(const std::string& path, const ReadBudget& budget = {});

}  // namespace sdm
