// sdm roundtrip: encode, decode and measure the reconstruction error.
#include "apps/cli_common.h"
#include "apps/cloud_maps.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "apps/encode_checks.h"
#include "apps/options.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/image.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/render/render_mesh.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

namespace sdm::cli {
namespace {

// The bytes of the map as `sdm encode` would write it, and the map as a reader sees it: written to a
// temporary file next to nothing the user owns, read back, removed (also by a signal).
std::pair<sdm::SdmImage, uintmax_t> through_file(const sdm::SdmImage& im, sdm::SdmPrecision precision) {
  namespace fs = std::filesystem;
  const sdm::ScratchFile tmp((fs::temp_directory_path() / ("sdm-roundtrip-" + std::to_string(::getpid()) + ".exr")).string());
  sdm::write_sdm_exr(im, tmp.path(), precision);
  return {sdm::read_sdm_exr(tmp.path()), fs::file_size(tmp.path())};
}

// Where a round trip's worst error is: the point of the Hausdorff distance, and the
// segment and base face of the decoded vertex nearest it.
struct WorstError {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int segment = -1, base_face = -1;
  bool decoded_strays = false;  // the decoded surface leaves the input there (else it misses input)
};
WorstError locate_worst(const sdm::SurfaceDistance& d, const sdm::Mesh& decoded, const sdm::DecodeTrace& trace) {
  WorstError w;
  w.position = d.worst_point;
  w.decoded_strays = d.worst_on_b;
  const Eigen::Vector3d on_decoded = d.worst_on_b ? d.worst_point : d.worst_closest;
  double best = INFINITY;
  for (auto v : decoded.vertices()) {
    const double dist = (sdm::point(decoded, v) - on_decoded).squaredNorm();
    if (dist < best) best = dist, w.segment = trace.vertex_segment[v.idx()], w.base_face = trace.vertex_base_face[v.idx()];
  }
  return w;
}

// The decoded mesh coloured by each vertex's distance to the input (grey-blue at 0, yellow at
// 0.15 %, red from 0.5 % of the diagonal on), seen from four sides, lit. The colour comes from a
// ramp texture through per-vertex uv, so the renderer needs nothing new.
void write_error_png(const sdm::Mesh& input, sdm::Mesh decoded, double diag, const std::string& path) {
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(input), sdm::face_matrix(input));
  constexpr int kRamp = 256;
  sdm::Image ramp(kRamp, 2);
  for (int x = 0; x < kRamp; ++x) {
    const double t = x / double(kRamp - 1);
    const Eigen::Vector3d grey(0.72, 0.76, 0.86), yellow(1.0, 0.85, 0.2), red(0.85, 0.1, 0.1);
    const Eigen::Vector3d c = t < 0.3 ? grey + (yellow - grey) * (t / 0.3) : yellow + (red - yellow) * ((t - 0.3) / 0.7);
    for (int y = 0; y < 2; ++y) {
      for (int k = 0; k < 3; ++k) ramp.at(x, y)[k] = uint8_t(std::lround(255 * c[k]));
      ramp.at(x, y)[3] = 255;
    }
  }
  decoded.request_halfedge_texcoords2D();
  for (auto v : decoded.vertices()) {
    const double t = std::min(1.0, bvh.closest_point(sdm::point(decoded, v)).distance / (0.005 * diag));
    const float u = float((0.5 + t * (kRamp - 1)) / kRamp);
    for (auto h : decoded.vih_range(v)) decoded.set_texcoord2D(h, sdm::Mesh::TexCoord2D(u, 0.5f));
  }
  sdm::GlContext gl;
  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.texture = &ramp;
  ro.frame = sdm::principal_view_frame(decoded);
  std::vector<sdm::Image> views;
  for (int k = 0; k < 4; ++k) {
    ro.azimuth_deg = 30 + 90 * k;
    views.push_back(sdm::render_mesh(gl, decoded, ro));
  }
  sdm::write_png(sdm::contact_sheet(views, 2), path);
}

// Roundtrip's summary (its --json object) as text, the decoded surface's topology in its own words.
void print_roundtrip_text(const nlohmann::json& j, const SurfaceTopology& top) {
  auto num = [&](const char* key) { return j[key].get<double>(); };
  const nlohmann::json& w = j["worst"];
  const Eigen::Vector3d at(w["position"][0].get<double>(), w["position"][1].get<double>(), w["position"][2].get<double>());
  std::cout << j["mesh"].get<std::string>() << " at " << j["size"] << ", level " << j["lod"] << ": RMS " << 100 * num("rms")
            << " %, Hausdorff " << 100 * num("hausdorff") << " % of the diagonal, PSNR " << num("psnr") << " dB, " << j["faces"]
            << " faces, " << top.text() << " (input: " << j["input_boundary_loops"] << " boundary loop(s)), map " << j["map_bytes"]
            << " bytes (" << j["precision"].get<std::string>() << ")\n"
            << "  worst at " << point_text(at) << ", segment " << w["segment"] << ", base face " << w["base_face"] << " ("
            << w["where"].get<std::string>() << ")\n"
            << "  longest decoded edge " << num("longest_edge_ratio") << " times the input's\n";
}

}  // namespace

Command add_roundtrip_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, png, precision = "10", reference;
    LayoutSource layout = layout_defaults(1024, 4, true);  // the stages announced
    int lod = 3, samples = 100000;
    double max_rms = -1;
    EncodeQuality q;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "roundtrip", "Encode a mesh, decode it, and measure the reconstruction error: symmetric Hausdorff and RMS\n"
                   "distance by dense sampling, as fractions of the bounding-box diagonal, and PSNR.\n"
                   "Exits 3 when the RMS exceeds --max-rms.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf) or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_option("--reference", o->reference,
                  "For a point cloud: also measure the decoded surface against this mesh (RMS and Hausdorff both ways); the points "
                  "themselves are measured one way, each to the decoded surface");
  add_layout_options(app, o->layout, {});
  app->add_option("--lod", o->lod, "Level of detail of the decode")->capture_default_str()->check(number_in(0, 8));
  app->add_option("--samples", o->samples, "Points sampled on each surface")->capture_default_str()->check(number_in(1000, 1e7));
  app->add_option("--max-rms", o->max_rms, "Fail (exit 3) when the RMS error, as a fraction of the diagonal, is larger")->check(number_in(0, 1));
  app->add_option("--precision", o->precision, kPrecisionHelp)->capture_default_str();
  app->add_option("-o,--output", o->out, "Also write the decoded mesh");
  app->add_option("--png", o->png,
                  "Also draw the decoded mesh coloured by its distance to the input (.png, four views; grey at 0, yellow at "
                  "0.15 %, red from 0.5 % of the diagonal)");
  add_encode_quality_options(app, o->q,
                             "Refuse (exit 2) a self-intersecting input or a decoded surface that carries under --min-carried of the input");
  app->add_flag("--json", o->json, "Print one JSON object with the summary");
  return {app, [o]() {
            check_layout_memory(o->layout, 10, o->q.max_memory);
            if (sdm::is_point_cloud_file(o->mesh))
              return cloud_roundtrip({o->mesh, o->out, o->png, o->precision, o->reference, o->layout.options.size, o->lod, o->samples,
                                      o->q.face_error, o->max_rms, o->json});
            if (!o->reference.empty()) throw sdm::InputError("--reference is for a point cloud; a mesh is its own reference");
            const sdm::Stopwatch total;
            const sdm::SdmPrecision precision = sdm::SdmPrecision::parse(o->precision);
            const sdm::Mesh mesh = load_mesh_min_part(o->mesh, o->q.min_part, o->q.fill_holes);
            const sdm::SelfIntersections crossings = check_self_intersections(mesh, o->q.strict);
            const sdm::Layout layout = layout_for(mesh, o->layout, o->q.max_memory).layout;
            sdm::Stopwatch stage;
            progress("encoding");
            sdm::EncodeOptions eo;
            eo.progress = [](const std::string& s) { progress("  " + s); };  // as encode reports it
            eo.fill_unread = false;  // the file leaves them out
            encode_check_options(eo, o->q.face_error);
            sdm::EncodeStats st;
            const auto [im, map_bytes] = through_file(sdm::encode_sdm(mesh, layout, eo, &st), precision);
            const double encode_s = stage.lap();
            progress("decoding");
            sdm::DecodeOptions d;
            d.level = o->lod;
            check_decode_memory(im, d, o->q.max_memory);
            sdm::DecodeTrace trace;
            const sdm::Mesh out = sdm::decode_sdm(im, d, &trace);
            const double decode_s = stage.lap();
            const sdm::SurfaceCoverage carried = check_carried(mesh, out, sdm::bounding_box_diagonal(mesh), o->q.min_carried, o->q.strict);
            if (!o->out.empty()) sdm::write_mesh(out, o->out);
            progress("measuring");
            const sdm::SurfaceDistance dist = sdm::surface_distance(mesh, out, o->samples);
            const double rms = dist.rms / dist.diagonal, hd = dist.hausdorff / dist.diagonal;
            const double psnr = 20 * std::log10(1.0 / rms);
            const SurfaceTopology top = topology_of(out), input_top = topology_of(mesh);
            const WorstError worst = locate_worst(dist, out, trace);
            const double edge_ratio = longest_edge(out) / longest_edge(mesh);  // the bound: at most 1
            if (!o->png.empty()) write_error_png(mesh, out, dist.diagonal, o->png);
            const nlohmann::json worst_json = {{"position", {worst.position.x(), worst.position.y(), worst.position.z()}},
                                               {"segment", worst.segment}, {"base_face", worst.base_face},
                                               {"where", worst.decoded_strays ? "decoded surface off the input" : "input not reached"}};
            // One summary: --json prints it, the text reads it (and the topology's own words).
            const nlohmann::json j = {
                {"mesh", o->mesh}, {"size", o->layout.options.size}, {"lod", o->lod}, {"segments", layout.segments.size()},
                {"precision", precision.name()}, {"map_bytes", map_bytes}, {"base_faces", st.base_faces}, {"flat_faces", st.flat_faces},
                {"rms", rms}, {"hausdorff", hd}, {"psnr", psnr}, {"faces", out.n_faces()},
                {"closed", top.closed()}, {"manifold", top.manifold}, {"boundary_loops", top.boundary_loops},
                {"input_boundary_loops", input_top.boundary_loops}, {"encode_seconds", encode_s}, {"decode_seconds", decode_s},
                {"total_seconds", total.seconds()}, {"samples", o->samples}, {"carried", carried.share},
                {"self_intersections", crossings.pairs}, {"longest_edge_ratio", edge_ratio}, {"worst", worst_json}};
            if (o->json) print_json(j);
            else print_roundtrip_text(j, top);
            if (o->max_rms >= 0 && rms > o->max_rms) {
              std::cerr << "sdm roundtrip: RMS " << rms << " exceeds --max-rms " << o->max_rms << std::endl;
              return 3;
            }
            return 0;
          }};
}

}  // namespace sdm::cli
