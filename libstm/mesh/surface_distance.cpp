#include "libstm/mesh/surface_distance.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <algorithm>
#include <random>

namespace sdm {
namespace {

// The closest point of bvh's surface to every row of P, on every core (each row its own slot: the
// same result on any number of threads).
std::vector<TriangleBvh::Closest> closest_points(const TriangleBvh& bvh, const Eigen::MatrixX3d& P) {
  std::vector<TriangleBvh::Closest> closest(size_t(P.rows()));
  parallel_for(int(P.rows()), 4096, [&](int i) { closest[size_t(i)] = bvh.closest_point(P.row(i).transpose()); });
  return closest;
}

}  // namespace

Eigen::MatrixX3d sample_surface(const Mesh& mesh, int count, unsigned seed) {
  const Eigen::MatrixX3d V = vertex_matrix(mesh);
  const Eigen::MatrixX3i F = face_matrix(mesh);
  std::vector<double> cumulative(F.rows());
  double total = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    total += triangle_area(a, b, c);
    cumulative[f] = total;
  }
  Eigen::MatrixX3d P(count, 3);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const double x = uni(rng) * total;
    const int f = int(std::min<ptrdiff_t>(std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin(), F.rows() - 1));
    double r1 = uni(rng), r2 = uni(rng);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    P.row(i) = (a + r1 * (b - a) + r2 * (c - a)).transpose();
  }
  return P;
}

SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, int samples) {
  SurfaceDistance d;
  d.samples_per_surface = samples;
  d.diagonal = bounding_box_diagonal(a);
  const Eigen::MatrixX3d va = vertex_matrix(a), vb = vertex_matrix(b);
  const TriangleBvh bvh_a(va, face_matrix(a));
  const TriangleBvh bvh_b(vb, face_matrix(b));
  const Eigen::MatrixX3d pa = sample_surface(a, samples, 1);
  const Eigen::MatrixX3d pb = sample_surface(b, samples, 2);
  double sum2 = 0, sum = 0;
  auto measure = [&](const Eigen::MatrixX3d& P, const TriangleBvh& other, bool on_b, bool in_rms) {
    const std::vector<TriangleBvh::Closest> closest = closest_points(other, P);  // then taken in order
    for (int i = 0; i < P.rows(); ++i) {
      const auto& c = closest[i];
      if (c.distance > d.hausdorff) d.hausdorff = c.distance, d.worst_point = P.row(i).transpose(), d.worst_closest = c.point, d.worst_on_b = on_b;
      if (!in_rms) continue;
      sum2 += c.distance * c.distance;
      sum += c.distance;
    }
  };
  measure(pa, bvh_b, false, true);
  measure(pb, bvh_a, true, true);
  measure(va, bvh_b, false, false);
  measure(vb, bvh_a, true, false);
  d.rms = std::sqrt(sum2 / (2.0 * samples));
  d.mean = sum / (2.0 * samples);
  return d;
}

SurfaceCoverage surface_coverage(const Mesh& reference, const Mesh& carrier, double tolerance) {
  return surface_coverage(reference, vertex_matrix(carrier), face_matrix(carrier), tolerance);
}

SurfaceCoverage surface_coverage(const Mesh& reference, const Eigen::MatrixX3d& points, const Eigen::MatrixX3i& triangles,
                                 double tolerance) {
  SurfaceCoverage c;
  const TriangleBvh bvh(points, triangles);
  const std::vector<double> area = vertex_areas(reference);
  const std::vector<TriangleBvh::Closest> closest = closest_points(bvh, vertex_matrix(reference));  // summed in vertex order
  double total = 0, within = 0, sq = 0;
  for (auto v : reference.vertices()) {
    const Eigen::Vector3d p = point(reference, v);
    const double d = closest[size_t(v.idx())].distance, a = area[v.idx()];
    total += a, sq += a * d * d;
    if (d <= tolerance) within += a;
    if (d > c.worst) c.worst = d, c.worst_point = p;
  }
  if (total > 0) c.share = within / total, c.rms = std::sqrt(sq / total);
  return c;
}

}  // namespace sdm
