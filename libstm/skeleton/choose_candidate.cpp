#include "libstm/skeleton/choose_candidate.h"

#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <tuple>

namespace sdm {

double tube_error(const SkeletonGraph& g, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                  const Eigen::MatrixX3d& poles) {
  std::vector<double> w(V.rows(), 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    // Twice the area: only the ratio of the weights counts, and doubling is exact.
    const double a = 2 * triangle_area(V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
    for (int k = 0; k < 3; ++k) w[F(f, k)] += a;
  }
  double sum = 0, wsum = 0;
  for (int i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i);
    double d = INFINITY;
    for (const auto& e : g.edges) {
      const Eigen::Vector3d a = g.pos[e.first], b = g.pos[e.second];
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      d = std::min(d, (a + t * ab - p).norm());
    }
    for (const auto& q : g.pos) d = std::min(d, (q - p).norm());
    const double r = (poles.row(i) - V.row(i)).norm();
    sum += w[i] * std::abs(d - r);
    wsum += w[i];
  }
  return wsum > 0 ? sum / wsum : 0.0;
}

SkeletonCandidate measure_candidate(SkeletonGraph graph, const InsideMesh& inside, const Eigen::MatrixX3d& V,
                                    const Eigen::MatrixX3i& F, const Eigen::MatrixX3d* poles, double diag) {
  SkeletonCandidate c;
  c.graph = std::move(graph);
  const SkeletonGraph& g = c.graph;
  c.cycles = int(g.edges.size()) - int(g.pos.size()) + 1;
  for (const auto& e : g.edges)
    if (!inside.segment_inside(g.pos[e.first], g.pos[e.second])) ++c.outside;
  if (poles) c.error = tube_error(g, V, F, *poles) / std::max(diag, 1e-300);
  return c;
}

SkeletonMethod choose_candidate(const SkeletonCandidate& contraction, const SkeletonCandidate& medial, int genus,
                                const SkeletonOptions& options) {
  if (options.method != SkeletonMethod::automatic) return options.method;
  auto rank = [&](const SkeletonCandidate& c, double handicap) {
    return std::make_tuple(c.graph.edges.empty(), c.cycles != genus, c.outside, c.error * handicap);
  };
  const bool more_limbs = rank(medial, 1.0) < rank(contraction, 1.0) && medial.graph.ends() > contraction.graph.ends();
  return more_limbs || rank(medial, options.medial_handicap) < rank(contraction, 1.0) ? SkeletonMethod::medial
                                                                                     : SkeletonMethod::contraction;
}

}  // namespace sdm
