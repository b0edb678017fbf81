// sdm roundtrip: encode, decode and measure the reconstruction error.
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "apps/encode_checks.h"
#include "apps/memory_budget.h"
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

}  // namespace

Command add_roundtrip_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, png, precision = "10";
    int size = 1024, lod = 3, samples = 100000;
    double max_rms = -1, min_part = 0, min_carried = 0.9, face_error = sdm::EncodeOptions().flat_above;
    bool fill_holes = false;
    std::string max_memory;
    bool json = false, strict = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "roundtrip", "Encode a mesh, decode it, and measure the reconstruction error: symmetric Hausdorff and RMS\n"
                   "distance by dense sampling, as fractions of the bounding-box diagonal, and PSNR.\n"
                   "Exits 3 when the RMS exceeds --max-rms.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("--size", o->size, "Atlas size in texels")->capture_default_str()->check(number_in(16, 16384));
  app->add_option("--lod", o->lod, "Level of detail of the decode")->capture_default_str()->check(number_in(0, 8));
  app->add_option("--samples", o->samples, "Points sampled on each surface")->capture_default_str()->check(number_in(1000, 1e7));
  app->add_option("--max-rms", o->max_rms, "Fail (exit 3) when the RMS error, as a fraction of the diagonal, is larger")->check(number_in(0, 1));
  app->add_option("--precision", o->precision, kPrecisionHelp)->capture_default_str();
  app->add_option("-o,--output", o->out, "Also write the decoded mesh");
  app->add_option("--png", o->png,
                  "Also draw the decoded mesh coloured by its distance to the input (.png, four views; grey at 0, yellow at "
                  "0.15 %, red from 0.5 % of the diagonal)");
  add_min_part_option(app, o->min_part);
  add_repair_options(app);
  add_fill_holes_option(app, o->fill_holes);
  add_max_memory_option(app, o->max_memory);
  app->add_flag("--strict", o->strict,
                "Refuse (exit 2) a self-intersecting input or a decoded surface that carries under --min-carried of the input");
  add_min_carried_option(app, o->min_carried);
  add_face_error_option(app, o->face_error);
  app->add_flag("--json", o->json, "Print one JSON object with the summary");
  return {app, [o]() {
            const sdm::Stopwatch total;
            const sdm::SdmPrecision precision = sdm::SdmPrecision::parse(o->precision);
            const sdm::Mesh mesh = load_mesh_min_part(o->mesh, o->min_part, o->fill_holes);
            const sdm::SelfIntersections crossings = check_self_intersections(mesh, o->strict);
            const sdm::Layout layout = layout_for(mesh, encode_layout_source("", "", o->size)).layout;
            sdm::Stopwatch stage;
            progress("encoding");
            sdm::EncodeOptions eo;
            eo.progress = [](const std::string& s) { progress("  " + s); };  // as encode reports it
            eo.fill_unread = false;  // the file leaves them out
            encode_check_options(eo, o->face_error);
            sdm::EncodeStats st;
            const auto [im, map_bytes] = through_file(sdm::encode_sdm(mesh, layout, eo, &st), precision);
            const double encode_s = stage.lap();
            progress("decoding");
            sdm::DecodeOptions d;
            d.level = o->lod;
            const sdm::DecodeEstimate e = sdm::estimate_decode(im, d);
            check_memory(e.bytes, o->max_memory, "decoding " + std::to_string(int64_t(e.triangles / 1e6)) + " million triangles",
                         "use a lower --lod (each level quadruples the triangles)");
            sdm::DecodeTrace trace;
            const sdm::Mesh out = sdm::decode_sdm(im, d, &trace);
            const double decode_s = stage.lap();
            const sdm::SurfaceCoverage carried = check_carried(mesh, out, sdm::bounding_box_diagonal(mesh), o->min_carried, o->strict);
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
            if (o->json) {
              print_json({{"mesh", o->mesh}, {"size", o->size}, {"lod", o->lod}, {"segments", layout.segments.size()},
                          {"precision", precision.name()}, {"map_bytes", map_bytes}, {"base_faces", st.base_faces}, {"flat_faces", st.flat_faces},
                          {"rms", rms}, {"hausdorff", hd}, {"psnr", psnr}, {"faces", out.n_faces()},
                          {"closed", top.closed()}, {"manifold", top.manifold}, {"boundary_loops", top.boundary_loops},
                          {"input_boundary_loops", input_top.boundary_loops}, {"encode_seconds", encode_s}, {"decode_seconds", decode_s},
                          {"total_seconds", total.seconds()}, {"samples", o->samples}, {"carried", carried.share},
                          {"self_intersections", crossings.pairs}, {"longest_edge_ratio", edge_ratio}, {"worst", worst_json}});
            } else {
              std::cout << o->mesh << " at " << o->size << ", level " << o->lod << ": RMS " << 100 * rms << " %, Hausdorff "
                        << 100 * hd << " % of the diagonal, PSNR " << psnr << " dB, " << out.n_faces() << " faces, "
                        << top.text() << " (input: " << input_top.boundary_loops << " boundary loop(s)), map " << map_bytes << " bytes (" << precision.name() << ")\n"
                        << "  worst at " << point_text(worst.position) << ", segment " << worst.segment << ", base face "
                        << worst.base_face << " (" << worst_json.at("where").get<std::string>() << ")\n"
                        << "  longest decoded edge " << edge_ratio << " times the input's\n";
            }
            if (o->max_rms >= 0 && rms > o->max_rms) {
              std::cerr << "sdm roundtrip: RMS " << rms << " exceeds --max-rms " << o->max_rms << std::endl;
              return 3;
            }
            return 0;
          }};
}

}  // namespace sdm::cli
