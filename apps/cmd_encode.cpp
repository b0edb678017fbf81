// sdm encode: a mesh as a skeleton displacement map (one OpenEXR file).
#include "apps/cli_common.h"
#include "apps/cloud_maps.h"
#include "apps/commands.h"
#include "apps/encode_checks.h"
#include "apps/options.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/image.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace sdm::cli {
namespace {

// False colour of D (blue near the axis, red far) where A = 1, grey where A = 0, black outside.
sdm::Image false_color(const sdm::SdmImage& im) {
  float lo = INFINITY, hi = -INFINITY;
  for (size_t i = 0; i < im.D.size(); ++i)
    if (im.A[i] > 0.5f) lo = std::min(lo, im.D[i]), hi = std::max(hi, im.D[i]);
  sdm::Image out;
  out.width = im.width;
  out.height = im.height;
  out.channels = 4;
  out.pixels.assign(size_t(im.width) * im.height * 4, 255);
  for (size_t i = 0; i < im.D.size(); ++i) {
    uint8_t* p = &out.pixels[4 * i];
    if (im.A[i] > 0.5f) {
      const double x = hi > lo ? (im.D[i] - lo) / (hi - lo) : 0.5;
      p[0] = uint8_t(255 * std::clamp(1.5 * x - 0.25, 0.0, 1.0));
      p[1] = uint8_t(255 * std::clamp(1.0 - std::abs(2 * x - 1), 0.0, 1.0));
      p[2] = uint8_t(255 * std::clamp(1.25 - 1.5 * x, 0.0, 1.0));
    } else if (im.D[i] != 0.0f) {
      p[0] = p[1] = p[2] = 96;
    } else {
      p[0] = p[1] = p[2] = 0;
    }
  }
  return out;
}

// Encode's summary (its --json object) as text.
void print_encode_text(const nlohmann::json& j) {
  const double texels = j["texels"].get<double>(), own = texels > 0 ? j["own_hits"].get<double>() / texels : 0.0;
  const long left = j["decode_folds"]["left"].get<long>();
  std::cout << j["output"].get<std::string>() << ": " << j["size"] << "x" << j["size"] << ", " << j["segments"] << " segments, "
            << j["base_faces"] << " base faces, " << std::round(1000 * own) / 10 << " % of segment texels on their own surface\n"
            << "  carries " << std::round(1000 * j["carried"].get<double>()) / 10 << " % of the surface within "
            << 100 * kCarriedTolerance << " % of the diagonal at level 3 (RMS " << 100 * j["carried_rms"].get<double>() << " %)\n"
            << (left ? "  level 3 keeps " + std::to_string(left) + " folded face pairs (crossing) it could not untangle\n" : std::string())
            << "  layout " << j["layout_seconds"].get<double>() << " s, encode " << j["encode_seconds"].get<double>() << " s, check "
            << j["check_seconds"].get<double>() << " s\n";
}

}  // namespace

Command add_encode_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, png, precision = "10";  // BENCHMARKS: float's accuracy, 3.6-6.1x smaller at 1024
    LayoutSource layout = layout_defaults(1024, 4, true);  // the stages announced
    EncodeQuality q;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "encode", "Encode a mesh (closed, or open with holes) as a skeleton displacement map: one OpenEXR file (channels Y = displacement, A = mask)\n"
                "with the layout and base mesh in its header, so 'sdm decode' needs nothing else.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf) or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_option("-o,--output", o->out, "Output map (.exr)")->required();
  add_layout_options(app, o->layout, {true, true, false});
  app->add_option("--png", o->png, "Also write a false-colour picture of the map (.png)");
  app->add_option("--precision", o->precision, kPrecisionHelp)->capture_default_str();
  add_encode_quality_options(
      app, o->q, "Refuse (exit 2, nothing written) a self-intersecting input or a map that carries under --min-carried of the surface");
  app->add_flag("--json", o->json, "Print one JSON object with the summary");
  return {app, [o]() {
            check_layout_memory(o->layout, 10, o->q.max_memory);
            if (sdm::is_point_cloud_file(o->mesh))
              return cloud_encode({o->mesh, o->out, o->png, o->precision, "", o->layout.options.size, 3, 0, o->q.face_error, -1, o->json});
            const sdm::SdmPrecision precision = sdm::SdmPrecision::parse(o->precision);
            sdm::Stopwatch clock;
            const sdm::Mesh mesh = load_mesh_min_part(o->mesh, o->q.min_part, o->q.fill_holes);
            const sdm::SelfIntersections crossings = check_self_intersections(mesh, o->q.strict);
            const sdm::Layout layout = layout_for(mesh, o->layout, o->q.max_memory).layout;
            const double layout_s = clock.lap();
            sdm::EncodeStats st;
            sdm::EncodeOptions eo;
            eo.progress = [](const std::string& s) { progress("  " + s); };
            eo.fill_unread = !o->png.empty();  // only the picture shows texels no face reads
            encode_check_options(eo, o->q.face_error);
            const sdm::SdmImage im = sdm::encode_sdm(mesh, layout, eo, &st);
            const double encode_s = clock.lap();
            progress("  checking the map (decoded at level 3)");
            const double diag = sdm::bounding_box_diagonal(mesh);
            // The map as stored, decoded as 'sdm decode' does (its points and triangles; the
            // halfedge mesh 'sdm decode' builds of them for writing is not needed to measure them).
            const sdm::DecodedSurface decoded = sdm::decode_surface(sdm::as_stored(im, precision));
            const sdm::UntangleReport& folds = decoded.untangle;
            const sdm::SurfaceCoverage carried = check_carried(mesh, decoded, diag, o->q.min_carried, o->q.strict);
            const double check_s = clock.lap();
            sdm::write_sdm_exr(im, o->out, precision);
            if (!o->png.empty()) sdm::write_png(false_color(im), o->png);
            // One summary: --json prints it, the text reads it.
            const nlohmann::json j = {
                {"output", o->out}, {"size", im.width}, {"segments", layout.segments.size()},
                {"texels", st.texels}, {"own_hits", st.own_hits}, {"other_hits", st.other_hits},
                {"filled", st.filled}, {"base_faces", st.base_faces}, {"flat_faces", st.flat_faces}, {"layout_seconds", layout_s},
                {"encode_seconds", encode_s}, {"check_seconds", check_s}, {"carried", carried.share},
                {"carried_rms", carried.rms / diag}, {"self_intersections", crossings.pairs},
                {"decode_folds", {{"level", 3}, {"untangled", folds.crossing - folds.left},
                                  {"left", folds.left}, {"segments", folds.left_segments}}}};
            if (o->json) print_json(j);
            else print_encode_text(j);
            return 0;
          }};
}

}  // namespace sdm::cli
