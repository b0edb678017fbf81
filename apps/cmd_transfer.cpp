#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/decoded_mesh.h"
#include "apps/options.h"
#include "apps/transfer_setup.h"
#include "apps/view_up.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/core/parallel.h"
#include "libstm/correspondence/correspondence_file.h"
#include "libstm/correspondence/small_parts.h"
#include "libstm/layout/layout_json.h"
#include "libstm/registration/correspondence_jumps.h"
#include "libstm/transfer/carry_attributes.h"
#include "libstm/transfer/transfer_texture.h"
#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"
#include "libstm/render/render_mesh.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

namespace sdm::cli {

namespace {

struct TransferArgs {
  std::string source, texture, target, output, source_skeleton, target_skeleton, sdm, correspondence, vertex_colors;
  std::string max_memory;
  sdm::cli::TransferSettings settings;  // size, margin, --match, --force (the skeletons given are set on running)
  int lod = 3;
  bool json = false;
  std::string up, source_up, target_up;  // --up for both, or each its own
  bool strict = false;  // --strict: a small separate part refuses the pair instead of being left out
};

// The match's chains as JSON objects: source and target key nodes, and lengths.
nlohmann::json match_chains(const sdm::SkeletonMatch& m) {
  nlohmann::json chains = nlohmann::json::array();
  for (size_t c = 0; c < m.a.chains.size(); ++c) {
    const auto& ca = m.a.chains[c];
    const auto& cb = m.b.chains[m.chain_a_to_b[c].first];
    const bool rev = m.chain_a_to_b[c].second;
    const int t0 = m.b.keys[rev ? cb.to : cb.from], t1 = m.b.keys[rev ? cb.from : cb.to];
    chains.push_back({{"source", {m.a.keys[ca.from], m.a.keys[ca.to]}},
                      {"target", {t0, t1}},
                      {"source_length", ca.length},
                      {"target_length", cb.length}});
  }
  return chains;
}

// The summary's chains (match_chains) as text lines.
std::string chains_text(const nlohmann::json& chains) {
  std::ostringstream out;
  for (const auto& c : chains)
    out << "  chain " << c["source"][0] << "-" << c["source"][1] << " (length " << c["source_length"].get<double>() << ") -> "
        << c["target"][0] << "-" << c["target"][1] << " (length " << c["target_length"].get<double>() << ")\n";
  return out.str();
}

// The geometry counterpart: the map decoded around a target skeleton with the same branching.
int run_sdm_transfer(const TransferArgs& o) {
  if (!o.source.empty() || !o.target.empty())
    throw sdm::InputError("--sdm decodes a map around --target-skeleton; --source and --target belong to the texture transfer");
  if (o.target_skeleton.empty()) throw sdm::InputError("--sdm needs --target-skeleton SKEL.json (the skeleton to decode around)");
  const sdm::SdmImage im = sdm::read_sdm_exr(o.sdm);
  const sdm::Skeleton graph = sdm::layout_from_json(im.layout).skeleton;
  const sdm::Skeleton target = sdm::read_skeleton_json(o.target_skeleton, json_budget(o.max_memory, o.target_skeleton));
  sdm::SkeletonMatch m;
  sdm::DecodeOptions d;
  d.level = o.lod;
  check_decode_memory(im, d, o.max_memory);
  d.skeleton = sdm::skeleton_onto_graph(graph, target, parse_node_pairs(o.settings.match), &m);
  const sdm::Mesh mesh = sdm::decode_sdm(im, d);
  sdm::write_mesh(mesh, o.output);
  // One summary: --json prints it, the text reads it.
  const nlohmann::json j = {{"output", o.output}, {"vertices", mesh.n_vertices()}, {"faces", mesh.n_faces()},
                            {"confidence", m.confidence}, {"candidates", m.candidates}, {"chains", match_chains(m)}};
  if (o.json) {
    print_json(j);
  } else {
    std::cout << o.output << ": " << j["vertices"] << " vertices decoded from " << o.sdm << " around " << o.target_skeleton
              << "\n  match confidence " << j["confidence"].get<double>() << " (" << j["candidates"] << " candidates)\n"
              << chains_text(j["chains"]);
  }
  return 0;
}

// The texture transfer's inputs, read and checked.
// A target vertex whose source point lies farther than this fraction of the source's diagonal from
// most of its neighbours' jumps (a speck); a warning when their area passes kJumpWarning of the target's.
constexpr double kJumpDistance = 0.05, kJumpWarning = 0.001;

struct TransferInputs {
  sdm::Mesh source, target;
  sdm::Image texture;                         // empty until painted when the source has colours only
  std::string texture_path;                   // empty when the texture is painted from the source's colours
  std::vector<Eigen::Vector3f> source_colors;  // per source vertex, when its file has vertex colours
  sdm::Skeleton skeleton_a, skeleton_b;
  sdm::SkeletonStats stats_a, stats_b;  // of the extractions (empty for a skeleton given as a file)
  // The models as read, and their main parts (small_parts.h): `source` and `target` are the main
  // parts, the correspondence written is onto and over the models as read.
  sdm::Mesh source_input, target_input;
  sdm::MainParts source_parts, target_parts;
};

// Leaves a model's small separate parts out of the matching (small_parts.h), with a warning, or
// refuses them with --strict; not for a model whose skeleton was given (it numbers every vertex).
void leave_out_small_parts(const TransferArgs& o, TransferInputs& in) {
  auto one = [&](sdm::Mesh& mesh, sdm::Mesh& input, sdm::MainParts& parts, bool given, const std::string& path) {
    if (given) return;
    parts = sdm::main_parts(mesh, path, o.strict, progress);
    if (!parts.reduced()) return;
    input = std::move(mesh);
    mesh = parts.mesh;
  };
  one(in.source, in.source_input, in.source_parts, !o.source_skeleton.empty(), o.source);
  one(in.target, in.target_input, in.target_parts, !o.target_skeleton.empty(), o.target);
  if (in.source_parts.reduced() && !in.source_colors.empty()) {
    std::vector<Eigen::Vector3f> kept;
    for (int v : in.source_parts.vertex_of) kept.push_back(in.source_colors[size_t(v)]);
    in.source_colors = std::move(kept);
  }
}

// The correspondence over the target as read, onto the source as read.
std::vector<sdm::SourcePoint> input_correspondence(const TransferInputs& in, const std::vector<sdm::SourcePoint>& c) {
  std::vector<sdm::SourcePoint> onto = in.source_parts.reduced() ? sdm::onto_input_source(in.source_parts, in.source_input, c) : c;
  return in.target_parts.reduced() ? sdm::onto_input_target(in.target_parts, in.target_input, onto) : onto;
}

// Throws InputError for a missing --source or --target, or an output, --correspondence or
// --vertex-colors path of the wrong kind: before any work.
void check_output_paths(const TransferArgs& o) {
  if (o.source.empty() || o.target.empty())
    throw sdm::InputError("transfer needs --source and --target (texture), or --sdm and --target-skeleton (geometry)");
  if (!has_extension(o.output, {".obj", ".glb", ".gltf"}))
    throw sdm::InputError("--output must be an .obj file (it carries the uv and names the atlas) or a .glb/.gltf file (the atlas embedded)");
  if (!o.correspondence.empty() && !has_extension(o.correspondence, {".txt", ".json"}))
    throw sdm::InputError("--correspondence must name a .txt or .json file, not '" + o.correspondence + "'");
  if (!o.vertex_colors.empty() && !has_extension(o.vertex_colors, {".ply"}))
    throw sdm::InputError("--vertex-colors must name a .ply file (the target with a colour per vertex), not '" + o.vertex_colors + "'");
}

// Throws InputError for a source with neither texture and uv nor vertex colours (a source with
// colours only has its texture painted from them once the GL context exists).
TransferInputs read_inputs(const TransferArgs& o) {
  check_output_paths(o);
  TransferInputs in;
  sdm::LoadedMesh loaded = load_input(o.source);
  const std::string material = loaded.texture;
  sdm::Image embedded = std::move(loaded.texture_image);  // a glTF source's own texture
  in.source = std::move(loaded.mesh);
  in.source_colors = std::move(loaded.colors);
  in.texture_path = o.texture.empty() ? material : o.texture;
  const bool colored = !in.source_colors.empty();
  if (in.texture_path.empty() && !embedded.pixels.empty() && in.source.has_halfedge_texcoords2D()) {
    in.texture = std::move(embedded);
    in.texture_path = o.source + " (embedded)";
  } else if (!colored || (!in.texture_path.empty() && in.source.has_halfedge_texcoords2D())) {
    if (in.texture_path.empty())
      throw sdm::InputError("'" + o.source + "' names no texture in its material and has no vertex colours: pass --texture TEX.png");
    if (!in.source.has_halfedge_texcoords2D())
      throw sdm::InputError("'" + o.source + "' has no texture coordinates (nor vertex colours), so its texture cannot be transferred");
    in.texture = sdm::read_png(in.texture_path, image_budget(o.max_memory, in.texture_path));
  } else {
    in.texture_path.clear();
  }
  in.target = load_mesh_min_part(o.target);
  leave_out_small_parts(o, in);
  // Both skeletons at once (obtain_both_skeletons); each line says whose it is.
  const sdm::Progress shared = sdm::serialised(progress);
  auto labelled = [&](const std::string& what) -> sdm::Progress {
    return [shared, what](const std::string& line) { shared(line.rfind("extracting", 0) == 0 ? line : what + ": " + line); };
  };
  auto source = [&] { in.skeleton_a = skeleton_for(in.source, o.source_skeleton, "source", &in.stats_a, labelled("source"),
                                                   json_budget(o.max_memory, o.source_skeleton)); };
  auto target = [&] { in.skeleton_b = skeleton_for(in.target, o.target_skeleton, "target", &in.stats_b, labelled("target"),
                                                   json_budget(o.max_memory, o.target_skeleton)); };
  obtain_both_skeletons(in.source.n_vertices() + in.target.n_vertices(), source, target);
  return in;
}

// The up of the source and of the target: --source-up / --target-up, else --up, else the file's
// own (glTF), else unknown.
std::pair<ViewUp, ViewUp> preview_ups(const TransferArgs& o) {
  return {view_up(o.source_up.empty() ? o.up : o.source_up, o.source, o.source_up.empty() ? "--up" : "--source-up"),
          view_up(o.target_up.empty() ? o.up : o.target_up, o.target, o.target_up.empty() ? "--up" : "--target-up")};
}

// How a model of the preview is seen: in its own principal frame (principal_view_frame), looked at
// along its shortest axis square to up (a person from the front or back, Spot from its side), up
// its known up, else guessed: a model lying down (TOSCA's lie along z) stood up along its longest
// axis, any other with +y up.
Eigen::Matrix3d preview_frame(const sdm::Mesh& mesh, const ViewUp& up) {
  return sdm::principal_view_frame(mesh, up.known() ? std::optional<Eigen::Vector3d>(up.axis) : std::nullopt);
}

// Source (its own texture) and target (the transferred atlas) side by side, 512 x 512 each, each
// seen upright (preview_frame).
sdm::Image render_preview(sdm::GlContext& gl, const TransferInputs& in, const sdm::TextureTransfer& r, const TransferArgs& o) {
  progress("rendering the preview");
  const auto [source_up, target_up] = preview_ups(o);
  sdm::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.azimuth_deg = ro.elevation_deg = 0;
  ro.texture = &in.texture;
  ro.frame = preview_frame(in.source, source_up);
  const sdm::Image left = sdm::render_mesh(gl, in.source, ro);
  ro.texture = &r.atlas;
  ro.frame = preview_frame(r.target, target_up);
  const sdm::Image right = sdm::render_mesh(gl, r.target, ro);
  return sdm::side_by_side({left, right});
}

// The output files' paths: OUT.obj (write_mesh puts its OUT.mtl beside it), OUT_atlas.png and
// OUT_preview.png beside it; the optional --correspondence and --vertex-colors files.
struct OutputPaths {
  std::string mesh, atlas, preview, correspondence, vertex_colors;
  explicit OutputPaths(const TransferArgs& o)
      : mesh(o.output),
        atlas(sibling(o.output, "_atlas.png")),
        preview(sibling(o.output, "_preview.png")),
        correspondence(o.correspondence),
        vertex_colors(o.vertex_colors) {}
};

// A source with vertex colours and no texture: its colours painted into an atlas over its own STM
// (the transfer's size and margin), so it can be transferred like a textured one.
void paint_source_texture(sdm::GlContext& gl, const TransferArgs& o, TransferInputs& in) {
  progress("the source has vertex colours and no texture: painting them into its own STM atlas");
  sdm::TexturedMesh t =
      sdm::texture_from_vertex_colors(gl, in.source, in.source_colors, in.skeleton_a, o.settings.size, o.settings.margin);
  in.source = std::move(t.mesh);
  in.texture = std::move(t.texture);
}

// The target's vertex colours: the source's vertex colours blended at each target vertex's source
// point, or, for a source without them, its texture sampled there.
std::vector<Eigen::Vector3f> target_vertex_colors(const TransferInputs& in, const sdm::TextureTransfer& r) {
  progress("carrying the source's " + std::string(in.source_colors.empty() ? "texture" : "vertex colours") + " onto the target's vertices");
  return in.source_colors.empty() ? sdm::carry_texture_colors(in.source, in.texture, r.correspondence)
                                  : sdm::carry_vertex_colors(in.source, in.source_colors, r.correspondence);
}

// Everything is computed; now the files, each to its temporary name: the command's OutputCommit
// (main.cpp) renames them together once it returns, and removes them if a later one fails.
void write_outputs(const TransferInputs& in, const sdm::TextureTransfer& r, const sdm::Image& preview, const OutputPaths& out,
                   const std::vector<Eigen::Vector3f>& vertex_colors) {
  if (!out.correspondence.empty())
    sdm::write_text_file(out.correspondence, sdm::correspondence_text(input_correspondence(in, r.correspondence),
                                                                      has_extension(out.correspondence, {".json"})));
  if (!out.vertex_colors.empty()) sdm::write_colored_ply(r.target, vertex_colors, out.vertex_colors);
  sdm::write_png(r.atlas, out.atlas);
  sdm::write_png(preview, out.preview);
  sdm::write_mesh(r.target, out.mesh, std::filesystem::absolute(out.atlas).string());
}

// x, or null when it is not finite (a stage that was not tried).
nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

// Per branch of a registered transfer: its source key nodes and how closely it fits.
nlohmann::json branch_fit_json(const std::vector<sdm::BranchFit>& fits) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& b : fits) a.push_back({{"source", {b.source_from, b.source_to}}, {"rms", b.rms}, {"p99", b.p99}, {"vertices", b.vertices}});
  return a;
}

// The result as one JSON object (node numbers as in the given skeletons): what --json prints and
// the text (print_transfer_text) reads.
nlohmann::json transfer_summary(const TransferArgs& o, const TransferInputs& in, const sdm::TextureTransfer& r, const OutputPaths& out,
                                const sdm::CorrespondenceJumps& jumps) {
  const sdm::SkeletonMatch m = sdm::match_in_given_numbering(r.skeletons);
  nlohmann::json chains = match_chains(m);
  for (size_t c = 0; c < chains.size(); ++c) chains[c]["segments"] = r.skeletons.chain_edges[c].size();
  nlohmann::json keys = nlohmann::json::array();
  for (size_t k = 0; k < m.a.keys.size(); ++k)
    keys.push_back({{"source", m.a.keys[k]}, {"target", m.b.keys[m.key_a_to_b[k]]}, {"degree", m.a.key_degree[k]}});
  return {{"output", out.mesh},
              {"source", o.source},
              {"target_vertices", in.target.n_vertices()},
              {"atlas", out.atlas},
              {"preview", out.preview},
              {"texture", in.texture_path.empty() ? nlohmann::json() : nlohmann::json(in.texture_path)},
              {"size", r.layout_a.size},
              {"segments", r.layout_a.segments.size()},
              {"confidence", m.confidence},
              {"shape_cost", m.cost},
              {"candidates", m.candidates},
              {"keys", keys},
              {"chains", chains},
              {"pruned_source_ends", r.skeletons.pruned_a},
              {"pruned_target_ends", r.skeletons.pruned_b},
              {"slid_source_branches", r.skeletons.slid_a},
              {"slid_target_branches", r.skeletons.slid_b},
              {"branch_length_disagreement", r.skeletons.length_disagreement},
              // node numbers of a model registered with its other extraction candidate refer to that candidate
              {"ambiguous_match", r.ambiguity.empty() ? nlohmann::json() : nlohmann::json(r.ambiguity)},
              {"other_skeleton_candidate", {{"source", r.other_source_candidate}, {"target", r.other_target_candidate}}},
              {"extremity_distortion", r.distortion},
              {"candidate_twist", r.candidate_twist},
              {"candidate_distortion", r.candidate_distortion},
              {"candidate_attachment", r.candidate_attachment},
              {"candidate_bend", r.candidate_bend},
              {"attachment_misfit", r.attachment},
              {"target_skeleton", target_skeleton_name(r.kind, !o.target_skeleton.empty())},
              {"bent_rms", finite_or_null(r.kind == sdm::CorrespondenceKind::bent ? r.fit_rms : INFINITY)},
              {"fit_rms", finite_or_null(r.fit_rms)},
              {"fit_p99", finite_or_null(r.fit_p99)},
              {"refined", r.refined},
              {"branch_fit", branch_fit_json(r.branch_fit)},
              {"correspondence", o.correspondence.empty() ? nlohmann::json() : nlohmann::json(o.correspondence)},
              {"vertex_colors", o.vertex_colors.empty() ? nlohmann::json() : nlohmann::json(o.vertex_colors)},
              {"vertex_colors_from", o.vertex_colors.empty()       ? nlohmann::json()
                                     : in.source_colors.empty() ? nlohmann::json("texture")
                                                                : nlohmann::json("vertex colours")},
              {"registration_rms", finite_or_null(r.registration.rms)},
              {"registration_p99", finite_or_null(r.registration.p99)},
              {"stretch", r.stretch},
              {"seam_faces", r.seam_faces},
              {"jumping_share", r.correspondence.empty() ? nlohmann::json() : nlohmann::json(jumps.area_share)},
              {"jumping_vertices", r.correspondence.empty() ? nlohmann::json() : nlohmann::json(jumps.vertices)}};
}

// The summary (transfer_summary) as text.
void print_transfer_text(const nlohmann::json& j) {
  auto pc = [](const nlohmann::json& x) { return x.is_null() ? NAN : 100 * x.get<double>(); };  // null: not measured
  std::cout << j["output"].get<std::string>() << ": " << j["target_vertices"] << " vertices textured from " << j["source"].get<std::string>()
            << (j["texture"].is_null() ? " (its vertex colours)" : "") << "\n"
            << "  atlas " << j["atlas"].get<std::string>() << " (" << j["size"] << "^2, " << j["segments"] << " segments), preview "
            << j["preview"].get<std::string>() << "\n";
  if (!j["vertex_colors"].is_null())
    std::cout << "  vertex colours " << j["vertex_colors"].get<std::string>() << " (from the source's "
              << j["vertex_colors_from"].get<std::string>() << ")\n";
  if (!j["correspondence"].is_null()) std::cout << "  correspondence " << j["correspondence"].get<std::string>() << "\n";
  std::cout << "  match confidence " << j["confidence"].get<double>() << " (" << j["candidates"] << " candidates)\n";
  const std::string kind = j["target_skeleton"];
  if (kind == "carried")
    std::cout << "  the target is the source's shape (registered to " << pc(j["registration_rms"])
              << " % of the diagonal, RMS): the source's skeleton carried over\n";
  if (kind == "bent")
    std::cout << "  the target is the source in another pose (bent onto it to " << pc(j["fit_rms"])
              << " % of the diagonal, RMS): the source's skeleton bent along\n";
  if (kind == "registered") {
    std::cout << "  the target is another body with the same branching: the source registered onto it along its skeleton, "
              << pc(j["fit_rms"]) << " % of the diagonal (RMS), 99th percentile " << pc(j["fit_p99"]) << " %\n";
    const bool other_source = j["other_skeleton_candidate"]["source"], other_target = j["other_skeleton_candidate"]["target"];
    if (other_source || other_target)
      std::cout << "    with the other extraction candidate of the " << sdm::other_candidates_named(other_source, other_target)
                << " (the registration with the kept ones was refused or marginal; node numbers below are that candidate's)\n";
    for (const auto& b : j["branch_fit"])
      std::cout << "    branch " << b["source"][0] << "-" << b["source"][1] << ": RMS " << pc(b["rms"]) << " %, 99th percentile "
                << pc(b["p99"]) << " %\n";
  }
  for (const auto& k : j["keys"]) std::cout << "  node " << k["source"] << " -> " << k["target"] << " (degree " << k["degree"] << ")\n";
  std::cout << chains_text(j["chains"]);
}

// The texture transfer: inputs, transfer_texture, preview, files, report.
int run_texture_transfer(const TransferArgs& o) {
  check_atlas_memory(o.settings.size, 60, o.max_memory);
  preview_ups(o);  // a bad axis named before the work
  TransferInputs in = read_inputs(o);
  sdm::GlContext gl;
  progress("GL renderer: " + gl.renderer() + " (" + gl.version() + ", " + gl.platform() + ")");
  if (in.texture.pixels.empty()) paint_source_texture(gl, o, in);
  TransferSettings settings = o.settings;
  settings.source_skeleton_given = !o.source_skeleton.empty();
  settings.target_skeleton_given = !o.target_skeleton.empty();
  const sdm::TransferOptions to = transfer_command_options(settings, in.source, in.target, in.stats_a, in.stats_b, progress);
  const sdm::TextureTransfer r = sdm::transfer_texture(gl, in.source, in.texture, in.skeleton_a, in.target, in.skeleton_b, to);
  if ((!o.correspondence.empty() || !o.vertex_colors.empty()) && r.correspondence.empty())
    throw sdm::InputError(std::string(o.correspondence.empty() ? "--vertex-colors" : "--correspondence") +
                          ": the target was matched by its skeleton alone (its skeleton was given with --target-skeleton, or its "
                          "genus differs from the source's), so no point correspondence was computed. Fix: leave out "
                          "--target-skeleton so that the source is registered onto the target");
  if (!r.ambiguity.empty())
    progress("warning: left and right (or front and back) may be swapped (--force was given): " + r.ambiguity);
  const bool registered = r.kind == sdm::CorrespondenceKind::registered;
  if (registered && r.attachment > to.registered_attachment)
    progress("warning: the skeletons' branches meet the core at other places on the two models (--force was given): limbs may "
             "land on other limbs");
  if (registered && !(r.fit_rms <= to.registered_rms && r.fit_p99 <= to.registered_p99))
    progress("warning: the source fits the target poorly (--force was given): the texture may be misplaced");
  for (const auto& b : r.branch_fit)
    if (b.p99 > to.registered_p99)
      progress("warning: the source's branch " + std::to_string(b.source_from) + "-" + std::to_string(b.source_to) + " lies up to " +
               std::to_string(100 * b.p99) + " % of the diagonal from the target (99th percentile): its texture may be misplaced");
  for (int x : r.skeletons.pruned_a) progress("source end branch at node " + std::to_string(x) + " pruned: the target's skeleton has none there");
  for (int x : r.skeletons.pruned_b) progress("target end branch at node " + std::to_string(x) + " pruned: the source's skeleton has none there");
  for (const auto& [node, from, to] : r.skeletons.slid_a)
    progress("source branch at node " + std::to_string(node) + " moved from junction " + std::to_string(from) + " to junction " +
             std::to_string(to) + ": the matched branches disagreed in length");
  for (const auto& [node, from, to] : r.skeletons.slid_b)
    progress("target branch at node " + std::to_string(node) + " moved from junction " + std::to_string(from) + " to junction " +
             std::to_string(to) + ": the matched branches disagreed in length");
  // Specks: target vertices whose source point lies over 5 % of the diagonal from most neighbours'.
  const sdm::CorrespondenceJumps jumps =
      r.correspondence.empty() ? sdm::CorrespondenceJumps{}
                               : sdm::correspondence_jumps(in.source, in.target, r.correspondence, kJumpDistance * sdm::bounding_box_diagonal(in.source));
  if (jumps.area_share > kJumpWarning)
    progress("warning: " + std::to_string(100 * jumps.area_share) + " % of the target's area (" + std::to_string(jumps.vertices) +
             " vertices, e.g. vertex " + std::to_string(jumps.example) +
             ") shows source points that jump away from their neighbours': specks of another part's texture");
  const std::vector<Eigen::Vector3f> colors = o.vertex_colors.empty() ? std::vector<Eigen::Vector3f>() : target_vertex_colors(in, r);
  const sdm::Image preview = render_preview(gl, in, r, o);
  const OutputPaths out(o);
  write_outputs(in, r, preview, out, colors);
  const nlohmann::json summary = transfer_summary(o, in, r, out, jumps);
  if (o.json) print_json(summary);
  else print_transfer_text(summary);
  return 0;
}

// The command's options, bound to o.
void declare_options(CLI::App* app, TransferArgs& o) {
  app->add_option("--source", o.source,
                  "Source mesh with uv and a texture (.obj with its MTL, .glb/.gltf with its base colour texture), or with vertex\n"
                  "colours (e.g. .ply with red, green, blue)");
  app->add_option("--texture", o.texture, "Source texture (.png); default: the map_Kd of the source's MTL");
  app->add_option("--target", o.target, "Target mesh (.obj, .off, .ply, .stl, .glb, .gltf), closed and manifold");
  app->add_option("-o,--output", o.output,
                  "Output mesh: .obj, the target with uv into OUT_atlas.png, or .glb/.gltf with the atlas embedded (with --sdm:\n"
                  "the decoded mesh, any format)")
      ->required();
  app->add_option("--sdm", o.sdm, "Displacement map (.exr from 'sdm encode') to decode around --target-skeleton");
  app->add_option("--lod", o.lod, "With --sdm: level of detail of the decode (every base edge cut into 2^L pieces)")
      ->check(number_in(0, 8))
      ->capture_default_str();
  app->add_option("--source-skeleton", o.source_skeleton, "Source skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--target-skeleton", o.target_skeleton, "Target skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--match", o.settings.match,
                  "Force a pair of junction or end nodes to correspond: SOURCE_NODE=TARGET_NODE (skeleton node\n"
                  "indices; repeatable), for symmetric models whose pose does not tell the branches apart");
  add_size_option(app, o.settings.size, "Atlas width and height in texels");
  add_margin_option(app, o.settings.margin);
  app->add_option("--correspondence", o.correspondence,
                  "Also write, per target vertex, the source face and barycentric coordinates it takes (.txt or .json)");
  app->add_option("--vertex-colors", o.vertex_colors,
                  "Also write the target with a colour per vertex (.ply, uchar red/green/blue): the source's vertex colours,\n"
                  "or its texture, at the source point each target vertex corresponds to (needs a correspondence, as above)");
  app->add_flag("--no-refine", o.settings.no_refine,
                "Between different bodies, keep the registration's closest points instead of refining the correspondence\n"
                "in the Laplace-Beltrami eigenbases of both models (ZoomOut)");
  add_max_memory_option(app, o.max_memory);
  app->add_flag("--force", o.settings.force, "Write the result even when the registered source fits the target poorly, its branches disagree in length or meet the core at other places, or left and right are a tie");
  app->add_flag("--json", o.json, "Print one JSON object instead of text");
  add_up_option(app, o.up, "--up", "both models (for the preview)");
  add_up_option(app, o.source_up, "--source-up", "the source (for the preview; overrides --up)");
  add_up_option(app, o.target_up, "--target-up", "the target (for the preview; overrides --up)");
  app->add_flag("--strict", o.strict,
                "Refuse a model with a small separate part (a blob inside it, a floating speck) instead of leaving the part out\n"
                "of the matching with a warning (its vertices then take the nearest vertex's source point)");
  add_repair_options(app);
}

}  // namespace

Command add_transfer_command(CLI::App& parent) {
  auto o = std::make_shared<TransferArgs>();
  auto* app = parent.add_subcommand(
      "transfer", "Transfer the texture of a source model to a target model with the same skeleton branching:\n"
                  "the skeletons' junctions, ends and chains are matched, matched chains resampled to the same\n"
                  "segments, the source's skeleton texture map reused around the target's skeleton, and the\n"
                  "source's texture remapped into it. Writes OUT.obj (the target with uv) with its MTL,\n"
                  "OUT_atlas.png (the texture it names) and OUT_preview.png (source and target side by side).\n"
                  "A target that is the source's shape (another tessellation, moved or scaled) takes the source's\n"
                  "skeleton carried over; one that is the source in another pose (limbs turned, bent, thickened)\n"
                  "takes it bent along; another body with the same branching (another person, an animal of the\n"
                  "same kind, in the same orientation) is registered: the source bent onto it along its matched\n"
                  "skeleton, refused (exit code 2, nothing written) when the fit is poor unless --force. A target\n"
                  "whose major branching differs is refused; small end branches (fingers, heels, tails: at most 8 %\n"
                  "of a skeleton's length and of its vertices) found in one skeleton only are pruned first.\n"
                  "With --sdm MAP.exr --target-skeleton SKEL.json instead: the geometry counterpart, the map decoded\n"
                  "around another skeleton with the same branching (matched and resampled onto the map's own).");
  declare_options(app, *o);
  return {app, [o]() { return o->sdm.empty() ? run_texture_transfer(*o) : run_sdm_transfer(*o); }};
}

}  // namespace sdm::cli
