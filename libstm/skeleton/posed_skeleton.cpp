#include "libstm/skeleton/posed_skeleton.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/limits.h"

#include <cmath>

namespace sdm {

namespace {

// "node_rotations" and "segment_radius_scale" (posed_skeleton.h), when present; the counts are checked by
// the caller once the nodes and edges are known.
void read_pose_fields(const nlohmann::json& j, PosedSkeleton& s) {
  if (j.contains("node_rotations")) {
    const auto& r = j.at("node_rotations");
    if (!r.is_array()) throw InputError("not a valid skeleton: \"node_rotations\" must be an array (one [x, y, z, w] or null per node)");
    for (size_t i = 0; i < r.size(); ++i) {
      if (r[i].is_null()) {
        s.node_rotations.emplace_back();
        continue;
      }
      if (!r[i].is_array() || r[i].size() != 4)
        throw InputError("not a valid skeleton: node rotation " + std::to_string(i) + " is not a quaternion [x, y, z, w]");
      const Eigen::Quaterniond q(r[i].at(3).get<double>(), r[i].at(0).get<double>(), r[i].at(1).get<double>(), r[i].at(2).get<double>());
      if (!q.coeffs().allFinite() || std::abs(q.norm() - 1) > 1e-3)
        throw InputError("not a valid skeleton: node rotation " + std::to_string(i) + " is not a unit quaternion (norm " +
                         number(q.norm()) + ")");
      s.node_rotations.push_back(q.normalized());
    }
  }
  if (j.contains("segment_radius_scale")) {
    const auto& f = j.at("segment_radius_scale");
    if (!f.is_array()) throw InputError("not a valid skeleton: \"segment_radius_scale\" must be an array (one factor per edge)");
    for (size_t i = 0; i < f.size(); ++i) {
      const double x = f[i].get<double>();
      if (!std::isfinite(x) || x <= 0 || x > 1e6)
        throw InputError("not a valid skeleton: segment_radius_scale of edge " + std::to_string(i) + " is " + number(x) +
                         " (a factor > 0 expected)");
      s.segment_radius_scale.push_back(x);
    }
  }
}

}  // namespace

nlohmann::json posed_skeleton_to_json(const PosedSkeleton& s) {
  nlohmann::json j = skeleton_to_json(s);
  if (!s.node_rotations.empty()) {
    j["node_rotations"] = nlohmann::json::array();
    for (const auto& q : s.node_rotations)
      j["node_rotations"].push_back(q ? nlohmann::json{q->x(), q->y(), q->z(), q->w()} : nlohmann::json(nullptr));
  }
  if (!s.segment_radius_scale.empty()) j["segment_radius_scale"] = s.segment_radius_scale;
  return j;
}

PosedSkeleton posed_skeleton_from_json(const nlohmann::json& j) {
  if (j.is_object() && j.contains("skeleton")) return posed_skeleton_from_json(j.at("skeleton"));  // a layout holds one
  PosedSkeleton s(skeleton_from_json(j));
  try {
    read_pose_fields(j, s);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a valid skeleton: ") + e.what());
  }
  if (!s.node_rotations.empty() && s.node_rotations.size() != s.nodes.size())
    throw InputError("not a valid skeleton: " + std::to_string(s.node_rotations.size()) + " node rotations for " +
                     std::to_string(s.nodes.size()) + " nodes (one [x, y, z, w] or null per node)");
  if (!s.segment_radius_scale.empty() && s.segment_radius_scale.size() != s.edges.size())
    throw InputError("not a valid skeleton: " + std::to_string(s.segment_radius_scale.size()) + " radius scales for " +
                     std::to_string(s.edges.size()) + " edges (one factor per edge)");
  return s;
}

void write_posed_skeleton_json(const PosedSkeleton& s, const std::string& path) {
  write_text_file(path, posed_skeleton_to_json(s).dump() + "\n");
}

PosedSkeleton read_posed_skeleton_json(const std::string& path, const ReadBudget& budget) {
  const std::string text = read_input_file(path, "skeleton", kMaxJsonFileBytes, budget, kJsonBytesPerFileByte);
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InputError("cannot read skeleton " + path + ": not JSON");
  try {
    return posed_skeleton_from_json(j);
  } catch (const InputError& e) {
    throw InputError("skeleton " + path + ": " + e.what());
  }
}

}  // namespace sdm
