// sdm decode: the mesh of a skeleton displacement map, at a level of detail, optionally posed or rigged.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "apps/options.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout_json.h"
#include "libstm/mesh/mesh.h"

#include <iostream>
#include <memory>
#include <optional>

namespace sdm::cli {

Command add_decode_command(CLI::App& parent) {
  struct Opts {
    std::string map, out, skeleton, write_skeleton;
    int lod = 3;
    std::vector<std::string> segment_lod;
    std::string max_memory;
    bool json = false, rig = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "decode", "Rebuild the mesh from a skeleton displacement map, with a level of detail chosen globally\n"
                "or per segment, optionally around a skeleton with moved nodes (same graph).");
  app->add_option("map", o->map, "Input map (.exr from 'sdm encode')")->required();
  app->add_option("-o,--output", o->out, "Output mesh (.obj, .ply, .off, .stl, .glb, .gltf)")->required();
  app->add_option("--lod", o->lod, "Level of detail: every base edge is cut into 2^L pieces")->capture_default_str()->check(number_in(0, 8));
  app->add_option("--lod-segment", o->segment_lod, "Per-segment level, ID=L (repeatable)");
  app->add_option("--skeleton", o->skeleton,
                  "Decode posed by this skeleton: the map's own skeleton (see --write-skeleton) with moved nodes, optionally "
                  "node_rotations and segment_radius_scale (README; as 'sdm pose')");
  app->add_option("--write-skeleton", o->write_skeleton,
                  "Also write the map's skeleton (.json, or .obj polyline): edit its node positions for --skeleton");
  app->add_flag("--rig", o->rig,
                "Write the mesh at rest with a glTF skin (.glb/.gltf only): a joint per skeleton node, 4 weights per vertex from "
                "the decode's blending; with --skeleton the joints hold that pose");
  add_max_memory_option(app, o->max_memory);
  app->add_flag("--json", o->json, "Print one JSON object with the summary");
  return {app, [o]() {
            const sdm::Stopwatch clock;
            if (o->rig) check_rig_output(o->out);
            const sdm::SdmImage im = sdm::read_sdm_exr(o->map);
            sdm::DecodeOptions d;
            d.level = o->lod;
            d.segment_level = parse_segment_levels(o->segment_lod);
            check_decode_memory(im, d, o->max_memory);
            if (!o->skeleton.empty()) d.skeleton = sdm::read_posed_skeleton_json(o->skeleton, json_budget(o->max_memory, o->skeleton));
            std::optional<sdm::PosedSkeleton> posed;
            if (o->rig) posed.swap(d.skeleton);  // decoded at rest, the pose goes into the joints
            const sdm::Layout layout = o->rig ? sdm::layout_from_json(im.layout) : sdm::Layout{};
            if (posed) sdm::pose_skeleton(layout.skeleton, *posed);  // the graph checked before the work
            sdm::DecodeTrace trace;
            const sdm::Mesh mesh = sdm::decode_sdm(im, d, o->rig ? &trace : nullptr);
            const double s = clock.seconds();
            // The output's topology is checked on the second core while the file is written.
            SurfaceTopology top;
            sdm::run_concurrently([&] { top = topology_of(mesh); }, [&] {
              if (o->rig) write_rigged(mesh, layout, trace, posed ? &*posed : nullptr, o->out);
              else sdm::write_mesh(mesh, o->out);
            });
            note_float32_rounding(mesh, o->out);
            if (!o->write_skeleton.empty()) {
              const sdm::Skeleton sk = sdm::layout_from_json(im.layout).skeleton;
              if (has_extension(o->write_skeleton, {".obj"}))
                sdm::write_skeleton_obj(sk, o->write_skeleton);
              else
                sdm::write_skeleton_json(sk, o->write_skeleton);
            }
            // One summary: --json prints it, the text reads it (and the topology's own words).
            const nlohmann::json j = {{"output", o->out}, {"vertices", mesh.n_vertices()}, {"faces", mesh.n_faces()},
                                      {"closed", top.closed()}, {"manifold", top.manifold}, {"boundary_loops", top.boundary_loops},
                                      {"seconds", s}};
            if (o->json)
              print_json(j);
            else
              std::cout << j["output"].get<std::string>() << ": " << j["vertices"] << " vertices, " << j["faces"] << " faces, "
                        << top.text() << ", " << j["seconds"].get<double>() << " s\n";
            return 0;
          }};
}

}  // namespace sdm::cli
