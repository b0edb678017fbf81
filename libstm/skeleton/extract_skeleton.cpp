#include "libstm/skeleton/extract_skeleton.h"

#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/core/union_find.h"
#include "libstm/mesh/fill_holes.h"
#include "libstm/mesh/inside_mesh.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/geometry/working_origin.h"
#include "libstm/skeleton/choose_candidate.h"
#include "libstm/skeleton/contraction_proxy.h"
#include "libstm/skeleton/medial_poles.h"
#include "libstm/skeleton/refine_skeleton.h"
#include "libstm/skeleton/surgery.h"

#include <algorithm>
#include <cstdio>
#include <future>
#include <map>
#include <optional>
#include <string>

namespace sdm {

namespace {

// One connected part of the mesh in part-local numbering.
struct Part {
  std::vector<int> global;  // part-local vertex -> mesh vertex
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
};

// Connected parts (through faces), ordered by their smallest vertex; faces keep their order,
// vertices are numbered in the order the part's faces reach them.
std::vector<Part> split_parts(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const int n = int(V.rows()), m = int(F.rows());
  UnionFind sets(n);
  for (int f = 0; f < m; ++f)
    for (int k = 1; k < 3; ++k) sets.unite(F(f, 0), F(f, k));
  std::vector<int> smallest(n, -1);
  for (int v = 0; v < n; ++v)
    if (smallest[sets.find(v)] < 0) smallest[sets.find(v)] = v;
  std::map<int, std::vector<int>> part_faces;
  for (int f = 0; f < m; ++f) part_faces[smallest[sets.find(F(f, 0))]].push_back(f);
  std::vector<Part> parts;
  for (const auto& [first, fs] : part_faces) {
    (void)first;
    Part& p = parts.emplace_back();
    std::vector<int> local(n, -1);
    p.F.resize(Eigen::Index(fs.size()), 3);
    for (size_t r = 0; r < fs.size(); ++r)
      for (int k = 0; k < 3; ++k) {
        const int v = F(fs[r], k);
        if (local[v] < 0) local[v] = int(p.global.size()), p.global.push_back(v);
        p.F(Eigen::Index(r), k) = local[v];
      }
    p.V.resize(Eigen::Index(p.global.size()), 3);
    for (size_t i = 0; i < p.global.size(); ++i) p.V.row(Eigen::Index(i)) = V.row(p.global[i]);
  }
  return parts;
}

std::string surgery_line(const char* name, const SkeletonGraph& g, const SkeletonStats& st) {
  return std::string(name) + " surgery: " + std::to_string(g.pos.size()) + " nodes, " + std::to_string(g.edges.size()) +
         " edges, " + std::to_string(g.ends()) + " ends, refused " + std::to_string(st.refused_collapses) + ", forced " +
         std::to_string(st.forced_collapses);
}

std::string candidate_line(const char* name, const SkeletonCandidate& c, int genus) {
  char line[200];
  std::snprintf(line, sizeof line, "%s skeleton: %zu nodes, %d ends, %d cycles (genus %d), %d edges outside, tube error %.4f",
                name, c.graph.pos.size(), c.graph.ends(), c.cycles, genus, c.outside, c.error);
  return line;
}

// The skeleton of one part: the mesh the candidates are computed on (the part or its proxy), what
// they share (inside tests, surface, medial poles), and the two candidates.
class PartSkeleton {
 public:
  PartSkeleton(const Part& part, const SkeletonOptions& opt, const Progress& say, SkeletonStats& st);
  // Both candidates, the medial one on a second thread (they are independent).
  void build_candidates();
  // The chosen candidate's graph, and the node of every part vertex in `owner`.
  SkeletonGraph choose(std::vector<int>& owner);

 private:
  void prepare_shared();
  void contraction_candidate();
  void medial_candidate();
  SkeletonGraph cut(const Eigen::MatrixX3d& contracted, const char* name, SkeletonStats& cst) const;
  SkeletonCandidate finish(SkeletonGraph g, const char* name, SkeletonStats& cst) const;

  const Part& part_;
  const SkeletonOptions& opt_;
  const Progress& say_;
  SkeletonStats& st_;
  const double diag_;
  const int genus_;
  const bool use_proxy_;
  Eigen::MatrixX3d XV_;  // the mesh contracted and cut: the part or its proxy
  Eigen::MatrixX3i XF_;
  std::optional<TriangleBvh> surface_;  // wide leaves: it serves the poles' ball queries
  // Set once prepare_shared has built surface_, inside_ and the poles' work (or has failed).
  std::promise<void> shared_;
  std::shared_future<void> shared_ready_ = shared_.get_future().share();
  std::optional<MedialPoles> pole_finder_;
  Eigen::MatrixX3d poles_;
  std::optional<SharedLoop> pole_work_;
  std::optional<InsideMesh> inside_;
  SkeletonCandidate contraction_, medial_;
  SkeletonStats contraction_st_, medial_st_;  // each candidate's share of the work
};

PartSkeleton::PartSkeleton(const Part& part, const SkeletonOptions& opt, const Progress& say, SkeletonStats& st)
    : part_(part), opt_(opt), say_(say), st_(st),
      diag_((part.V.colwise().maxCoeff() - part.V.colwise().minCoeff()).norm()),
      // Genus of the part from its Euler characteristic (closed: E = 3F/2).
      genus_(int((2 - part.V.rows() + part.F.rows() / 2) / 2)),
      // Large parts are contracted through a proxy (cotangent weights); parts up to the proxy's
      // size as they are, with the raw contraction options (uniform weights by default).
      use_proxy_(opt.proxy_max_vertices > 0 && part.V.rows() > opt.proxy_max_vertices) {
  XV_ = part.V;
  XF_ = part.F;
  if (use_proxy_) {
    surface_.emplace(part.V, part.F, std::vector<int>{}, 8);  // the proxy's projection needs it now
    Stopwatch proxy_time;
    make_proxy(part.V, part.F, opt.proxy_max_vertices, XV_, XF_, &*surface_);
    const double proxy_seconds = proxy_time.seconds();
    st.proxy_seconds += proxy_seconds;
    st.contraction_seconds += proxy_seconds;
  }
  st.proxy_vertices += int(XV_.rows());
}

// What the candidates share besides the contracted shape: the surface's tree, the inside tests
// and the medial poles (the medial candidate's contracted shape and, for both, the radius the
// skeleton should keep from the surface). Built on the medial candidate's thread while the
// contraction starts on the other, which needs none of it before its surgery (it waited 2.5-12 ms
// for them at 600-3600 vertices, a tenth of its path). Vertices' poles are independent: both
// threads share their work (pole_work_) without changing the result.
void PartSkeleton::prepare_shared() {
  try {
    if (!surface_) surface_.emplace(part_.V, part_.F, std::vector<int>{}, 8);
    pole_finder_.emplace(XV_, XF_, use_proxy_ ? nullptr : &*surface_);
    poles_.resize(XV_.rows(), 3);
    pole_work_.emplace(int(XV_.rows()), 32, [this](int i) { poles_.row(i) = pole_finder_->pole(i); });
    inside_.emplace(part_.V, part_.F);
    shared_.set_value();
  } catch (...) {
    shared_.set_exception(std::current_exception());
    throw;
  }
}

// Connectivity surgery of one candidate's contracted shape.
SkeletonGraph PartSkeleton::cut(const Eigen::MatrixX3d& contracted, const char* name, SkeletonStats& cst) const {
  Stopwatch t;
  SkeletonGraph g = connectivity_surgery(XV_, contracted, XF_, *inside_, genus_, opt_, &cst);
  cst.surgery_seconds += t.seconds();
  if (say_) say_(surgery_line(name, g, cst));
  return g;
}

// Refinement and measures of one candidate; needs the poles (bent edges, tube error).
SkeletonCandidate PartSkeleton::finish(SkeletonGraph g, const char* name, SkeletonStats& cst) const {
  Stopwatch t;
  refine_skeleton(g, XV_, *inside_, *surface_, diag_, opt_);
  if (opt_.centre_junctions > 0) centre_junctions(g, XV_, poles_, *inside_, opt_.centre_junctions);
  bend_crossing_edges(g, *inside_, poles_);
  const bool automatic = opt_.method == SkeletonMethod::automatic;
  SkeletonCandidate c = measure_candidate(std::move(g), *inside_, XV_, XF_, automatic ? &poles_ : nullptr, diag_);
  cst.refinement_seconds += t.seconds();
  if (say_) say_(candidate_line(name, c, genus_));
  return c;
}

// The poles are on the medial candidate's critical path, the contraction's surgery is not: the
// contraction's thread helps with the poles once it is done contracting, then cuts, then waits.
void PartSkeleton::contraction_candidate() {
  if (opt_.method == SkeletonMethod::medial) {
    shared_ready_.get();
    pole_work_->work();
    return;
  }
  Stopwatch t;
  const ContractResult cr = contract_mesh(XV_, XF_, use_proxy_ ? opt_.contraction : opt_.raw_contraction, say_);
  st_.iterations = std::max(st_.iterations, cr.iterations);
  if (!cr.area_ratio.empty()) st_.area_ratio = std::max(st_.area_ratio, cr.area_ratio.back());
  st_.contraction_seconds += t.seconds();
  shared_ready_.get();
  pole_work_->work();
  SkeletonGraph g = cut(cr.positions, "contraction", contraction_st_);
  pole_work_->wait();
  contraction_ = finish(std::move(g), "contraction", contraction_st_);
}

void PartSkeleton::medial_candidate() {
  prepare_shared();
  pole_work_->work();
  pole_work_->wait();
  if (opt_.method == SkeletonMethod::contraction) return;
  const Eigen::MatrixX3d smooth = smooth_poles(poles_, XF_, opt_.medial_smoothing);
  medial_ = finish(cut(smooth, "medial", medial_st_), "medial", medial_st_);
}

void PartSkeleton::build_candidates() {
  run_concurrently([this] { medial_candidate(); }, [this] { contraction_candidate(); });
  st_.medial_seconds += pole_work_->seconds();
  st_.contraction_seconds += pole_work_->seconds();
  for (const SkeletonStats* c : {&contraction_st_, &medial_st_}) {
    st_.surgery_seconds += c->surgery_seconds;
    st_.refinement_seconds += c->refinement_seconds;
    st_.refused_collapses += c->refused_collapses;
    st_.forced_collapses += c->forced_collapses;
  }
}

SkeletonGraph PartSkeleton::choose(std::vector<int>& owner) {
  const SkeletonMethod kept = choose_candidate(contraction_, medial_, genus_, opt_);
  const bool medial = kept == SkeletonMethod::medial;
  if (medial) ++st_.medial_parts;
  st_.kept.push_back(kept);
  SkeletonCandidate& best = medial ? medial_ : contraction_;
  SkeletonGraph& g = best.graph;
  split_lone_node(g, XV_, *inside_);
  st_.outside_edges += best.outside;
  Stopwatch t;
  owner.assign(part_.V.rows(), 0);
  if (use_proxy_) {
    owner = map_to_nodes(part_.V, part_.F, XV_, XF_, g);
  } else {
    for (size_t a = 0; a < g.verts.size(); ++a)
      for (int v : g.verts[a]) owner[v] = int(a);
  }
  st_.proxy_seconds += t.seconds();
  return std::move(g);
}

}  // namespace

Skeleton extract_skeleton(const Mesh& mesh, const SkeletonOptions& opt, const Progress& progress, SkeletonStats* stats) {
  Stopwatch total;
  SkeletonStats st;
  Skeleton sk;
  // An open mesh is extracted with its holes filled (the contraction and the inside tests need a
  // closed surface); the patches' vertices then leave the map.
  // The stages work on the model moved near the origin (working_origin.h), the nodes going back to
  // the input's frame at the end.
  Eigen::MatrixX3d centred = vertex_matrix(mesh);
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  if (centred.rows()) centre = working_origin(centred.colwise().minCoeff().transpose(), centred.colwise().maxCoeff().transpose()).transpose();
  centred.rowwise() -= centre;
  const FilledMesh filled = fill_holes(centred, face_matrix(mesh));
  const Eigen::MatrixX3d& V = filled.V;
  const Eigen::MatrixX3i& F = filled.F;
  st.filled_loops = filled.loops;
  st.fill_vertices = int(V.rows()) - filled.original_vertices;
  if (filled.loops && progress)
    progress("closed " + std::to_string(filled.loops) + " boundary loop(s) with " + std::to_string(st.fill_vertices) +
             " vertices for the extraction");
  sk.vertex_node.assign(V.rows(), -1);
  const Progress say = serialised(progress);  // the candidates report from two threads
  for (const Part& part : split_parts(V, F)) {
    ++st.parts;
    PartSkeleton ps(part, opt, say, st);
    ps.build_candidates();
    std::vector<int> owner;
    const SkeletonGraph g = ps.choose(owner);
    const int base = int(sk.nodes.size());
    for (size_t a = 0; a < g.pos.size(); ++a) sk.nodes.push_back(g.pos[a] + centre.transpose());
    for (size_t v = 0; v < part.global.size(); ++v) sk.vertex_node[part.global[v]] = base + owner[v];
    for (const auto& e : g.edges) sk.edges.push_back({base + e.first, base + e.second});
  }
  if (filled.loops) st.dropped_nodes = restrict_to_vertices(sk, filled.original_vertices);
  st.seconds = total.seconds();
  if (stats) *stats = st;
  return sk;
}

}  // namespace sdm
