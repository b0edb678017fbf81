#include "libstm/layout/segments.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sdm {


namespace {

void check_inputs(const Mesh& mesh, const Skeleton& sk) {
  if (sk.edges.empty()) throw InputError("the skeleton has no edge, so there is no segment to map the surface to");
  if (sk.vertex_node.size() != mesh.n_vertices())
    throw InputError("the skeleton maps " + std::to_string(sk.vertex_node.size()) + " vertices but the mesh has " +
                     std::to_string(mesh.n_vertices()) + " (skeleton of another mesh?)");
  for (int n : sk.vertex_node)
    if (n < 0 || n >= int(sk.nodes.size())) throw InputError("the skeleton maps a vertex to node " + std::to_string(n));
}

// Faces mapped with less stretch than this by some candidate never go to a worse one.
constexpr double kGoodStretch = 2.0;

// L2 stretch (Sander et al. 2001) of face p under the capsule map of segment a -> b with radius
// `radius`, or the face's mean distance to the segment when it is 0; infinity when the map flattens
// the face. *folded tells whether the map turns the face over (orient: +1 when p's order winds
// around the outward normal, -1 for a part wound inside out). See assign_faces.
double face_stretch(const Eigen::Vector3d p[3], double orient, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    double radius, bool* folded) {
  *folded = false;
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d ab = b - a;
  const double len = ab.norm();
  if (!(len > 0)) return inf;
  const Eigen::Vector3d axis = ab / len;
  // Any frame will do: the stretch does not depend on where phi = 0 is.
  Eigen::Vector3d e1 = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (e1 - axis * axis.dot(e1)).normalized();
  const Eigen::Vector3d e2 = axis.cross(e1);
  double r = 0;
  for (int k = 0; k < 3; ++k) r += distance_to_segment(p[k], a, b) / 3;
  if (radius > 0) r = radius;
  if (!(r > 0)) return inf;
  double phi[3], v[3], rho[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d x = p[k] - a;
    const double t = x.dot(axis) / len;
    rho[k] = std::hypot(x.dot(e1), x.dot(e2));
    phi[k] = std::atan2(x.dot(e2), x.dot(e1));
    if (t < 0) v[k] = -r * std::atan2(-x.dot(axis), rho[k]);
    else if (t > 1) v[k] = len + r * std::atan2((p[k] - b).dot(axis), rho[k]);
    else v[k] = t * len;
  }
  // Unwrap the angles around the first corner that has one (a corner on the axis has none).
  const double eps = 1e-9 * (r + len);
  int ref = -1;
  for (int k = 0; k < 3 && ref < 0; ++k)
    if (rho[k] > eps) ref = k;
  if (ref < 0) return inf;
  double mean = 0;
  int cnt = 0;
  for (int k = 0; k < 3; ++k)
    if (rho[k] > eps) {
      phi[k] = phi[ref] + std::remainder(phi[k] - phi[ref], 2 * M_PI);
      mean += phi[k], ++cnt;
    }
  for (int k = 0; k < 3; ++k)
    if (rho[k] <= eps) phi[k] = mean / cnt;
  const Eigen::Vector2d s0(r * phi[0], v[0]), s1(r * phi[1], v[1]), s2(r * phi[2], v[2]);
  // u runs along axis x radial and v along the axis, so an outward face keeps a positive area.
  const double a2 = orient * 0.5 * ((s1 - s0).x() * (s2 - s0).y() - (s2 - s0).x() * (s1 - s0).y());
  const double a3 = triangle_area(p[0], p[1], p[2]);
  *folded = a2 < 0;
  if (!(std::abs(a2) > 1e-12 * a3)) return inf;
  const Eigen::Vector3d Ss = (p[0] * (s1.y() - s2.y()) + p[1] * (s2.y() - s0.y()) + p[2] * (s0.y() - s1.y())) / (2 * a2);
  const Eigen::Vector3d St = (p[0] * (s2.x() - s1.x()) + p[1] * (s0.x() - s2.x()) + p[2] * (s1.x() - s0.x())) / (2 * a2);
  return std::sqrt(0.5 * (Ss.squaredNorm() + St.squaredNorm()));
}

// How segment a -> b would map face p (the part of assign_faces' rule that looks at one candidate).
// shaders/stm.geom.glsl mirrors rate_candidate and better_candidate line by line, in float: keep
// them in step.
struct Candidate {
  int rank = 0;       // 0: mapped well, 1: mapped the right way round but stretched, 2: folded over
  double stretch = 0; // face_stretch, infinity when the map flattens the face
  double score = 0;   // outward normal against the capsule's radial direction, mean cosine
  double dist = 0;    // centroid's distance to the segment
  double len = 0;     // segment length
};

// The capsule projects the surface radially, from the axis over the cylinder part and from the
// end node over a cap. The candidate maps the face as its capsule would, with the face's own
// distance from the axis as the radius (so the map is locally isometric where the face is
// parallel to the capsule), and the L2 stretch of that triangle map decides: it is 1 for a face
// lying over its segment's axis, grows where the face tilts away from the radial direction or
// lies past the end node, and is infinite where the face would be mapped edge-on or folded
// over (a face on the far side of a junction seen through another segment's cap).
Candidate rate_candidate(const Eigen::Vector3d p[3], double orient, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Candidate x;
  const Eigen::Vector3d c = (p[0] + p[1] + p[2]) / 3.0;
  Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
  if (n.norm() > 0) n.normalize();
  n *= orient;
  bool folded = false;
  x.stretch = face_stretch(p, orient, a, b, 0.0, &folded);
  x.rank = folded ? 2 : x.stretch < kGoodStretch ? 0 : 1;
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  for (const Eigen::Vector3d& q : {p[0], p[1], p[2], c}) {
    const double t = l2 > 0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    const Eigen::Vector3d r = q - (a + t * ab);
    const double rn = r.norm();
    if (rn > 0) x.score += n.dot(r) / rn;
  }
  x.score /= 4;
  x.dist = distance_to_segment(c, a, b);
  x.len = std::sqrt(l2);
  return x;
}

// Whether candidate x beats best, the candidate kept so far (candidates come in increasing index,
// so an exact tie keeps the lower index). Exact ties (a face across a node's plane in a symmetric
// tessellation) go to the nearer segment; the tolerances keep float noise (a rotated copy of the
// mesh) from flipping the choice. An infinite stretch loses to any finite one.
bool better_candidate(const Candidate& x, const Candidate& best) {
  const double tol = 1e-9;
  if (x.rank != best.rank) return x.rank < best.rank;
  if (x.rank == 0 && std::abs(x.score - best.score) > tol) return x.score > best.score;
  if (x.rank > 0) {
    const bool x_inf = std::isinf(x.stretch), best_inf = std::isinf(best.stretch);
    if (x_inf != best_inf) return best_inf;
    if (!x_inf && std::abs(x.stretch - best.stretch) > tol * best.stretch) return x.stretch < best.stretch;
  }
  return x.dist < best.dist - tol * (x.dist + x.len);
}

}  // namespace

std::vector<int> face_orientation(const Mesh& mesh) {
  std::vector<int> part(mesh.n_faces(), -1);
  std::vector<double> volume;
  for (auto f0 : mesh.faces()) {
    if (part[f0.idx()] >= 0) continue;
    const int id = int(volume.size());
    volume.push_back(0.0);
    std::vector<Mesh::FaceHandle> stack{f0};
    part[f0.idx()] = id;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      Eigen::Vector3d p[3];
      int k = 0;
      for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
      volume[id] += p[0].dot(p[1].cross(p[2]));
      for (auto g : mesh.ff_range(f))
        if (part[g.idx()] < 0) part[g.idx()] = id, stack.push_back(g);
    }
  }
  std::vector<int> result(mesh.n_faces());
  for (size_t f = 0; f < result.size(); ++f) result[f] = volume[part[f]] < 0 ? -1 : 1;
  return result;
}

namespace {

// Segments per node (a loop once).
std::vector<std::vector<int>> node_segments(const Skeleton& sk) {
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < sk.edges.size(); ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    if (sk.edges[e][1] != sk.edges[e][0]) node_edges[sk.edges[e][1]].push_back(int(e));
  }
  return node_edges;
}

// The face's corners and, appended to `nodes`, their skeleton nodes.
void face_corners(const Mesh& mesh, const Skeleton& sk, int fi, Eigen::Vector3d p[3], std::vector<int>& nodes) {
  int k = 0;
  for (auto v : mesh.fv_range(mesh.face_handle(fi))) {
    p[k++] = point(mesh, v);
    nodes.push_back(sk.vertex_node[v.idx()]);
  }
}

// The first pass of assign_faces: candidates at the face's own nodes, rated with rate_candidate.
// Faces whose nodes have no edge get kNoEdge (-2), faces no candidate takes kNoSegment (-3).
constexpr int kNoEdge = -2, kNoSegment = -3;
std::vector<int> first_pass(const Mesh& mesh, const Skeleton& sk, const std::vector<std::vector<int>>& node_edges,
                            const std::vector<int>& orientation) {
  std::vector<int> result(mesh.n_faces(), -1);
  parallel_for(int(mesh.n_faces()), 2048, [&](int fi) {
    Eigen::Vector3d p[3];
    thread_local std::vector<int> nodes, cand;  // reused face after face by each thread
    nodes.clear(), cand.clear();
    face_corners(mesh, sk, fi, p, nodes);
    for (int n : nodes)
      for (int e : node_edges[n]) cand.push_back(e);
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    // A face whose nodes have no edge belongs to a part the skeleton does not reach: giving it to
    // some other part's segment would silently lose its surface.
    if (cand.empty()) {
      result[fi] = kNoEdge;
      return;
    }
    int best = -1;
    Candidate best_fit;
    for (int e : cand) {
      const Candidate x = rate_candidate(p, orientation[fi], sk.nodes[sk.edges[e][0]], sk.nodes[sk.edges[e][1]]);
      if (best < 0 || better_candidate(x, best_fit)) best = e, best_fit = x;
    }
    result[fi] = best < 0 ? kNoSegment : best;
  });
  return result;
}

// What the second pass minimises: the stretch with the segment's radius, twice that when the map
// folds the face (a folded face overlaps its neighbours in the atlas), infinity when it flattens it.
// The capsule runs on past its nodes by `extension` radii (cap_extensions).
double second_pass_cost(const Eigen::Vector3d p[3], double orient, const Skeleton& sk, int e, double radius,
                        const std::array<double, 2>& extension, bool* folded) {
  const Eigen::Vector3d& a = sk.nodes[sk.edges[e][0]];
  const Eigen::Vector3d& b = sk.nodes[sk.edges[e][1]];
  const double len = (b - a).norm();
  const Eigen::Vector3d axis = len > 0 ? Eigen::Vector3d((b - a) / len) : Eigen::Vector3d::Zero();
  const double s = face_stretch(p, orient, a - extension[0] * radius * axis, b + extension[1] * radius * axis, radius, folded);
  return *folded ? 2 * s : s;
}

// Whether cost x of segment e beats cost bx of segment be in the second pass: lower cost, ties
// (within float noise, or both infinite) to the lower index, so the visiting order does not matter.
bool better_second(double x, int e, double bx, int be) {
  const bool xi = std::isinf(x), bi = std::isinf(bx);
  if (xi || bi) return xi && bi ? e < be : bi;
  if (std::abs(x - bx) <= 1e-9 * bx) return e < be;
  return x < bx;
}

// Which end of segment e face p lies past (by its centroid): 1 past edges[e][0], 2 past edges[e][1],
// 0 over the segment.
char end_past(const Eigen::Vector3d p[3], const Skeleton& sk, int e) {
  const Eigen::Vector3d& a = sk.nodes[sk.edges[e][0]];
  const Eigen::Vector3d ab = sk.nodes[sk.edges[e][1]] - a;
  const double t = (p[0] + p[1] + p[2] - 3 * a).dot(ab) / (3 * std::max(ab.squaredNorm(), 1e-300));
  return t < 0 ? 1 : t > 1 ? 2 : 0;
}

// The second pass (see assign_faces): faces their first-pass segment maps folded or with stretch
// >= kGoodStretch at its radius try every segment at a node within two edges of their nodes.
// `folded_past`, when given, receives per face the end (end_past) of its final segment that it lies
// past when that segment still maps it folded with a stretch of kGoodStretch or more, else 0.
void second_pass(const Mesh& mesh, const Skeleton& sk, const std::vector<std::vector<int>>& node_edges,
                 const std::vector<int>& orientation, const std::vector<double>& radii,
                 const std::vector<std::array<double, 2>>& extensions, std::vector<int>& result,
                 std::vector<char>* folded_past = nullptr) {
  std::vector<std::vector<int>> node_nb(sk.nodes.size());
  for (const auto& e : sk.edges) node_nb[e[0]].push_back(e[1]), node_nb[e[1]].push_back(e[0]);
  if (folded_past) folded_past->assign(mesh.n_faces(), 0);
  parallel_for(int(mesh.n_faces()), 2048, [&](int fi) {
    const int first = result[fi];
    Eigen::Vector3d p[3];
    thread_local std::vector<int> nodes;
    nodes.clear();
    face_corners(mesh, sk, fi, p, nodes);
    const double orient = orientation[fi];
    bool folded = false;
    double best_cost = second_pass_cost(p, orient, sk, first, radii[first], extensions[first], &folded);
    if (!folded && best_cost < kGoodStretch) return;
    bool best_folded = folded;
    for (int hop = 0; hop < 2; ++hop)
      for (size_t i = 0, n = nodes.size(); i < n; ++i)
        for (int m : node_nb[nodes[i]]) nodes.push_back(m);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    int best = first;
    for (int n : nodes)
      for (int e : node_edges[n]) {
        const double c = second_pass_cost(p, orient, sk, e, radii[e], extensions[e], &folded);
        if (better_second(c, e, best_cost, best)) best = e, best_cost = c, best_folded = folded;
      }
    result[fi] = best;
    // A folded map costs twice its stretch.
    if (folded_past && best_folded && best_cost >= 2 * kGoodStretch) (*folded_past)[size_t(fi)] = end_past(p, sk, best);
  });
}

// The joints (nodes of degree 2 or more) past which a face lies folded over by its segment's cap
// with a stretch of kGoodStretch or more (second_pass's folded_past): every segment end there gets
// kCapExtension (see assign_faces). Per edge, at edges[e][0] and edges[e][1], in radii.
std::vector<std::array<double, 2>> cap_extensions(const Skeleton& sk, const std::vector<int>& face_segment,
                                                  const std::vector<char>& folded_past) {
  std::vector<char> extend(sk.nodes.size(), 0);
  for (size_t f = 0; f < folded_past.size(); ++f)
    if (folded_past[f]) extend[sk.edges[face_segment[f]][folded_past[f] - 1]] = 1;
  const std::vector<int> degree = sk.degrees();
  std::vector<std::array<double, 2>> ext(sk.edges.size(), {0.0, 0.0});
  for (size_t e = 0; e < sk.edges.size(); ++e)
    for (int k = 0; k < 2; ++k) {
      const int n = sk.edges[e][k];
      if (extend[n] && degree[n] >= 2) ext[e][k] = kCapExtension;
    }
  return ext;
}

std::vector<int> assign(const Mesh& mesh, const Skeleton& sk, const std::vector<double>* given, std::vector<double>* used,
                        bool second, const std::vector<std::array<double, 2>>& extensions,
                        std::vector<std::array<double, 2>>* extensions_used) {
  check_inputs(mesh, sk);
  const std::vector<std::vector<int>> node_edges = node_segments(sk);
  // The rule needs outward normals: a part wound inside out is flipped.
  const std::vector<int> orientation = face_orientation(mesh);
  std::vector<int> result = first_pass(mesh, sk, node_edges, orientation);
  // A face that failed is named afterwards, the first one by index, as one pass in face order would.
  for (auto f : mesh.faces()) {
    if (result[f.idx()] == kNoEdge)
      throw InputError("face " + std::to_string(f.idx()) + " belongs to skeleton node " +
                       std::to_string(sk.vertex_node[mesh.fv_range(f).begin()->idx()]) +
                       ", which has no edge: every connected part of the mesh needs at least one skeleton edge");
    if (result[f.idx()] == kNoSegment) throw InputError("face " + std::to_string(f.idx()) + " has no skeleton segment in reach");
  }
  std::vector<double> radii;
  if (given) {
    if (given->size() != sk.edges.size())
      throw InputError("got " + std::to_string(given->size()) + " segment radii for " + std::to_string(sk.edges.size()) + " skeleton edges");
    for (double r : *given)
      if (!(r > 0) || !std::isfinite(r)) throw InputError("segment radii must be positive");
    radii = *given;
  } else if (second || used) {
    for (const SegmentGeometry& g : segment_geometry(mesh, sk, result)) radii.push_back(g.radius);
  }
  if (second && given) {
    if (!extensions.empty() && extensions.size() != sk.edges.size())
      throw InputError("got " + std::to_string(extensions.size()) + " capsule extensions for " + std::to_string(sk.edges.size()) + " skeleton edges");
    const std::vector<std::array<double, 2>> none(extensions.empty() ? sk.edges.size() : 0, {0.0, 0.0});
    second_pass(mesh, sk, node_edges, orientation, radii, extensions.empty() ? none : extensions, result);
  } else if (second) {
    // Plain capsules first; where faces past a joint stay folded, extended ones.
    std::vector<std::array<double, 2>> ext(sk.edges.size(), {0.0, 0.0});
    std::vector<int> plain = result;
    std::vector<char> folded_past;
    second_pass(mesh, sk, node_edges, orientation, radii, ext, plain, &folded_past);
    ext = cap_extensions(sk, plain, folded_past);
    if (std::all_of(ext.begin(), ext.end(), [](const auto& x) { return x[0] == 0 && x[1] == 0; }))
      result = std::move(plain);
    else
      second_pass(mesh, sk, node_edges, orientation, radii, ext, result);
    if (extensions_used) *extensions_used = std::move(ext);
  }
  if (used) *used = std::move(radii);
  return result;
}

}  // namespace

std::vector<int> assign_faces(const Mesh& mesh, const Skeleton& sk, std::vector<double>* radii_used, bool second_pass,
                              std::vector<std::array<double, 2>>* extensions_used) {
  return assign(mesh, sk, nullptr, radii_used, second_pass, {}, extensions_used);
}

std::vector<int> assign_faces_with_radii(const Mesh& mesh, const Skeleton& sk, const std::vector<double>& radii,
                                         bool second_pass, const std::vector<std::array<double, 2>>& extensions) {
  return assign(mesh, sk, &radii, nullptr, second_pass, extensions, nullptr);
}

std::vector<SegmentGeometry> segment_geometry(const Mesh& mesh, const Skeleton& sk, const std::vector<int>& face_segment,
                                              const std::vector<double>* radius) {
  check_inputs(mesh, sk);
  if (face_segment.size() != mesh.n_faces()) throw InputError("face_segment does not match the mesh");
  const size_t ns = sk.edges.size();
  std::vector<SegmentGeometry> g(ns);
  std::vector<double> rsum(ns, 0.0);
  for (auto f : mesh.faces()) {
    const int s = face_segment[f.idx()];
    if (s < 0 || s >= int(ns)) throw InputError("face " + std::to_string(f.idx()) + " names no segment");
    const Eigen::Vector3d& a = sk.nodes[sk.edges[s][0]];
    const Eigen::Vector3d& b = sk.nodes[sk.edges[s][1]];
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = point(mesh, v);
    const double area = triangle_area(p[0], p[1], p[2]);
    // The vertices, not the centroid: the centroid of a flat triangle lies inside a curved surface.
    double r = 0;
    for (const auto& q : p) r += distance_to_segment(q, a, b);
    g[s].area += area;
    rsum[s] += area * r / 3.0;
  }
  for (size_t s = 0; s < ns; ++s) {
    g[s].length = (sk.nodes[sk.edges[s][1]] - sk.nodes[sk.edges[s][0]]).norm();
    if (g[s].area > 0) g[s].radius = rsum[s] / g[s].area;
  }
  // Segments without faces borrow the radius of adjacent segments that have some.
  std::vector<std::vector<int>> node_edges(sk.nodes.size());
  for (size_t e = 0; e < ns; ++e) {
    node_edges[sk.edges[e][0]].push_back(int(e));
    node_edges[sk.edges[e][1]].push_back(int(e));
  }
  for (size_t s = 0; s < ns; ++s) {
    if (g[s].area > 0) continue;
    double sum = 0;
    int cnt = 0;
    for (int end : sk.edges[s])
      for (int e : node_edges[end])
        if (g[e].area > 0) sum += g[e].radius, ++cnt;
    g[s].radius = cnt ? sum / cnt : std::max(g[s].length * 0.1, 1e-12);
  }
  if (radius) {
    if (radius->size() != ns) throw InputError("got " + std::to_string(radius->size()) + " segment radii for " + std::to_string(ns) + " skeleton edges");
    for (size_t s = 0; s < ns; ++s) g[s].radius = (*radius)[s];
  }
  for (auto& x : g) x.cap = M_PI * x.radius / 2.0;
  return g;
}

}  // namespace sdm
