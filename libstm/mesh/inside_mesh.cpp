#include "libstm/mesh/inside_mesh.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace sdm {

namespace {

// Ray (or segment, tmax = 1) against a box, with precomputed inverse direction.
bool hits_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o, const Eigen::Vector3d& inv,
              double tmax) {
  double t0 = 0, t1 = tmax;
  for (int k = 0; k < 3; ++k) {
    double ta = (lo[k] - o[k]) * inv[k], tb = (hi[k] - o[k]) * inv[k];
    if (ta > tb) std::swap(ta, tb);
    // NaN (0 * inf) when the ray lies in a slab plane: treat as inside that slab.
    if (ta == ta) t0 = std::max(t0, ta);
    if (tb == tb) t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Moller-Trumbore; returns the ray parameter or -1.
double ray_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0) return -1;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return -1;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0 || u + v > 1) return -1;
  return e2.dot(q) * inv;
}

}  // namespace

InsideMesh::InsideMesh(const Mesh& mesh) : InsideMesh(vertex_matrix(mesh), face_matrix(mesh)) {}

InsideMesh::InsideMesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const int m = int(F.rows());
  a_.resize(m), b_.resize(m), c_.resize(m);
  for (int f = 0; f < m; ++f) {
    a_[f] = V.row(F(f, 0)).transpose();
    b_[f] = V.row(F(f, 1)).transpose();
    c_[f] = V.row(F(f, 2)).transpose();
  }
  if (m > 0) {
    nodes_.reserve(2 * m / 2 + 16);
    build(0, m);
  }
}

int InsideMesh::build(int first, int count) {
  const int id = int(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int f = first; f < first + count; ++f) {
    lo = lo.cwiseMin(a_[f]).cwiseMin(b_[f]).cwiseMin(c_[f]);
    hi = hi.cwiseMax(a_[f]).cwiseMax(b_[f]).cwiseMax(c_[f]);
  }
  nodes_[id].lo = lo, nodes_[id].hi = hi;
  if (count <= 4) {
    nodes_[id].first = first, nodes_[id].count = count;
    return id;
  }
  // Median split on the longest axis of the centroids; nth_element over an index keeps the three
  // corner arrays in step.
  Eigen::Vector3d clo = Eigen::Vector3d::Constant(1e300), chi = -clo;
  for (int f = first; f < first + count; ++f) {
    const Eigen::Vector3d c = a_[f] + b_[f] + c_[f];
    clo = clo.cwiseMin(c), chi = chi.cwiseMax(c);
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  std::vector<int> idx(count);
  std::iota(idx.begin(), idx.end(), first);
  const int half = count / 2;
  std::nth_element(idx.begin(), idx.begin() + half, idx.end(), [&](int x, int y) {
    const double cx = a_[x][axis] + b_[x][axis] + c_[x][axis], cy = a_[y][axis] + b_[y][axis] + c_[y][axis];
    return cx < cy || (cx == cy && x < y);
  });
  std::vector<Eigen::Vector3d> ta(count), tb(count), tc(count);
  for (int i = 0; i < count; ++i) ta[i] = a_[idx[i]], tb[i] = b_[idx[i]], tc[i] = c_[idx[i]];
  std::copy(ta.begin(), ta.end(), a_.begin() + first);
  std::copy(tb.begin(), tb.end(), b_.begin() + first);
  std::copy(tc.begin(), tc.end(), c_.begin() + first);
  const int l = build(first, half);
  const int r = build(first + half, count - half);
  nodes_[id].left = l, nodes_[id].right = r;
  return id;
}

int InsideMesh::count_ray_hits(const Eigen::Vector3d& p, const Eigen::Vector3d& d) const {
  if (nodes_.empty()) return 0;
  const Eigen::Vector3d inv = d.cwiseInverse();
  int hits = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top) {
    const Node& n = nodes_[stack[--top]];
    if (!hits_box(n.lo, n.hi, p, inv, 1e300)) continue;
    if (n.count) {
      for (int f = n.first; f < n.first + n.count; ++f)
        if (ray_triangle(p, d, a_[f], b_[f], c_[f]) > 0) ++hits;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return hits;
}

bool InsideMesh::inside(const Eigen::Vector3d& p) const {
  // Directions with irrational-looking components so that axis-aligned meshes are not grazed.
  static const std::array<Eigen::Vector3d, 3> dirs = {Eigen::Vector3d(0.5773, 0.6181, 0.5334).normalized(),
                                                      Eigen::Vector3d(-0.7071, 0.3162, -0.6325).normalized(),
                                                      Eigen::Vector3d(0.2357, -0.8944, 0.3802).normalized()};
  int votes = 0;
  for (int k = 0; k < 3; ++k) {
    votes += count_ray_hits(p, dirs[k]) & 1;
    if (votes == 2) return true;
    if (votes + (2 - k) < 2) return false;
  }
  return votes >= 2;
}

bool InsideMesh::segment_crosses(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  if (nodes_.empty()) return false;
  const Eigen::Vector3d d = b - a;
  const Eigen::Vector3d inv = d.cwiseInverse();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top) {
    const Node& n = nodes_[stack[--top]];
    if (!hits_box(n.lo, n.hi, a, inv, 1.0)) continue;
    if (n.count) {
      for (int f = n.first; f < n.first + n.count; ++f) {
        const double t = ray_triangle(a, d, a_[f], b_[f], c_[f]);
        if (t >= 0 && t <= 1) return true;
      }
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return false;
}

bool InsideMesh::triangle_crosses(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                  int fan) const {
  if (segment_crosses(a, b) || segment_crosses(b, c) || segment_crosses(c, a)) return true;
  for (int k = 1; k < fan; ++k) {
    const double t = double(k) / fan;
    if (segment_crosses(c, a + t * (b - a))) return true;
  }
  return false;
}

}  // namespace sdm
