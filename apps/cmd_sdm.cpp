// sdm encode / decode / roundtrip: skeleton displacement maps.
#include "apps/cli_common.h"
#include "apps/cloud_maps.h"
#include "apps/commands.h"
#include "apps/memory_budget.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/pose/deform_decoded.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libsdm/pose/rig_skin.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/gltf_skin.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/self_intersections.h"
#include "libstm/render/render_mesh.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/mesh/validate_mesh.h"


#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace sdm::cli {
namespace {

// The layout encode and roundtrip use: the stages announced, the atlas size given, the default margin.
LayoutSource encode_layout_source(const std::string& layout_file, const std::string& skeleton_file, int size) {
  LayoutSource source;
  source.layout_file = layout_file;
  source.skeleton_file = skeleton_file;
  source.options.size = size;
  source.announce_stages = true;
  return source;
}

// False colour of D (blue near the axis, red far) where A = 1, grey where A = 0, black outside.
sdm::Image false_colour(const sdm::SdmImage& im) {
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

// --lod-segment ID=L
std::map<int, int> parse_segment_levels(const std::vector<std::string>& items) {
  std::map<int, int> out;
  for (const auto& s : items) {
    const auto eq = s.find('=');
    try {
      if (eq == std::string::npos) throw std::invalid_argument("");
      size_t a = 0, b = 0;
      const int id = std::stoi(s.substr(0, eq), &a);
      const int level = std::stoi(s.substr(eq + 1), &b);
      if (a != eq || b != s.size() - eq - 1) throw std::invalid_argument("");
      out[id] = level;
    } catch (const std::exception&) {
      throw sdm::InputError("--lod-segment '" + s + "' is not of the form ID=LEVEL (e.g. 3=1)");
    }
  }
  return out;
}

// What a decoded surface is: 2-manifold (usable by the pipeline again) and with how many boundary
// loops (those of an open input's holes; 0 for a closed one).
struct SurfaceTopology {
  bool manifold = false;
  int boundary_loops = 0;
  bool closed() const { return manifold && boundary_loops == 0; }
  std::string text() const {
    if (!manifold) return "NOT manifold";
    return boundary_loops ? "2-manifold with " + std::to_string(boundary_loops) + " boundary loop(s)" : "closed 2-manifold";
  }
};

SurfaceTopology topology_of(const sdm::Mesh& m) {
  const sdm::MeshReport r = sdm::validate_mesh(sdm::mesh_to_soup(m));
  return {r.usable(), r.boundary_loops};
}

constexpr const char* kPrecisionHelp =
    "Displacement precision in the file: float (32 bits), half (16 bits: 11 significant bits), or a number of bits "
    "from 4 to 11: the residual against the flat base mesh, quantised (the smallest file; docs/BENCHMARKS.md)";

// The bytes of the map as `sdm encode` would write it, and the map as a reader sees it: written to a
// temporary file next to nothing the user owns, read back, removed (also by a signal).
std::pair<sdm::SdmImage, uintmax_t> through_file(const sdm::SdmImage& im, sdm::SdmPrecision precision) {
  namespace fs = std::filesystem;
  const sdm::ScratchFile tmp((fs::temp_directory_path() / ("sdm-roundtrip-" + std::to_string(::getpid()) + ".exr")).string());
  sdm::write_sdm_exr(im, tmp.path(), precision);
  return {sdm::read_sdm_exr(tmp.path()), fs::file_size(tmp.path())};
}

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return s.str();
}

// The quality gate of encode and roundtrip. A surface that crosses itself has two sheets
// where a map holds one per ray (a Spot with its head pushed through its body encoded silently to
// 1.2 % RMS): named on stderr, refused under --strict.
sdm::SelfIntersections check_self_intersections(const sdm::Mesh& mesh, bool strict) {
  const sdm::SelfIntersections x = sdm::find_self_intersections(sdm::vertex_matrix(mesh), sdm::face_matrix(mesh));
  if (x.pairs == 0) return x;
  const std::string what = "the surface intersects itself (" + std::to_string(x.pairs) + " pairs of faces cross, e.g. faces " +
                           std::to_string(x.face_a) + " and " + std::to_string(x.face_b) + " at " + point_text(x.example) + ")";
  const std::string fix = "a displacement map holds one surface per ray, so crossing sheets cannot both be kept: separate them "
                          "in a modelling tool (e.g. Blender's 3D-Print toolbox, 'Intersect Faces')";
  if (strict) throw sdm::InputError(what + "; " + fix);
  progress("warning: " + what + ": " + fix + " (--strict refuses such input)");
  return x;
}

// The share of the input's surface (by vertex area) that the decoded surface carries within 1 % of
// the diagonal (diag: the input's). Under `floor` (--min-carried, 90 % by default): a warning, or a
// refusal under --strict.
constexpr double kCarriedTolerance = 0.01;
sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::Mesh& decoded, double diag, double floor, bool strict) {
  sdm::SurfaceCoverage c = sdm::surface_coverage(input, decoded, kCarriedTolerance * diag);
  if (c.share >= floor) return c;
  std::ostringstream what;
  what << "the map carries only " << std::round(1000 * c.share) / 10 << " % of the surface within "
       << 100 * kCarriedTolerance << " % of the diagonal (at least " << 100 * floor << " % expected); the farthest point, "
       << point_text(c.worst_point) << ", is " << std::round(1000 * c.worst / diag) / 10 << " % of the diagonal away";
  const std::string fix = "try a larger --size, or check the input for sheets inside each other or parts the skeleton misses "
                          "('sdm skeleton --png')";
  if (strict) throw sdm::InputError(what.str() + "; " + fix);
  progress("warning: " + what.str() + ": " + fix + " (--strict refuses such output)");
  return c;
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

// The encoder's check of its own map (EncodeOptions::flat_above; refine_above three times it).
void add_face_error_option(CLI::App* app, double& error) {
  app->add_option("--face-error", error,
                  "Base faces that decode (level 3) farther than this fraction of the diagonal from the input are placed on their flat "
                  "triangle, or the base mesh is made finer there (0: no check)")
      ->capture_default_str()
      ->check(number_in(0.0, 1.0));
}

void encode_check_options(sdm::EncodeOptions& eo, double face_error) {
  eo.flat_above = face_error;
  eo.refine_above = 3 * face_error;
}

void add_min_carried_option(CLI::App* app, double& floor) {
  app->add_option("--min-carried", floor,
                  "Share of the input's surface the decoded map must carry within 1 % of the diagonal; below it a warning, "
                  "or a refusal with --strict")
      ->capture_default_str()
      ->check(number_in(0.0, 1.0));
}

}  // namespace

Command add_encode_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, layout, skeleton, png, max_memory, precision = "10";  // BENCHMARKS: float's accuracy, 3.6-6.1x smaller at 1024
    int size = 1024;
    double min_part = 0, min_carried = 0.9, face_error = sdm::EncodeOptions().flat_above;
    bool fill_holes = false;
    bool json = false, strict = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "encode", "Encode a mesh (closed, or open with holes) as a skeleton displacement map: one OpenEXR file (channels Y = displacement, A = mask)\n"
                "with the layout and base mesh in its header, so 'sdm decode' needs nothing else.");
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf) or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_option("-o,--output", o->out, "Output map (.exr)")->required();
  app->add_option("--size", o->size, "Atlas size in texels")->capture_default_str()->check(number_in(16, 16384));
  app->add_option("--layout", o->layout, "Use this layout (from 'sdm stm') instead of computing one");
  app->add_option("--skeleton", o->skeleton, "Use this skeleton (from 'sdm skeleton') instead of extracting one");
  app->add_option("--png", o->png, "Also write a false-colour picture of the map (.png)");
  add_min_part_option(app, o->min_part);
  add_repair_options(app);
  add_fill_holes_option(app, o->fill_holes);
  add_max_memory_option(app, o->max_memory);
  app->add_option("--precision", o->precision, kPrecisionHelp)->capture_default_str();
  app->add_flag("--strict", o->strict,
                "Refuse (exit 2, nothing written) a self-intersecting input or a map that carries under --min-carried of the surface");
  add_min_carried_option(app, o->min_carried);
  add_face_error_option(app, o->face_error);
  app->add_flag("--json", o->json, "Print one JSON object with the summary");
  return {app, [o]() {
            if (o->layout.empty()) check_atlas_memory(o->size, 10, o->max_memory);
            if (sdm::is_point_cloud_file(o->mesh))
              return cloud_encode({o->mesh, o->out, o->png, o->precision, "", o->size, 3, 0, o->face_error, -1, o->json});
            const sdm::SdmPrecision precision = sdm::SdmPrecision::parse(o->precision);
            sdm::Stopwatch clock;
            const sdm::Mesh mesh = load_mesh_min_part(o->mesh, o->min_part, o->fill_holes);
            const sdm::SelfIntersections crossings = check_self_intersections(mesh, o->strict);
            const sdm::Layout layout = layout_for(mesh, encode_layout_source(o->layout, o->skeleton, o->size)).layout;
            const double layout_s = clock.lap();
            sdm::EncodeStats st;
            sdm::EncodeOptions eo;
            eo.progress = [](const std::string& s) { progress("  " + s); };
            eo.fill_unread = !o->png.empty();  // only the picture shows texels no face reads
            encode_check_options(eo, o->face_error);
            const sdm::SdmImage im = sdm::encode_sdm(mesh, layout, eo, &st);
            const double encode_s = clock.lap();
            progress("  checking the map (decoded at level 3)");
            const double diag = sdm::bounding_box_diagonal(mesh);
            const sdm::SurfaceCoverage carried =
                check_carried(mesh, sdm::decode_sdm(sdm::as_stored(im, precision), sdm::DecodeOptions{}), diag, o->min_carried, o->strict);
            const double check_s = clock.lap();
            sdm::write_sdm_exr(im, o->out, precision);
            if (!o->png.empty()) sdm::write_png(false_colour(im), o->png);
            const double own = st.texels ? double(st.own_hits) / st.texels : 0.0;
            if (o->json) {
              print_json({{"output", o->out}, {"size", im.width}, {"segments", layout.segments.size()},
                          {"texels", st.texels}, {"own_hits", st.own_hits}, {"other_hits", st.other_hits},
                          {"filled", st.filled}, {"base_faces", st.base_faces}, {"flat_faces", st.flat_faces}, {"layout_seconds", layout_s},
                          {"encode_seconds", encode_s}, {"check_seconds", check_s}, {"carried", carried.share},
                          {"carried_rms", carried.rms / diag}, {"self_intersections", crossings.pairs}});
            } else {
              std::cout << o->out << ": " << im.width << "x" << im.height << ", " << layout.segments.size() << " segments, "
                        << st.base_faces << " base faces, " << std::round(1000 * own) / 10 << " % of segment texels on their own surface\n"
                        << "  carries " << std::round(1000 * carried.share) / 10 << " % of the surface within "
                        << 100 * kCarriedTolerance << " % of the diagonal at level 3 (RMS "
                        << 100 * carried.rms / diag << " %)\n"
                        << "  layout " << layout_s << " s, encode " << encode_s << " s, check " << check_s << " s\n";
            }
            return 0;
          }};
}

namespace {

// --rig writes a skin, which only glTF carries: InputError for another output format.
void check_rig_output(const std::string& out) {
  std::string ext = std::filesystem::path(out).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".glb" && ext != ".gltf")
    throw sdm::InputError("--rig writes a glTF skin: the output must be .glb or .gltf, not '" + out + "'");
}

// Writes `mesh` (decoded at rest, `trace` its decode's) to `out` rigged by rig_skin: the bind pose
// is the map's own skeleton; `posed`, when given, is the pose the file opens in.
void write_rigged(const sdm::Mesh& mesh, const sdm::Layout& layout, const sdm::DecodeTrace& trace, const sdm::Skeleton* posed,
                  const std::string& out) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) points.push_back(sdm::point(mesh, v));
  if (posed && std::any_of(posed->segment_radius_scale.begin(), posed->segment_radius_scale.end(), [](double f) { return f != 1.0; }))
    std::cerr << "warning: --rig writes a glTF skin, which carries joint motions only: the radius scales are left out of "
              << out << " (write a mesh without --rig to keep them)\n";
  sdm::write_gltf_skinned(mesh, sdm::rig_skin(layout, points, trace.vertex_segment, sdm::face_matrix(mesh), posed), out);
}

}  // namespace

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
            const sdm::DecodeEstimate e = sdm::estimate_decode(im, d);
            check_memory(e.bytes, o->max_memory, "decoding " + std::to_string(int64_t(e.triangles / 1e6)) + " million triangles",
                         "use a lower --lod (each level quadruples the triangles)");
            if (!o->skeleton.empty()) d.skeleton = sdm::read_skeleton_json(o->skeleton);
            std::optional<sdm::Skeleton> posed;
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
              if (o->write_skeleton.size() > 4 && o->write_skeleton.substr(o->write_skeleton.size() - 4) == ".obj")
                sdm::write_skeleton_obj(sk, o->write_skeleton);
              else
                sdm::write_skeleton_json(sk, o->write_skeleton);
            }
            if (o->json) {
              print_json({{"output", o->out}, {"vertices", mesh.n_vertices()}, {"faces", mesh.n_faces()},
                          {"closed", top.closed()}, {"manifold", top.manifold}, {"boundary_loops", top.boundary_loops}, {"seconds", s}});
            } else {
              std::cout << o->out << ": " << mesh.n_vertices() << " vertices, " << mesh.n_faces() << " faces, "
                        << top.text() << ", " << s << " s\n";
            }
            return 0;
          }};
}

namespace {

// A whole number, or InputError naming the option and its expected form.
int parse_index(const std::string& text, const std::string& what) {
  size_t used = 0;
  int i = -1;
  try {
    i = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw sdm::InputError(what);
  return i;
}

double parse_number(const std::string& text, const std::string& what) {
  size_t used = 0;
  double x = NAN;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(x)) throw sdm::InputError(what);
  return x;
}

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
void apply_rotate(const sdm::Skeleton& rest, sdm::Skeleton& posed, const std::string& item) {
  const std::string form = "--rotate '" + item + "' is not of the form NODE=AX,AY,AZ,DEG, NODE=x|y|z,DEG or NODE=twist,DEG";
  const auto eq = item.find('=');
  if (eq == std::string::npos) throw sdm::InputError(form);
  const int node = parse_index(item.substr(0, eq), form);
  if (node < 0 || size_t(node) >= rest.nodes.size())
    throw sdm::InputError("--rotate names node " + std::to_string(node) + " but the skeleton has " + std::to_string(rest.nodes.size()) +
                          " nodes (0.." + std::to_string(rest.nodes.size() - 1) + "; see --write-skeleton)");
  const std::vector<std::string> parts = split(item.substr(eq + 1), ',');
  Eigen::Vector3d axis;
  if (parts.size() == 4) {
    for (int k = 0; k < 3; ++k) axis[k] = parse_number(parts[size_t(k)], form);
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
  const double degrees = parse_number(parts.back(), form);
  sdm::rotate_subtree(rest, posed, node, Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized())));
}

// One --scale-radius SEG=F: the factor multiplies the segment's (repeated options compose).
void apply_scale(sdm::Skeleton& posed, const std::string& item) {
  const std::string form = "--scale-radius '" + item + "' is not of the form SEGMENT=FACTOR (e.g. 3=1.2)";
  const auto eq = item.find('=');
  if (eq == std::string::npos) throw sdm::InputError(form);
  const int seg = parse_index(item.substr(0, eq), form);
  const double f = parse_number(item.substr(eq + 1), form);
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
            sdm::Skeleton posed = rest;
            if (!o->skeleton.empty()) {
              posed = sdm::read_skeleton_json(o->skeleton);
              posed.vertex_node = rest.vertex_node;
              sdm::pose_skeleton(rest, posed);  // the graph checked before the work
            }
            for (const auto& r : o->rotate) apply_rotate(rest, posed, r);
            for (const auto& s : o->scale) apply_scale(posed, s);
            sdm::DecodeOptions d;
            d.level = o->lod;
            const sdm::DecodeEstimate e = sdm::estimate_decode(im, d);
            check_memory(e.bytes, o->max_memory, "decoding " + std::to_string(int64_t(e.triangles / 1e6)) + " million triangles",
                         "use a lower --lod (each level quadruples the triangles)");
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
            if (!o->write_skeleton.empty()) sdm::write_skeleton_json(posed, o->write_skeleton);
            const double diag = sdm::bounding_box_diagonal(mesh);
            const double s = clock.seconds();
            if (o->json) {
              nlohmann::json j = pose_summary(rest, sdm::pose_skeleton(rest, posed), diag);
              j["output"] = o->out;
              j["vertices"] = mesh.n_vertices();
              j["faces"] = mesh.n_faces();
              j["max_displacement"] = moved;
              j["max_displacement_diagonal"] = diag > 0 ? moved / diag : 0.0;
              j["closed"] = top.closed();
              j["seconds"] = s;
              print_json(j);
            } else {
              std::cout << o->out << ": " << mesh.n_vertices() << " vertices, " << mesh.n_faces() << " faces, " << top.text()
                        << ", largest displacement " << moved << " (" << 100 * moved / diag << " % of the diagonal), " << s << " s\n";
            }
            return 0;
          }};
}

Command add_roundtrip_command(CLI::App& parent) {
  struct Opts {
    std::string mesh, out, png, precision = "10", reference;
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
  app->add_option("mesh", o->mesh, "Input mesh (.obj, .off, .ply, .stl, .glb, .gltf) or point cloud (.xyz, .pcd, .ply or .off without faces)")->required();
  app->add_option("--reference", o->reference,
                  "For a point cloud: also measure the decoded surface against this mesh (RMS and Hausdorff both ways); the points "
                  "themselves are measured one way, each to the decoded surface");
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
            if (sdm::is_point_cloud_file(o->mesh))
              return cloud_roundtrip({o->mesh, o->out, o->png, o->precision, o->reference, o->size, o->lod, o->samples, o->face_error,
                                      o->max_rms, o->json});
            if (!o->reference.empty()) throw sdm::InputError("--reference is for a point cloud; a mesh is its own reference");
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

Command add_compare_command(CLI::App& parent) {
  struct Opts {
    std::string reference, other;
    int samples = 100000;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "compare", "Measure how far a mesh lies from a reference mesh, as 'sdm roundtrip' does: symmetric Hausdorff and\n"
                 "RMS distance by dense sampling (exact closest points), as fractions of the reference's bounding-box\n"
                 "diagonal. For comparing any other tool's output (a Draco decode, a decimation) with sdm's.");
  app->add_option("reference", o->reference, "Reference mesh (.obj, .off, .ply, .stl, .glb, .gltf)")->required();
  app->add_option("other", o->other, "Mesh to measure against it")->required();
  app->add_option("--samples", o->samples, "Points sampled on each surface")->capture_default_str()->check(number_in(1000, 1e7));
  app->add_flag("--json", o->json, "Print one JSON object");
  add_repair_options(app);
  return {app, [o]() {
            const sdm::Mesh a = load_mesh_min_part(o->reference), b = load_mesh_min_part(o->other);
            const sdm::SurfaceDistance d = sdm::surface_distance(a, b, o->samples);
            const double rms = d.rms / d.diagonal, hd = d.hausdorff / d.diagonal;
            if (o->json)
              print_json({{"reference", o->reference}, {"other", o->other}, {"rms", rms}, {"hausdorff", hd},
                          {"mean", d.mean / d.diagonal}, {"samples", o->samples}});
            else
              std::cout << o->other << " against " << o->reference << ": RMS " << 100 * rms << " %, Hausdorff " << 100 * hd
                        << " % of the diagonal\n";
            return 0;
          }};
}

}  // namespace sdm::cli
