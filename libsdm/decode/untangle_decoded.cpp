#include "libsdm/decode/untangle_decoded.h"

#include "libstm/mesh/grouped_crossings.h"

#include <algorithm>
#include <memory>

namespace sdm {
namespace {

// Rounds of smoothing before the displacements are also shrunk, and rounds in all (each shrinking
// halves them: after 12 rounds what is left of a displacement is within 1/256 of the flat base).
constexpr int kSmoothRounds = 4;
constexpr int kRounds = 12;

// Each point's neighbours along the triangles' edges (compressed rows, each row sorted): each
// triangle's corners listed at each other, then each row sorted and its repeats dropped (a sort of
// all the edges took a twentieth of a level-3 decode).
struct Neighbours {
  std::vector<int> start, list;
  Neighbours(const Eigen::MatrixX3i& T, size_t n) : start(n + 1, 0) {
    std::vector<int> count(n + 1, 0);
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      for (int c = 0; c < 3; ++c) count[size_t(T(t, c)) + 1] += 2;
    for (size_t i = 0; i < n; ++i) count[i + 1] += count[i];
    std::vector<int> all(size_t(count[n])), fill(count.begin(), count.end() - 1);
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      for (int c = 0; c < 3; ++c) {
        const size_t v = size_t(T(t, c));
        all[size_t(fill[v]++)] = T(t, (c + 1) % 3), all[size_t(fill[v]++)] = T(t, (c + 2) % 3);
      }
    list.reserve(all.size() / 2);
    for (size_t v = 0; v < n; ++v) {
      const auto b = all.begin() + count[v], e = all.begin() + count[v + 1];
      std::sort(b, e);
      list.insert(list.end(), b, std::unique(b, e));
      start[v + 1] = int(list.size());
    }
  }
};

// The base faces that share a corner with each (itself among them): the groups whose decoded faces'
// pairs are searched (a fold's two faces come from one base face or from two such faces).
std::vector<std::vector<int>> faces_around(const Eigen::MatrixX3i& base) {
  std::vector<std::vector<int>> around(size_t(base.rows()));
  std::vector<std::vector<int>> at_corner(size_t(base.rows() ? base.maxCoeff() + 1 : 0));
  for (Eigen::Index f = 0; f < base.rows(); ++f)
    for (int c = 0; c < 3; ++c) at_corner[size_t(base(f, c))].push_back(int(f));
  for (Eigen::Index f = 0; f < base.rows(); ++f) {
    auto& a = around[size_t(f)];
    for (int c = 0; c < 3; ++c) a.insert(a.end(), at_corner[size_t(base(f, c))].begin(), at_corner[size_t(base(f, c))].end());
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  return around;
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
  // Pairs within a base face or two sharing a corner, at first all, then those with a face the
  // last round moved (only points near folds move; grouped_crossings.h).
  GroupedCrossings crossings(triangles, triangle_face, faces_around(base_triangles), points);
  for (int round = 0; round <= kRounds; ++round) {
    local = crossings.find(points, look);
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
