#include "apps/commands.h"
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/transfer/transfer_texture.h"
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

std::vector<std::pair<int, int>> parse_match_pairs(const std::vector<std::string>& items) {
  std::vector<std::pair<int, int>> out;
  for (const auto& s : items) {
    const auto eq = s.find('=');
    try {
      size_t used = 0;
      if (eq == std::string::npos) throw std::invalid_argument("no =");
      const int a = std::stoi(s.substr(0, eq), &used);
      if (used != eq) throw std::invalid_argument("junk");
      const std::string rhs = s.substr(eq + 1);
      const int b = std::stoi(rhs, &used);
      if (used != rhs.size()) throw std::invalid_argument("junk");
      out.push_back({a, b});
    } catch (const std::exception&) {
      throw sdm::InputError("--match " + s + ": expected SOURCE_NODE=TARGET_NODE (two skeleton node indices)");
    }
  }
  return out;
}

sdm::Skeleton skeleton_for(const sdm::Mesh& mesh, const std::string& json_path, const std::string& what) {
  if (!json_path.empty()) {
    sdm::Skeleton s = sdm::read_skeleton_json(json_path);
    if (s.vertex_node.size() != mesh.n_vertices())
      throw sdm::InputError(what + " skeleton " + json_path + " was made for a mesh with " + std::to_string(s.vertex_node.size()) +
                            " vertices, not " + std::to_string(mesh.n_vertices()));
    return s;
  }
  progress("extracting the " + what + " skeleton");
  return sdm::extract_skeleton(mesh, sdm::transfer_skeleton_options(), progress);
}

std::string sibling(const std::string& path, const std::string& suffix) {
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

std::string match_text(const sdm::SkeletonMatch& m, nlohmann::json* chains) {
  std::ostringstream out;
  *chains = nlohmann::json::array();
  for (size_t c = 0; c < m.a.chains.size(); ++c) {
    const auto& ca = m.a.chains[c];
    const auto& cb = m.b.chains[m.chain_a_to_b[c].first];
    const bool rev = m.chain_a_to_b[c].second;
    const int t0 = m.b.keys[rev ? cb.to : cb.from], t1 = m.b.keys[rev ? cb.from : cb.to];
    chains->push_back({{"source", {m.a.keys[ca.from], m.a.keys[ca.to]}},
                       {"target", {t0, t1}},
                       {"source_length", ca.length},
                       {"target_length", cb.length}});
    out << "  chain " << m.a.keys[ca.from] << "-" << m.a.keys[ca.to] << " (length " << ca.length << ") -> " << t0 << "-" << t1
        << " (length " << cb.length << ")\n";
  }
  return out.str();
}

// The geometry counterpart: the map decoded around a target skeleton with the same branching.
template <class Opts>
int run_sdm_transfer(const Opts& o) {
  if (!o.source.empty() || !o.target.empty())
    throw sdm::InputError("--sdm decodes a map around --target-skeleton; --source and --target belong to the texture transfer");
  if (o.target_skeleton.empty()) throw sdm::InputError("--sdm needs --target-skeleton SKEL.json (the skeleton to decode around)");
  const sdm::SdmImage im = sdm::read_sdm_exr(o.sdm);
  const sdm::Skeleton graph = sdm::layout_from_json(im.layout).skeleton;
  const sdm::Skeleton target = sdm::read_skeleton_json(o.target_skeleton);
  sdm::SkeletonMatch m;
  sdm::DecodeOptions d;
  d.level = o.lod;
  d.skeleton = sdm::skeleton_onto_graph(graph, target, parse_match_pairs(o.match), &m);
  const sdm::Mesh mesh = sdm::decode_sdm(im, d);
  sdm::write_mesh(mesh, o.output);
  nlohmann::json chains;
  const std::string text = match_text(m, &chains);
  if (o.json) {
    print_json({{"output", o.output}, {"vertices", mesh.n_vertices()}, {"faces", mesh.n_faces()}, {"confidence", m.confidence},
                {"candidates", m.candidates}, {"chains", chains}});
  } else {
    std::cout << o.output << ": " << mesh.n_vertices() << " vertices decoded from " << o.sdm << " around " << o.target_skeleton
              << "\n  match confidence " << m.confidence << " (" << m.candidates << " candidates)\n"
              << text;
  }
  return 0;
}

}  // namespace

Command add_transfer_command(CLI::App& parent) {
  struct Opts {
    std::string source, texture, target, output, source_skeleton, target_skeleton, sdm;
    std::vector<std::string> match;
    int size = 2048, margin = 8, lod = 3;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  auto* app = parent.add_subcommand(
      "transfer", "Transfer the texture of a source model to a target model with the same skeleton branching:\n"
                  "the skeletons' junctions, ends and chains are matched, matched chains resampled to the same\n"
                  "segments, the source's skeleton texture map reused around the target's skeleton, and the\n"
                  "source's texture remapped into it. Writes OUT.obj (the target with uv) with its MTL,\n"
                  "OUT_atlas.png (the texture it names) and OUT_preview.png (source and target side by side).\n"
                  "A target that is the source's shape (another tessellation, moved or scaled) takes the source's\n"
                  "skeleton carried over; one that is the source in another pose (limbs turned, bent, thickened)\n"
                  "takes it bent along; otherwise the extracted skeletons are matched. A target whose branching\n"
                  "differs is refused (exit code 2) and nothing is written; up to two short end branches (under 8 %\n"
                  "of a skeleton's length) found in one skeleton only are pruned first.\n"
                  "With --sdm MAP.exr --target-skeleton SKEL.json instead: the geometry counterpart, the map decoded\n"
                  "around another skeleton with the same branching (matched and resampled onto the map's own).");
  app->add_option("--source", o->source, "Source mesh with uv and a texture (.obj with its MTL)");
  app->add_option("--texture", o->texture, "Source texture (.png); default: the map_Kd of the source's MTL");
  app->add_option("--target", o->target, "Target mesh (.obj, .off, .ply, .stl), closed and manifold");
  app->add_option("-o,--output", o->output,
                  "Output mesh: .obj, the target with uv into OUT_atlas.png (with --sdm: the decoded mesh, any format)")
      ->required();
  app->add_option("--sdm", o->sdm, "Displacement map (.exr from 'sdm encode') to decode around --target-skeleton");
  app->add_option("--lod", o->lod, "With --sdm: level of detail of the decode (every base edge cut into 2^L pieces)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  app->add_option("--source-skeleton", o->source_skeleton, "Source skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--target-skeleton", o->target_skeleton, "Target skeleton (.json from 'sdm skeleton') instead of extracting one");
  app->add_option("--match", o->match,
                  "Force a pair of junction or end nodes to correspond: SOURCE_NODE=TARGET_NODE (skeleton node\n"
                  "indices; repeatable), for symmetric models whose pose does not tell the branches apart");
  app->add_option("--size", o->size, "Atlas width and height in texels")->check(CLI::Range(16, 16384))->capture_default_str();
  app->add_option("--margin", o->margin, "Texels of margin around every rectangle")->check(CLI::Range(0, 256))->capture_default_str();
  app->add_flag("--json", o->json, "Print one JSON object instead of text");
  return {app, [o]() {
            if (!o->sdm.empty()) return run_sdm_transfer(*o);
            if (o->source.empty() || o->target.empty())
              throw sdm::InputError("transfer needs --source and --target (texture), or --sdm and --target-skeleton (geometry)");
            if (std::filesystem::path(o->output).extension() != ".obj")
              throw sdm::InputError("--output must be an .obj file (it carries the uv and names the atlas)");
            std::string material;
            const sdm::Mesh source = sdm::load_mesh(o->source, &material);
            const std::string texture_path = o->texture.empty() ? material : o->texture;
            if (texture_path.empty())
              throw sdm::InputError("'" + o->source + "' names no texture in its material: pass --texture TEX.png");
            if (!source.has_halfedge_texcoords2D())
              throw sdm::InputError("'" + o->source + "' has no texture coordinates, so its texture cannot be transferred");
            const sdm::Image texture = sdm::read_png(texture_path);
            const sdm::Mesh target = sdm::load_mesh(o->target);
            const sdm::Skeleton sa = skeleton_for(source, o->source_skeleton, "source");
            const sdm::Skeleton sb = skeleton_for(target, o->target_skeleton, "target");
            sdm::GlContext gl;
            progress("GL renderer: " + gl.renderer() + " (" + gl.version() + ", " + gl.platform() + ")");
            sdm::TransferOptions to;
            to.size = o->size;
            to.margin = o->margin;
            to.fixed = parse_match_pairs(o->match);
            to.progress = progress;
            // A skeleton the user gives is used as given; an extracted one gives way to the source's
            // when the target turns out to be the source's shape (transfer_texture).
            to.carry_same_shape = o->target_skeleton.empty();
            const sdm::TextureTransfer r = sdm::transfer_texture(gl, source, texture, sa, target, sb, to);
            for (int x : r.skeletons.pruned_a) progress("source end branch at node " + std::to_string(x) + " pruned: the target's skeleton has none there");
            for (int x : r.skeletons.pruned_b) progress("target end branch at node " + std::to_string(x) + " pruned: the source's skeleton has none there");

            progress("rendering the preview");
            sdm::RenderOptions ro;
            ro.width = ro.height = 512;
            ro.texture = &texture;
            const sdm::Image left = sdm::render_mesh(gl, source, ro);
            ro.texture = &r.atlas;
            const sdm::Image right = sdm::render_mesh(gl, r.target, ro);
            const sdm::Image preview = sdm::side_by_side({left, right});

            // Everything is computed; now the files, each atomically, removed again if a later one fails.
            const std::string atlas_path = sibling(o->output, "_atlas.png"), preview_path = sibling(o->output, "_preview.png");
            const std::string mtl_path = sibling(o->output, ".mtl");
            std::vector<std::string> written;
            try {
              sdm::write_png(r.atlas, atlas_path);
              written.push_back(atlas_path);
              sdm::write_png(preview, preview_path);
              written.push_back(preview_path);
              written.push_back(mtl_path);
              sdm::write_mesh(r.target, o->output, std::filesystem::absolute(atlas_path).string());
            } catch (...) {
              std::error_code ec;
              for (const auto& f : written) std::filesystem::remove(f, ec);
              throw;
            }

            // Node numbers as in the given skeletons (the match numbers the pruned ones).
            sdm::SkeletonMatch m = r.skeletons.match;
            for (auto* red : {&m.a, &m.b}) {
              const auto& orig = red == &m.a ? r.skeletons.node_a : r.skeletons.node_b;
              for (int& k : red->keys) k = orig[k];
            }
            nlohmann::json chains;
            const std::string text = match_text(m, &chains);
            for (size_t c = 0; c < chains.size(); ++c) chains[c]["segments"] = r.skeletons.chain_edges[c].size();
            nlohmann::json keys = nlohmann::json::array();
            for (size_t k = 0; k < m.a.keys.size(); ++k)
              keys.push_back({{"source", m.a.keys[k]}, {"target", m.b.keys[m.key_a_to_b[k]]}, {"degree", m.a.key_degree[k]}});
            if (o->json) {
              print_json({{"output", o->output},
                          {"atlas", atlas_path},
                          {"preview", preview_path},
                          {"texture", texture_path},
                          {"size", r.layout_a.size},
                          {"segments", r.layout_a.segments.size()},
                          {"confidence", m.confidence},
                          {"shape_cost", m.cost},
                          {"candidates", m.candidates},
                          {"keys", keys},
                          {"chains", chains},
                          {"pruned_source_ends", r.skeletons.pruned_a},
                          {"pruned_target_ends", r.skeletons.pruned_b},
                          {"target_skeleton", r.carried ? "carried" : r.fitted ? "bent" : o->target_skeleton.empty() ? "extracted" : "given"},
                          {"bent_rms", std::isfinite(r.fit_rms) ? nlohmann::json(r.fit_rms) : nlohmann::json()},
                          {"registration_rms", std::isfinite(r.registration.rms) ? nlohmann::json(r.registration.rms) : nlohmann::json()},
                          {"registration_p99", std::isfinite(r.registration.p99) ? nlohmann::json(r.registration.p99) : nlohmann::json()},
                          {"stretch", r.stretch},
                          {"seam_faces", r.seam_faces}});
            } else {
              std::cout << o->output << ": " << target.n_vertices() << " vertices textured from " << o->source << "\n"
                        << "  atlas " << atlas_path << " (" << r.layout_a.size << "^2, " << r.layout_a.segments.size()
                        << " segments), preview " << preview_path << "\n"
                        << "  match confidence " << m.confidence << " (" << m.candidates << " candidates)\n";
              if (r.carried)
                std::cout << "  the target is the source's shape (registered to " << 100 * r.registration.rms
                          << " % of the diagonal, RMS): the source's skeleton carried over\n";
              if (r.fitted)
                std::cout << "  the target is the source in another pose (bent onto it to " << 100 * r.fit_rms
                          << " % of the diagonal, RMS): the source's skeleton bent along\n";
              for (size_t k = 0; k < m.a.keys.size(); ++k)
                std::cout << "  node " << m.a.keys[k] << " -> " << m.b.keys[m.key_a_to_b[k]] << " (degree " << m.a.key_degree[k] << ")\n";
              std::cout << text;
            }
            return 0;
          }};
}

}  // namespace sdm::cli
