// sdm pose: a skeleton displacement map decoded posed through its skeleton.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "apps/options.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/pose/deform_decoded.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace sdm::cli {
namespace {

std::vector<std::string> split(const std::string& s, char c) {
  std::vector<std::string> out(1);
  for (char x : s) {
    if (x == c) out.emplace_back();
    else out.back().push_back(x);
  }
  return out;
}

// One --rotate NODE=AX,AY,AZ,DEG | NODE=x|y|z,DEG | NODE=twist,DEG applied to `posed`: the sub-tree
// below NODE turned about NODE (twist: about the axis from NODE to its only child).
void apply_rotate(const sdm::Skeleton& rest, sdm::PosedSkeleton& posed, const std::string& item) {
  const std::string form = "--rotate '" + item + "' is not of the form NODE=AX,AY,AZ,DEG, NODE=x|y|z,DEG or NODE=twist,DEG";
  const IdValue iv = parse_id_value(item, form);
  const int node = iv.id;
  if (node < 0 || size_t(node) >= rest.nodes.size())
    throw sdm::InputError("--rotate names node " + std::to_string(node) + " but the skeleton has " + std::to_string(rest.nodes.size()) +
                          " nodes (0.." + std::to_string(rest.nodes.size() - 1) + "; see --write-skeleton)");
  const std::vector<std::string> parts = split(iv.value, ',');
  Eigen::Vector3d axis;
  if (parts.size() == 4) {
    for (int k = 0; k < 3; ++k) axis[k] = parse_finite_number(parts[size_t(k)], form);
  } else if (parts.size() == 2 && (parts[0] == "x" || parts[0] == "y" || parts[0] == "z")) {
    axis = Eigen::Vector3d::Unit(parts[0][0] - 'x');
  } else if (parts.size() == 2 && parts[0] == "twist") {
    const sdm::SkeletonPose pose = sdm::pose_skeleton(rest, posed);
    std::vector<int> children;
    for (size_t n = 0; n < pose.node_parent.size(); ++n)
      if (pose.node_parent[n] == node) children.push_back(int(n));
    if (children.size() != 1)
      throw sdm::InputError("--rotate " + std::to_string(node) + "=twist needs a node with one child in the bone tree; node " +
                            std::to_string(node) + " has " + std::to_string(children.size()) +
                            ": give the axis instead (NODE=AX,AY,AZ,DEG)");
    axis = posed.nodes[size_t(children[0])] - posed.nodes[size_t(node)];
  } else {
    throw sdm::InputError(form);
  }
  if (!(axis.norm() > 0)) throw sdm::InputError("--rotate '" + item + "': the axis has no direction");
  const double degrees = parse_finite_number(parts.back(), form);
  sdm::rotate_subtree(rest, posed, node, Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized())));
}

// One --scale-radius SEG=F: the factor multiplies the segment's (repeated options compose).
void apply_scale(sdm::PosedSkeleton& posed, const std::string& item) {
  const std::string form = "--scale-radius '" + item + "' is not of the form SEGMENT=FACTOR (e.g. 3=1.2)";
  const IdValue iv = parse_id_value(item, form);
  const int seg = iv.id;
  const double f = parse_finite_number(iv.value, form);
  if (seg < 0 || size_t(seg) >= posed.edges.size())
    throw sdm::InputError("--scale-radius names segment " + std::to_string(seg) + " but the map has " + std::to_string(posed.edges.size()) +
                          " segments (0.." + std::to_string(posed.edges.size() - 1) + ")");
  if (!(f > 0) || f > 1e6) throw sdm::InputError("--scale-radius " + item + ": the factor must be > 0");
  if (posed.segment_radius_scale.empty()) posed.segment_radius_scale.assign(posed.edges.size(), 1.0);
  posed.segment_radius_scale[size_t(seg)] *= f;
}

// What a pose moves: nodes displaced or turned, segments whose motion is not the identity.
nlohmann::json pose_summary(const sdm::Skeleton& rest, const sdm::SkeletonPose& pose, double diag) {
  std::vector<int> nodes, segments;
  for (size_t n = 0; n < rest.nodes.size(); ++n)
    if ((pose.posed[n] - pose.rest[n]).norm() > 1e-9 * diag || pose.node_rotation[n].angularDistance(Eigen::Quaterniond::Identity()) > 1e-9)
      nodes.push_back(int(n));
  for (size_t s = 0; s < pose.bones.size(); ++s) {
    const sdm::Bone& b = pose.bones[s];
    if (b.stretch != 1 || b.radius_scale != 1 || b.motion.rotation.angularDistance(Eigen::Quaterniond::Identity()) > 1e-9 ||
        b.motion.translation.norm() > 1e-9 * diag)
      segments.push_back(int(s));
  }
  return {{"nodes", nodes}, {"segments", segments}, {"root", pose.node_parent.empty() ? -1 : int(std::find(pose.node_parent.begin(), pose.node_parent.end(), -1) - pose.node_parent.begin())}};
}

// Pose's summary (its --json object) as text.
void print_pose_text(const nlohmann::json& j) {
  const SurfaceTopology top{j["manifold"].get<bool>(), j["boundary_loops"].get<int>(), 0};  // pose reports no genus
  const double moved = j["max_displacement"].get<double>();
  std::cout << j["output"].get<std::string>() << ": " << j["vertices"] << " vertices, " << j["faces"] << " faces, " << top.text()
            << ", largest displacement " << moved << " (" << 100 * moved / j["diagonal"].get<double>() << " % of the diagonal), "
            << j["seconds"].get<double>() << " s\n";
}

}  // namespace

Command add_pose_command(CLI::App& parent) {
  struct Opts {
    std::string map, out, skeleton, write_skeleton, max_memory;
    int lod = 3;
    std::vector<std::string> rotate, scale;
    bool json = false, rig = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "pose", "Decode a skeleton displacement map posed through its skeleton: parts turned about skeleton nodes,\n"
              "segments thickened or thinned; the surface follows the segments rigidly and blends near the joints\n"
              "(dual quaternions). Node and segment numbers: 'sdm decode MAP --write-skeleton S.json'.");
  app->add_option("map", o->map, "Input map (.exr from 'sdm encode')")->required();
  app->add_option("-o,--output", o->out, "Output mesh (.obj, .ply, .off, .stl, .glb, .gltf)")->required();
  app->add_option("--lod", o->lod, "Level of detail: every base edge is cut into 2^L pieces")->capture_default_str()->check(number_in(0, 8));
  app->add_option("--rotate", o->rotate,
                  "Turn the part below NODE (away from the skeleton's root) about NODE: NODE=AX,AY,AZ,DEG (axis and degrees), "
                  "NODE=x|y|z,DEG, or NODE=twist,DEG (about the axis from NODE to its only child); repeatable, applied in order");
  app->add_option("--scale-radius", o->scale, "Scale the surface's distance from segment SEG's axis: SEG=FACTOR (repeatable)");
  app->add_option("--skeleton", o->skeleton, "Start from this pose (a skeleton JSON of the map's graph) instead of the rest pose");
  app->add_option("--write-skeleton", o->write_skeleton, "Also write the posed skeleton (.json, with node_rotations), for --skeleton or 'sdm decode --skeleton'");
  app->add_flag("--rig", o->rig,
                "Write the mesh at rest with a glTF skin (.glb/.gltf only), the joints holding the pose (node rotations; linear blend "
                "skinning, no stretch or radius scale)");
  add_max_memory_option(app, o->max_memory);
  app->add_flag("--json", o->json, "Print one JSON object: what moved (nodes, segments), the largest vertex displacement, the output");
  return {app, [o]() {
            const sdm::Stopwatch clock;
            if (o->rig) check_rig_output(o->out);
            const sdm::SdmImage im = sdm::read_sdm_exr(o->map);
            const sdm::Layout layout = sdm::layout_from_json(im.layout);
            const sdm::Skeleton& rest = layout.skeleton;
            sdm::PosedSkeleton posed = rest;
            if (!o->skeleton.empty()) {
              posed = sdm::read_posed_skeleton_json(o->skeleton, json_budget(o->max_memory, o->skeleton));
              posed.vertex_node = rest.vertex_node;
              sdm::pose_skeleton(rest, posed);  // the graph checked before the work
            }
            for (const auto& r : o->rotate) apply_rotate(rest, posed, r);
            for (const auto& s : o->scale) apply_scale(posed, s);
            sdm::DecodeOptions d;
            d.level = o->lod;
            check_decode_memory(im, d, o->max_memory);
            progress("decoding at rest");
            sdm::DecodeTrace trace;
            sdm::Mesh mesh = sdm::decode_sdm(im, d, &trace);
            if (o->rig) write_rigged(mesh, layout, trace, &posed, o->out);
            progress("posing");
            std::vector<Eigen::Vector3d> points;
            for (auto v : mesh.vertices()) points.push_back(sdm::point(mesh, v));
            const std::vector<Eigen::Vector3d> before = points;
            sdm::pose_points(layout, posed, trace.vertex_segment, sdm::face_matrix(mesh), points);
            double moved = 0;
            for (size_t i = 0; i < points.size(); ++i) {
              moved = std::max(moved, (points[i] - before[i]).norm());
              mesh.set_point(mesh.vertex_handle(int(i)), sdm::Mesh::Point(points[i].x(), points[i].y(), points[i].z()));
            }
            SurfaceTopology top;
            sdm::run_concurrently([&] { top = topology_of(mesh); }, [&] {
              if (!o->rig) sdm::write_mesh(mesh, o->out);
            });
            if (!o->write_skeleton.empty()) sdm::write_posed_skeleton_json(posed, o->write_skeleton);
            const double diag = sdm::bounding_box_diagonal(mesh);
            const double s = clock.seconds();
            // One summary: --json prints it, the text reads it.
            nlohmann::json j = pose_summary(rest, sdm::pose_skeleton(rest, posed), diag);
            j["output"] = o->out;
            j["vertices"] = mesh.n_vertices();
            j["faces"] = mesh.n_faces();
            j["max_displacement"] = moved;
            j["max_displacement_diagonal"] = diag > 0 ? moved / diag : 0.0;
            j["diagonal"] = diag;
            j["closed"] = top.closed();
            j["manifold"] = top.manifold;
            j["boundary_loops"] = top.boundary_loops;
            j["seconds"] = s;
            if (o->json) print_json(j);
            else print_pose_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
