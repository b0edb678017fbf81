#include "libstm/mesh/self_intersections.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include <vector>

namespace sdm {
namespace {

// Where the closed segment p-q crosses triangle (a, b, c), if it does. A segment within 1e-12
// (relative) of parallel to the plane, or a degenerate triangle, does not cross it.
bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c, Eigen::Vector3d& at) {
  const Eigen::Vector3d d = q - p;
  double t, u, v;
  if (!ray_triangle(p, d, a, b, c, t, u, v) || t < 0 || t > 1) return false;
  const Eigen::Vector3d e1 = b - a, e2 = c - a;  // the parallel test after the cheaper one (the same answer)
  if (std::abs(e1.dot(d.cross(e2))) <= 1e-12 * e1.norm() * e2.norm() * d.norm()) return false;
  at = p + t * d;
  return true;
}

bool triangles_cross(const Eigen::Vector3d* A, const Eigen::Vector3d* B, Eigen::Vector3d& at) {
  for (int k = 0; k < 3; ++k) {
    if (segment_crosses_triangle(A[k], A[(k + 1) % 3], B[0], B[1], B[2], at)) return true;
    if (segment_crosses_triangle(B[k], B[(k + 1) % 3], A[0], A[1], A[2], at)) return true;
  }
  return false;
}

// The crossing pairs (f, g), f < g, with f in [begin, end), counted up to max_pairs in the order
// of f; the example is the first found.
SelfIntersections find_in_range(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const TriangleBvh& bvh, int begin, int end,
                                long max_pairs) {
  SelfIntersections out;
  std::vector<int> near;
  for (int f = begin; f < end && out.pairs < max_pairs; ++f) {
    const Eigen::Vector3d A[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    near.clear();
    bvh.faces_in_box(A[0].cwiseMin(A[1]).cwiseMin(A[2]), A[0].cwiseMax(A[1]).cwiseMax(A[2]), near);
    for (int g : near) {
      if (g <= f) continue;  // each pair once
      bool shared = false;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared |= F(f, i) == F(g, j);
      if (shared) continue;
      const Eigen::Vector3d B[3] = {V.row(F(g, 0)), V.row(F(g, 1)), V.row(F(g, 2))};
      Eigen::Vector3d at;
      if (!triangles_cross(A, B, at)) continue;
      if (out.pairs++ == 0) out.example = at, out.face_a = f, out.face_b = g;
      if (out.pairs >= max_pairs) break;
    }
  }
  return out;
}

// The side of the plane of triangle T that each point p[k] lies on (1 or -1), or 0 within a margin
// of it: 1e-9 of |e1| |e2| L in the unnormalised signed volume, L the farthest point from T[0], which
// the rounding of segment_crosses_triangle's test stays far within (where its parallel test lets a
// segment through, its t errs by under 1e-5 of the margin). A segment between two points on one
// side does not cross T, and the test is skipped: two faces next to each other on a smooth surface
// lie mostly on one side of each other's planes.
template <int N>
std::array<int, N> plane_sides(const std::array<const Eigen::Vector3d*, N>& p, const std::array<Eigen::Vector3d, 3>& T) {
  const Eigen::Vector3d e1 = T[1] - T[0], e2 = T[2] - T[0], n = e1.cross(e2);
  std::array<double, N> s;
  double far2 = 0;
  for (int k = 0; k < N; ++k) {
    const Eigen::Vector3d d = *p[size_t(k)] - T[0];
    far2 = std::max(far2, d.squaredNorm());
    s[size_t(k)] = n.dot(d);
  }
  const double margin2 = 1e-18 * e1.squaredNorm() * e2.squaredNorm() * far2;
  std::array<int, N> side;
  for (int k = 0; k < N; ++k) side[size_t(k)] = s[size_t(k)] * s[size_t(k)] > margin2 ? (s[size_t(k)] > 0 ? 1 : -1) : 0;
  return side;
}

// The segments between points of one side (plane_sides) are skipped.
bool may_cross(int side_p, int side_q) { return side_p == 0 || side_p != side_q; }

}  // namespace

bool face_pair_crosses(const std::array<Eigen::Vector3d, 3>& A, const std::array<int, 3>& a, const std::array<Eigen::Vector3d, 3>& B,
                       const std::array<int, 3>& b) {
  int shared = 0, sa = -1, sb = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[size_t(i)] == b[size_t(j)]) ++shared, sa = i, sb = j;
  Eigen::Vector3d at;
  if (shared == 0) {  // triangles_cross's segments
    const std::array<int, 3> sa3 = plane_sides<3>({&A[0], &A[1], &A[2]}, B), sb3 = plane_sides<3>({&B[0], &B[1], &B[2]}, A);
    for (size_t k = 0; k < 3; ++k) {
      if (may_cross(sa3[k], sa3[(k + 1) % 3]) && segment_crosses_triangle(A[k], A[(k + 1) % 3], B[0], B[1], B[2], at)) return true;
      if (may_cross(sb3[k], sb3[(k + 1) % 3]) && segment_crosses_triangle(B[k], B[(k + 1) % 3], A[0], A[1], A[2], at)) return true;
    }
    return false;
  }
  if (shared == 1) {  // the edges opposite the common corner
    const Eigen::Vector3d &a1 = A[size_t((sa + 1) % 3)], &a2 = A[size_t((sa + 2) % 3)];
    const Eigen::Vector3d &b1 = B[size_t((sb + 1) % 3)], &b2 = B[size_t((sb + 2) % 3)];
    const std::array<int, 2> sa2 = plane_sides<2>({&a1, &a2}, B), sb2 = plane_sides<2>({&b1, &b2}, A);
    return (may_cross(sa2[0], sa2[1]) && segment_crosses_triangle(a1, a2, B[0], B[1], B[2], at)) ||
           (may_cross(sb2[0], sb2[1]) && segment_crosses_triangle(b1, b2, A[0], A[1], A[2], at));
  }
  if (shared == 2) {
    const Eigen::Vector3d na = (A[1] - A[0]).cross(A[2] - A[0]), nb = (B[1] - B[0]).cross(B[2] - B[0]);
    return na.dot(nb) < -(1 - 1e-4) * na.norm() * nb.norm();
  }
  return false;
}

namespace {

// Whether faces f and g (a pair to test) cross, CGAL's way (crossing_face_pairs).
bool faces_cross(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int f, int g) {
  const std::array<Eigen::Vector3d, 3> A = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
  const std::array<Eigen::Vector3d, 3> B = {V.row(F(g, 0)), V.row(F(g, 1)), V.row(F(g, 2))};
  return face_pair_crosses(A, {F(f, 0), F(f, 1), F(f, 2)}, B, {F(g, 0), F(g, 1), F(g, 2)});
}

}  // namespace

std::vector<std::array<int, 2>> crossing_face_pairs(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const std::vector<char>& faces) {
  std::vector<std::array<int, 2>> out;
  if (F.rows() == 0) return out;
  const TriangleBvh bvh(V, F);
  const int n = int(F.rows());
  // Per face its pairs with later faces (or with any face when only flagged faces are looked at),
  // on every core; each pair once.
  std::vector<std::vector<int>> found(static_cast<size_t>(n));
  parallel_for(n, 256, [&](int f) {
    if (!faces.empty() && !faces[size_t(f)]) return;
    const Eigen::Vector3d A[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    std::vector<int> near;
    bvh.faces_in_box(A[0].cwiseMin(A[1]).cwiseMin(A[2]), A[0].cwiseMax(A[1]).cwiseMax(A[2]), near);
    for (int g : near) {
      if (g == f || (g < f && (faces.empty() || faces[size_t(g)]))) continue;  // each pair once
      if (faces_cross(V, F, f, g)) found[size_t(f)].push_back(g);
    }
  });
  for (int f = 0; f < n; ++f)
    for (int g : found[size_t(f)]) out.push_back({std::min(f, g), std::max(f, g)});
  return out;
}

SelfIntersections find_self_intersections(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, long max_pairs) {
  if (F.rows() == 0) return {};
  const TriangleBvh bvh(V, F);
  const int n = int(F.rows());
  if (n < 50000 || std::thread::hardware_concurrency() < 2) return find_in_range(V, F, bvh, 0, n, max_pairs);
  // Two halves of the faces on two threads (523k-vertex mesh: 3.5 -> 1.9 s); the same count and
  // example as one pass in face order: the first half's pairs come first.
  SelfIntersections first, second;
  run_concurrently([&] { second = find_in_range(V, F, bvh, n / 2, n, max_pairs); },
                   [&] { first = find_in_range(V, F, bvh, 0, n / 2, max_pairs); });
  if (first.pairs == 0) return second;
  first.pairs = std::min(max_pairs, first.pairs + second.pairs);
  return first;
}

}  // namespace sdm
