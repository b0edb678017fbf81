#include "apps/cloud_input.h"

#include "apps/commands.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/cloud_layout.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/skeleton/point_skeleton.h"

#include <iomanip>

namespace sdm::cli {

namespace {

void print_lines(const std::string& title, const nlohmann::json& j) {
  std::cout << title << "\n";
  for (auto it = j.begin(); it != j.end(); ++it) std::cout << "  " << std::left << std::setw(20) << it.key() << " " << it.value() << "\n";
}

}  // namespace

int cloud_skeleton(const std::string& path, const std::string& out, const std::string& obj, bool json) {
  sdm::Stopwatch clock;
  sdm::CloudReport report;
  const sdm::PointCloud cloud = sdm::load_point_cloud(path, &report, false);  // the skeleton needs no normals
  const double read_seconds = clock.lap();
  if (report.duplicates) progress(path + ": " + std::to_string(report.duplicates) + " duplicate points merged");
  sdm::PointSkeletonStats st;
  const sdm::Skeleton sk = sdm::point_cloud_skeleton(cloud.points, {}, progress, &st);
  sdm::write_skeleton_json(sk, out);
  if (!obj.empty()) sdm::write_skeleton_obj(sk, obj);
  const std::vector<double> radii = sdm::node_radii(sk, cloud.points);
  double mean_radius = 0;
  for (double r : radii) mean_radius += r / double(radii.size());
  nlohmann::json j = {{"points", report.points},
                      {"duplicates_merged", report.duplicates},
                      {"nodes", sk.nodes.size()},
                      {"edges", sk.edges.size()},
                      {"branch_nodes", sk.branch_nodes()},
                      {"end_nodes", sk.end_nodes()},
                      {"cycles", sk.cycles()},
                      {"components", sk.components()},
                      {"mean_node_radius", mean_radius},
                      {"contracted_points", st.samples},
                      {"iterations", st.iterations},
                      {"area_ratio", st.area_ratio},
                      {"sampled_nodes", st.sampled_nodes},
                      {"collapsed_triangles", st.collapsed_triangles},
                      {"opened_cycles", st.dropped_cycles},
                      {"pruned_branches", st.pruned_branches},
                      {"read_seconds", read_seconds},
                      {"seconds", st.seconds},
                      {"contraction_seconds", st.contraction_seconds}};
  if (json) print_json(j);
  else print_lines(out, j);
  return 0;
}

int cloud_stm(const std::string& path, const std::string& out, int size, int margin, const std::string& uv_obj, bool json) {
  sdm::CloudReport report;
  const sdm::PointCloud cloud = sdm::load_point_cloud(path, &report, false);  // normals estimated by cloud_layout when missing
  sdm::CloudLayoutOptions o;
  o.layout.size = size;
  o.layout.margin = margin;
  o.progress = [](const std::string& s) { progress("  " + s); };
  const sdm::CloudLayout cl = sdm::cloud_layout(cloud, o);
  const sdm::StmCoordinates c = sdm::stm_coordinates(cl.surface, cl.layout);
  sdm::write_layout_json(cl.layout, out);
  if (!uv_obj.empty()) sdm::write_mesh(c.mesh, uv_obj);
  nlohmann::json j = {{"points", report.points},
                      {"normals_estimated", cl.normals_estimated},
                      {"skeleton_nodes", cl.point_skeleton.nodes.size()},
                      {"segments", cl.layout.segments.size()},
                      {"surface_vertices", cl.traced_vertices},
                      {"gaps_filled", cl.filled_loops},
                      {"coverage", cl.layout.coverage},
                      {"stretch", c.stretch},
                      {"skeleton_seconds", cl.skeleton_seconds},
                      {"surface_seconds", cl.surface_seconds},
                      {"layout_seconds", cl.layout_seconds}};
  if (json) print_json(j);
  else print_lines(out, j);
  return 0;
}

int cloud_info(const std::string& path, bool json) {
  sdm::CloudReport report;
  sdm::load_point_cloud(path, &report);
  nlohmann::json j = {{"file", path}, {"kind", "point cloud"}, {"usable", true}};
  j.update(report.to_json());
  if (json) print_json(j);
  else print_lines(path, j);
  return 0;
}

}  // namespace sdm::cli
