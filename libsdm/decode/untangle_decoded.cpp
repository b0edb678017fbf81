#include "libsdm/decode/untangle_decoded.h"

#include "libsdm/map/base_mesh_record.h"
#include "libstm/mesh/self_intersections.h"

#include <algorithm>
#include <memory>

namespace sdm {
namespace {

// Rounds of smoothing before the displacements are also shrunk, and rounds in all (each shrinking
// halves them: after 12 rounds what is left of a displacement is within 1/256 of the flat base).
constexpr int kSmoothRounds = 4;
constexpr int kRounds = 12;

// Each point's neighbours along the triangles' edges (compressed rows).
struct Neighbours {
  std::vector<int> start, list;
  Neighbours(const Eigen::MatrixX3i& T, size_t n) : start(n + 1, 0) {
    std::vector<std::pair<int, int>> edges;
    edges.reserve(size_t(T.rows()) * 6);
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      for (int c = 0; c < 3; ++c) edges.push_back({T(t, c), T(t, (c + 1) % 3)}), edges.push_back({T(t, (c + 1) % 3), T(t, c)});
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& e : edges) ++start[size_t(e.first) + 1];
    for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    list.reserve(edges.size());
    for (const auto& e : edges) list.push_back(e.second);
  }
};

Eigen::MatrixX3d as_matrix(const std::vector<Eigen::Vector3d>& p) {
  Eigen::MatrixX3d V(Eigen::Index(p.size()), 3);
  for (size_t i = 0; i < p.size(); ++i) V.row(Eigen::Index(i)) = p[i];
  return V;
}

// The triangles of each base face, and the base faces sharing a corner with each.
struct NearbyTriangles {
  std::vector<std::vector<int>> of_face, around_face;
  NearbyTriangles(const Eigen::MatrixX3i& T, const std::vector<int>& triangle_face, const Eigen::MatrixX3i& base)
      : of_face(size_t(base.rows())), around_face(size_t(base.rows())) {
    for (Eigen::Index t = 0; t < T.rows(); ++t) of_face[size_t(triangle_face[size_t(t)])].push_back(int(t));
    std::vector<std::vector<int>> at_corner(size_t(base.rows() ? base.maxCoeff() + 1 : 0));
    for (Eigen::Index f = 0; f < base.rows(); ++f)
      for (int c = 0; c < 3; ++c) at_corner[size_t(base(f, c))].push_back(int(f));
    for (Eigen::Index f = 0; f < base.rows(); ++f) {
      auto& a = around_face[size_t(f)];
      for (int c = 0; c < 3; ++c) a.insert(a.end(), at_corner[size_t(base(f, c))].begin(), at_corner[size_t(base(f, c))].end());
      std::sort(a.begin(), a.end());
      a.erase(std::unique(a.begin(), a.end()), a.end());
    }
  }
};

// The crossing pairs with a triangle flagged in `look` (every pair when it is empty). After the first
// round only points near folds move, and a fold's pairs lie within base faces sharing a corner: the
// search then runs over the triangles of the base faces around the flagged ones only.
std::vector<std::array<int, 2>> local_crossings(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& T, const std::vector<char>& look,
                                                const NearbyTriangles& nearby) {
  if (look.empty()) return crossing_face_pairs(V, T);
  std::vector<char> face_near(nearby.of_face.size(), 0);
  for (size_t f = 0; f < nearby.of_face.size(); ++f) {
    bool flagged = false;
    for (int t : nearby.of_face[f]) flagged |= look[size_t(t)] != 0;
    if (flagged)
      for (int g : nearby.around_face[f]) face_near[size_t(g)] = 1;
  }
  std::vector<int> some;
  for (size_t f = 0; f < face_near.size(); ++f)
    if (face_near[f]) some.insert(some.end(), nearby.of_face[f].begin(), nearby.of_face[f].end());
  Eigen::MatrixX3i sub(Eigen::Index(some.size()), 3);
  std::vector<char> sub_look(some.size());
  for (size_t k = 0; k < some.size(); ++k) sub.row(Eigen::Index(k)) = T.row(some[k]), sub_look[k] = look[size_t(some[k])];
  std::vector<std::array<int, 2>> out = crossing_face_pairs(V, sub, sub_look);
  for (auto& p : out) p = {std::min(some[size_t(p[0])], some[size_t(p[1])]), std::max(some[size_t(p[0])], some[size_t(p[1])])};
  return out;
}

}  // namespace

UntangleReport untangle_decoded(std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& flat,
                                const Eigen::MatrixX3i& triangles, const std::vector<int>& triangle_face,
                                const Eigen::MatrixX3i& base_triangles, const std::vector<int>& point_segment) {
  UntangleReport report;
  const size_t n = points.size();
  if (n == 0 || triangles.rows() == 0) return report;
  std::vector<Eigen::Vector3d> disp(n);
  std::vector<char> fixed(n);
  for (size_t i = 0; i < n; ++i) disp[i] = points[i] - flat[i], fixed[i] = disp[i].squaredNorm() == 0;
  std::unique_ptr<Neighbours> nb;
  std::vector<char> look;  // the triangles whose pairs are looked at (empty: all)
  std::vector<std::array<int, 2>> local;
  std::vector<char> moved_point(n, 0);
  const NearbyTriangles nearby(triangles, triangle_face, base_triangles);
  for (int round = 0; round <= kRounds; ++round) {
    local.clear();
    for (const auto& p : local_crossings(as_matrix(points), triangles, look, nearby))
      if (faces_share_corner(base_triangles, triangle_face[size_t(p[0])], triangle_face[size_t(p[1])])) local.push_back(p);
    if (round == 0) report.crossing = long(local.size());
    if (local.empty() || round == kRounds) break;
    if (!nb) nb = std::make_unique<Neighbours>(triangles, n);
    // The points of the crossing pairs and one edge around them.
    std::vector<char> region(n, 0);
    for (const auto& p : local)
      for (int t : p)
        for (int c = 0; c < 3; ++c) {
          const int v = triangles(t, c);
          region[size_t(v)] = 1;
          for (int k = nb->start[size_t(v)]; k < nb->start[size_t(v) + 1]; ++k) region[size_t(nb->list[size_t(k)])] = 1;
        }
    std::vector<int> which;
    for (size_t i = 0; i < n; ++i)
      if (region[i] && !fixed[i]) which.push_back(int(i));
    for (int step = 0; step < 2; ++step) {  // Jacobi: the new displacements from the old ones
      std::vector<Eigen::Vector3d> next(which.size());
      for (size_t k = 0; k < which.size(); ++k) {
        const size_t v = size_t(which[k]);
        Eigen::Vector3d sum = disp[v];
        for (int j = nb->start[v]; j < nb->start[v + 1]; ++j) sum += disp[size_t(nb->list[size_t(j)])];
        next[k] = sum / double(1 + nb->start[v + 1] - nb->start[v]);
      }
      for (size_t k = 0; k < which.size(); ++k) disp[size_t(which[k])] = next[k];
    }
    if (round >= kSmoothRounds)
      for (int v : which) disp[size_t(v)] *= 0.5;
    for (int v : which) points[size_t(v)] = flat[size_t(v)] + disp[size_t(v)], moved_point[size_t(v)] = 1;
    // Only pairs with a triangle that moved can have changed.
    look.assign(size_t(triangles.rows()), 0);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
      for (int c = 0; c < 3; ++c) look[size_t(t)] |= region[size_t(triangles(t, c))];
  }
  report.left = long(local.size());
  for (char m : moved_point) report.moved += m;
  for (const auto& p : local)
    for (int t : p)
      for (int c = 0; c < 3; ++c) report.left_segments.push_back(point_segment[size_t(triangles(t, c))]);
  std::sort(report.left_segments.begin(), report.left_segments.end());
  report.left_segments.erase(std::unique(report.left_segments.begin(), report.left_segments.end()), report.left_segments.end());
  return report;
}

}  // namespace sdm
