#include "apps/cloud_maps.h"

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_cloud.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/point_distances.h"
#include "libstm/mesh/surface_distance.h"

#include <cmath>
#include <sstream>

namespace sdm::cli {
namespace {

// The cloud read and prepared, with the layout of its surface, progress on stderr.
struct CloudScene {
  PointCloud cloud;
  CloudReport report;
  CloudLayout layout;
  double diagonal = 0;
};

CloudScene cloud_scene(const CloudMapArgs& a) {
  CloudScene sc;
  sc.cloud = load_point_cloud(a.cloud, &sc.report, false);  // normals estimated by cloud_layout when missing
  if (sc.report.duplicates) progress(a.cloud + ": " + std::to_string(sc.report.duplicates) + " duplicate points merged");
  sc.diagonal = (sc.report.bbox_max - sc.report.bbox_min).norm();
  CloudLayoutOptions o;
  o.layout.size = a.size;
  o.progress = [](const std::string& s) { progress("  " + s); };
  sc.layout = cloud_layout(sc.cloud, o);
  return sc;
}

EncodeOptions cloud_encode_options(const CloudMapArgs& a) {
  EncodeOptions eo;
  eo.progress = [](const std::string& s) { progress("  " + s); };
  eo.fill_unread = false;
  eo.flat_above = a.face_error;
  eo.refine_above = 3 * a.face_error;
  return eo;
}

nlohmann::json scene_json(const CloudScene& sc) {
  const CloudLayout& l = sc.layout;
  return {{"points", sc.report.points},
          {"normals_estimated", l.normals_estimated},
          {"skeleton_nodes", l.point_skeleton.nodes.size()},
          {"segments", l.layout.segments.size()},
          {"surface_cell", l.surface_stats.cell},
          {"surface_vertices", l.traced_vertices},
          {"surface_faces", l.traced_faces},
          {"gaps_filled", l.filled_loops},
          {"normals_seconds", l.normals_seconds},
          {"skeleton_seconds", l.skeleton_seconds},
          {"surface_seconds", l.surface_seconds},
          {"layout_seconds", l.layout_seconds}};
}

}  // namespace

int cloud_encode(const CloudMapArgs& a) {
  const SdmPrecision precision = SdmPrecision::parse(a.precision);
  const Stopwatch clock;
  const CloudScene sc = cloud_scene(a);
  if (!a.png.empty()) throw InputError("--png draws a mesh's map; for a point cloud, decode the map and draw it with 'sdm render'");
  const EncodeOptions eo = cloud_encode_options(a);
  const Stopwatch encode_clock;
  EncodeStats st;
  CloudReach reach;
  const SdmImage im = encode_cloud(sc.cloud, sc.layout, eo, &st, &reach);
  const double encode_s = encode_clock.seconds();
  write_sdm_exr(im, a.out, precision);
  nlohmann::json j = scene_json(sc);
  j.update({{"output", a.out}, {"size", im.width}, {"texels", reach.texels}, {"reached", reach.share()},
            {"base_faces", st.base_faces}, {"encode_seconds", encode_s}, {"seconds", clock.seconds()}});
  if (a.json) {
    print_json(j);
  } else {
    std::cout << a.out << ": " << im.width << "x" << im.height << ", " << sc.layout.layout.segments.size() << " segments, "
              << st.base_faces << " base faces; the points reach " << std::round(1000 * reach.share()) / 10
              << " % of the texels (" << sc.layout.filled_loops << " gap(s) filled)\n"
              << "  skeleton " << sc.layout.skeleton_seconds << " s, surface " << sc.layout.surface_seconds << " s, layout "
              << sc.layout.layout_seconds << " s, encode " << encode_s << " s\n";
  }
  return 0;
}

int cloud_roundtrip(const CloudMapArgs& a) {
  if (!a.png.empty()) throw InputError("--png colours a round trip by its distance to the input mesh; for a point cloud, write the decoded mesh (-o) and draw it with 'sdm render'");
  const SdmPrecision precision = SdmPrecision::parse(a.precision);
  const Stopwatch clock;
  const CloudScene sc = cloud_scene(a);
  EncodeStats st;
  CloudReach reach;
  const SdmImage im = as_stored(encode_cloud(sc.cloud, sc.layout, cloud_encode_options(a), &st, &reach), precision);
  DecodeOptions d;
  d.level = a.lod;
  const Mesh out = decode_sdm(im, d);
  if (!a.out.empty()) write_mesh(out, a.out);
  const PointDistances pd = points_to_mesh(sc.cloud.points, out);
  const SurfaceTopology shape = topology_of(out);
  const int cycles = sc.layout.point_skeleton.cycles();
  // Handles the skeleton has not: sheets of the scan closer than the traced surface's cell, bridged.
  if (shape.genus > cycles)
    progress("warning: the decoded surface has " + std::to_string(shape.genus) + " handle(s), the skeleton " + std::to_string(cycles) +
             " cycle(s): the extra ones bridge sheets of the points closer than the surface's cell (" +
             std::to_string(sc.layout.surface_stats.cell) + "), e.g. fingers or parts that touch");
  nlohmann::json j = scene_json(sc);
  j.update({{"cloud", a.cloud}, {"size", a.size}, {"lod", a.lod}, {"reached", reach.share()}, {"faces", out.n_faces()},
            {"closed", shape.closed()}, {"genus", shape.genus}, {"skeleton_cycles", cycles}, {"points_rms", pd.rms / sc.diagonal},
            {"points_max", pd.max / sc.diagonal}, {"seconds", clock.seconds()}});
  std::ostringstream text;
  text << a.cloud << " at " << a.size << ", level " << a.lod << ": points to decoded surface RMS " << 100 * pd.rms / sc.diagonal
       << " %, max " << 100 * pd.max / sc.diagonal << " % of the diagonal; " << out.n_faces() << " faces, "
       << (shape.closed() ? "closed" : "NOT closed") << ", genus " << shape.genus << "; the points reach " << std::round(1000 * reach.share()) / 10
       << " % of the texels\n";
  double rms = pd.rms / sc.diagonal;
  if (!a.reference.empty()) {
    const Mesh ref = load_mesh_min_part(a.reference);
    const SurfaceDistance sd = surface_distance(ref, out, a.samples);
    rms = sd.rms / sd.diagonal;
    j["reference"] = a.reference;
    j["rms"] = rms;
    j["hausdorff"] = sd.hausdorff / sd.diagonal;
    text << "  against " << a.reference << ": RMS " << 100 * rms << " %, Hausdorff " << 100 * sd.hausdorff / sd.diagonal
         << " % of its diagonal\n";
  }
  if (a.json) print_json(j);
  else std::cout << text.str();
  if (a.max_rms >= 0 && rms > a.max_rms) {
    std::cerr << "sdm roundtrip: RMS " << rms << " exceeds --max-rms " << a.max_rms << std::endl;
    return 3;
  }
  return 0;
}

}  // namespace sdm::cli
