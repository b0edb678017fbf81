#include "apps/bench_pose.h"

#include "apps/commands.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/pose/deform_decoded.h"
#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <algorithm>
#include <iomanip>
#include <iostream>

namespace sdm::cli {
namespace {

std::vector<Eigen::Vector3d> points_of(const Mesh& m) {
  std::vector<Eigen::Vector3d> p;
  for (auto v : m.vertices()) p.push_back(point(m, v));
  return p;
}

Mesh with_points(Mesh m, const std::vector<Eigen::Vector3d>& p) {
  for (auto v : m.vertices()) m.set_point(v, Mesh::Point(p[size_t(v.idx())].x(), p[size_t(v.idx())].y(), p[size_t(v.idx())].z()));
  return m;
}

// Per skeleton node, the rigid motion (Kabsch) of the source vertices it owns onto their places in
// the target; a node owning fewer than 4 takes its neighbours' too.
std::vector<Similarity> node_motions(const Skeleton& s, const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  std::vector<std::vector<int>> owned(s.nodes.size());
  for (size_t i = 0; i < s.vertex_node.size(); ++i) owned[size_t(s.vertex_node[i])].push_back(int(i));
  const auto adj = s.adjacency();
  std::vector<Similarity> out(s.nodes.size());
  for (size_t n = 0; n < s.nodes.size(); ++n) {
    std::vector<int> ids = owned[n];
    if (ids.size() < 4)
      for (int k : adj[n]) ids.insert(ids.end(), owned[size_t(k)].begin(), owned[size_t(k)].end());
    std::vector<Eigen::Vector3d> x, y;
    for (int i : ids) x.push_back(from[size_t(i)]), y.push_back(to[size_t(i)]);
    Eigen::Vector3d cx = Eigen::Vector3d::Zero(), cy = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < x.size(); ++i) cx += x[i], cy += y[i];
    cx /= double(x.size()), cy /= double(x.size());
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < x.size(); ++i) M += (y[i] - cy) * (x[i] - cx).transpose();
    out[n].rotation = nearest_rotation(M);
    out[n].translation = cy - out[n].rotation * cx;
  }
  return out;
}

// The baseline: linear blend skinning of the source's vertices with the nodes' motions, Gaussian
// weights exp(-d^2 / (2 sigma^2)) over the 4 nearest nodes, sigma the mean of those 4 distances.
std::vector<Eigen::Vector3d> linear_blend(const Skeleton& s, const std::vector<Similarity>& motion, const std::vector<Eigen::Vector3d>& from) {
  std::vector<Eigen::Vector3d> out(from.size());
  std::vector<std::pair<double, int>> near(s.nodes.size());
  for (size_t i = 0; i < from.size(); ++i) {
    for (size_t n = 0; n < s.nodes.size(); ++n) near[n] = {(s.nodes[n] - from[i]).norm(), int(n)};
    const size_t k = std::min<size_t>(4, near.size());
    std::partial_sort(near.begin(), near.begin() + long(k), near.end());
    double sigma = 0;
    for (size_t j = 0; j < k; ++j) sigma += near[j].first / double(k);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double wsum = 0;
    for (size_t j = 0; j < k; ++j) {
      const double w = std::exp(-near[j].first * near[j].first / (2 * sigma * sigma));
      sum += w * motion[size_t(near[j].second)](from[i]), wsum += w;
    }
    out[i] = sum / wsum;
  }
  return out;
}

struct PoseRow {
  std::string source, target;
  int nodes = 0;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  // where ours is farthest from the target
  bool worst_on_posed = false;
  double rest_rms = 0, ours_rms = 0, ours_hd = 0, lbs_rms = 0, lbs_hd = 0, unposed_rms = 0, unposed_hd = 0, seconds = 0;
};

PoseRow measure_pair(const std::string& source_path, const std::string& target_path, int size) {
  PoseRow row;
  row.source = source_path, row.target = target_path;
  const Mesh source = load_mesh(source_path).mesh, target = load_mesh(target_path).mesh;
  if (source.n_vertices() != target.n_vertices())
    throw InputError("bench --pose: " + source_path + " and " + target_path + " have different vertex counts (vertex i must correspond)");
  LayoutOptions lo;
  lo.size = size;
  const Layout layout = compute_layout(source, extract_skeleton(source), lo);
  const SdmImage image = encode_sdm(source, layout);
  const Skeleton& rest = layout.skeleton;
  const std::vector<Eigen::Vector3d> from = points_of(source), to = points_of(target);
  const std::vector<Similarity> motion = node_motions(rest, from, to);
  PosedSkeleton posed = rest;
  posed.node_rotations.resize(rest.nodes.size());
  for (size_t n = 0; n < rest.nodes.size(); ++n) {
    posed.nodes[n] = motion[n](rest.nodes[n]);
    posed.node_rotations[n] = Eigen::Quaterniond(motion[n].rotation);
  }
  row.nodes = int(rest.nodes.size());
  const Stopwatch clock;
  DecodeTrace trace;
  const Mesh decoded = decode_sdm(image, {}, &trace);
  std::vector<Eigen::Vector3d> p = points_of(decoded);
  pose_points(layout, posed, trace.vertex_segment, face_matrix(decoded), p);
  row.seconds = clock.seconds();
  const Mesh ours = with_points(decoded, p);
  const Mesh lbs = with_points(source, linear_blend(rest, motion, from));
  auto measure = [&](const Mesh& a, const Mesh& b, double& rms, double& hd) {
    const SurfaceDistance d = surface_distance(a, b, 100000);
    rms = d.rms / d.diagonal, hd = d.hausdorff / d.diagonal;
    return d;
  };
  double unused = 0;
  measure(source, decoded, row.rest_rms, unused);
  const SurfaceDistance worst = measure(target, ours, row.ours_rms, row.ours_hd);
  row.worst = worst.worst_point;
  row.worst_on_posed = worst.worst_on_b;
  measure(target, lbs, row.lbs_rms, row.lbs_hd);
  measure(target, source, row.unposed_rms, row.unposed_hd);
  return row;
}

}  // namespace

int run_pose_bench(const std::vector<std::string>& pairs, int size, bool json, const std::string& machine) {
  if (pairs.size() % 2) throw InputError("bench --pose takes pairs of meshes: SOURCE TARGET [SOURCE TARGET ...]");
  std::vector<PoseRow> rows;
  for (size_t i = 0; i + 1 < pairs.size(); i += 2) {
    progress("bench: posing " + pairs[i] + " like " + pairs[i + 1]);
    rows.push_back(measure_pair(pairs[i], pairs[i + 1], size));
    const Eigen::Vector3d& w = rows.back().worst;
    progress("  farthest from the target at (" + std::to_string(w.x()) + ", " + std::to_string(w.y()) + ", " + std::to_string(w.z()) +
             (rows.back().worst_on_posed ? "), on the posed surface" : "), on the target"));
  }
  if (json) {
    nlohmann::json out = nlohmann::json::array();
    for (const PoseRow& r : rows)
      out.push_back({{"source", r.source}, {"target", r.target}, {"nodes", r.nodes}, {"rest_rms", r.rest_rms}, {"rms", r.ours_rms},
                     {"hausdorff", r.ours_hd}, {"lbs_rms", r.lbs_rms}, {"lbs_hausdorff", r.lbs_hd}, {"unposed_rms", r.unposed_rms},
                     {"unposed_hausdorff", r.unposed_hd}, {"pose_seconds", r.seconds},
                     {"worst", {r.worst.x(), r.worst.y(), r.worst.z()}}, {"worst_on_posed", r.worst_on_posed}});
    print_json({{"machine", machine}, {"size", size}, {"poses", out}});
    return 0;
  }
  std::cout << "Posing through the SDM's skeleton (atlas " << size << ", decode level 3; " << machine << ")\n"
            << "errors to the target's surface in % of its diagonal; per node the Kabsch motion of the vertices it owns\n"
            << "| source -> target | nodes | round trip RMS | ours RMS | ours Hausdorff | LBS RMS | LBS Hausdorff | unposed RMS | unposed Hausdorff | decode + pose (s) |\n"
            << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const PoseRow& r : rows)
    std::cout << "| " << r.source << " -> " << r.target << " | " << r.nodes << " | " << std::fixed << std::setprecision(3) << 100 * r.rest_rms
              << " | " << 100 * r.ours_rms << " | " << std::setprecision(2) << 100 * r.ours_hd << " | " << std::setprecision(3)
              << 100 * r.lbs_rms << " | " << std::setprecision(2) << 100 * r.lbs_hd << " | " << std::setprecision(3) << 100 * r.unposed_rms
              << " | " << std::setprecision(2) << 100 * r.unposed_hd << " | " << r.seconds << " |\n";
  return 0;
}

}  // namespace sdm::cli
