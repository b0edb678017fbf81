#include "apps/cli_common.h"
#include "apps/cloud_input.h"
#include "apps/commands.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/skeleton/skeleton.h"

#include <memory>

namespace sdm::cli {
namespace {

// Per part, the candidate the extraction kept, as --method spells it.
std::vector<std::string> kept_names(const sdm::SkeletonStats& st) {
  std::vector<std::string> names;
  for (sdm::SkeletonMethod m : st.kept) names.emplace_back(sdm::to_string(m));
  return names;
}

}  // namespace

Command add_skeleton_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, obj, method = "auto";
    bool json = false, uniform = false;
    sdm::SkeletonOptions sk;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "skeleton", "Extract the curve skeleton of a closed mesh (Laplacian contraction or medial poles, then\n"
                  "connectivity surgery) and write it as JSON (nodes, edges, the node of every vertex).");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf), closed and manifold, or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_option("-o,--output", o->out, "Output skeleton JSON file")->required();
  app->add_option("--obj", o->obj, "Also write the skeleton as an OBJ polyline");
  app->add_flag("--json", o->json, "Print the summary as one JSON object");
  add_repair_options(app);
  app->add_option("--method", o->method,
                  "Contracted shape for the surgery: auto (both candidates, the better kept), contraction (Laplacian "
                  "contraction only, the paper's method) or medial (medial poles only)")
      ->check(CLI::IsMember({"auto", "contraction", "medial"}));
  app->add_flag("--uniform", o->uniform, "Contract the proxy with uniform instead of cotangent weights (Au et al.)");
  app->add_option("--prune-radius", o->sk.prune_radius,
                  "End branches shorter than this multiple of their junction's radius are pruned")
      ->check(number_in(0, 100));
  app->add_option("--proxy-vertices", o->sk.proxy_max_vertices, "Parts with more vertices are contracted through a remeshed proxy of about this size (0: never)")->check(number_in(0, 1e7));
  app->add_option("--laplacian-weight", o->sk.contraction.laplacian_weight, "Initial Laplacian weight of the proxy contraction (relative)")->check(number_above(0, 1e6));
  app->add_option("--laplacian-scale", o->sk.contraction.laplacian_scale, "Growth of the proxy Laplacian weight per iteration")->check(number_above(1, 100));
  app->add_option("--max-iterations", o->sk.contraction.max_iterations, "Most proxy contraction iterations")->check(number_in(1, 1000));
  app->add_option("--cot-min", o->sk.contraction.cot_min, "Lower clamp of the proxy's cotangent weights (the upper clamp is 5)")
      ->check(number_in(-100.0, 4.0));
  app->add_option("--medial-smoothing", o->sk.medial_smoothing, "Umbrella smoothing steps of the medial poles before their surgery")->check(number_in(0, 1000));
  app->add_option("--sampling-weight", o->sk.sampling_weight, "Weight of the sampling term of the collapse cost")->check(number_in(0, 1000));
  return {app, [o]() {
            if (sdm::is_point_cloud_file(o->mesh)) return cloud_skeleton(o->mesh, o->out, o->obj, o->json);
            const sdm::Mesh mesh = load_mesh_min_part(o->mesh);
            if (o->uniform) o->sk.contraction = sdm::uniform_contraction();
            for (sdm::SkeletonMethod m : {sdm::SkeletonMethod::automatic, sdm::SkeletonMethod::contraction, sdm::SkeletonMethod::medial})
              if (o->method == sdm::to_string(m)) o->sk.method = m;
            sdm::SkeletonStats st;
            const sdm::Skeleton sk = sdm::extract_skeleton(mesh, o->sk, progress, &st);
            sdm::write_skeleton_json(sk, o->out);
            if (!o->obj.empty()) sdm::write_skeleton_obj(sk, o->obj);
            nlohmann::json j = {{"nodes", sk.nodes.size()},
                                {"edges", sk.edges.size()},
                                {"branch_nodes", sk.branch_nodes()},
                                {"end_nodes", sk.end_nodes()},
                                {"cycles", sk.cycles()},
                                {"components", sk.components()},
                                {"iterations", st.iterations},
                                {"seconds", st.seconds},
                                {"contraction_seconds", st.contraction_seconds},
                                {"surgery_seconds", st.surgery_seconds},
                                {"refinement_seconds", st.refinement_seconds},
                                {"proxy_vertices", st.proxy_vertices},
                                {"proxy_seconds", st.proxy_seconds},
                                {"medial_seconds", st.medial_seconds},
                                {"medial_parts", st.medial_parts},
                                {"area_ratio", st.area_ratio},
                                {"kept", kept_names(st)},
                                {"outside_edges", st.outside_edges},
                                {"filled_loops", st.filled_loops},
                                {"fill_vertices", st.fill_vertices},
                                {"dropped_nodes", st.dropped_nodes}};
            if (o->json) {
              print_json(j);
            } else {
              std::cout << o->out << "\n";
              for (auto it = j.begin(); it != j.end(); ++it) std::cout << "  " << it.key() << " " << it.value() << "\n";
            }
            return 0;
          }};
}

}  // namespace sdm::cli
