#include "libstm/mesh/fill_holes.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/edge_table.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace sdm {
namespace {

// What the patches add: vertices (initial positions) and faces, in the filled mesh's numbering.
struct Patches {
  int first_new = 0;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> faces;

  int add(const Eigen::Vector3d& p) {
    points.push_back(p);
    return first_new + int(points.size()) - 1;
  }
};

// Triangles between two rings that run the same way, each parameterised over [0, 1): the outer
// ring's edges keep their direction (outer[i] -> outer[i+1] in a face), the inner ring's are used
// backwards, so the next ring inwards continues the orientation.
void stitch_rings(const std::vector<int>& outer, const std::vector<int>& inner, Patches& p) {
  const size_t no = outer.size(), ni = inner.size();
  size_t i = 0, j = 0;
  while (i < no || j < ni) {
    const double next_outer = double(i + 1) / double(no), next_inner = double(j + 1) / double(ni);
    if (j == ni || (i < no && next_outer <= next_inner)) {
      p.faces.push_back({outer[i % no], outer[(i + 1) % no], inner[j % ni]});
      ++i;
    } else {
      p.faces.push_back({outer[i % no], inner[(j + 1) % ni], inner[j % ni]});
      ++j;
    }
  }
}

// The patch of one loop: rings from the loop inwards, then a fan to the centre.
void fill_loop(const std::vector<int>& loop, const Eigen::MatrixX3d& V, Patches& p) {
  const int n = int(loop.size());
  if (n == 3) {
    p.faces.push_back({loop[0], loop[1], loop[2]});
    return;
  }
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v : loop) centre += V.row(v).transpose();
  centre /= n;
  auto on_loop = [&](double t) {  // the loop's polyline at parameter t in [0, 1)
    const double x = t * n;
    const int a = std::min(n - 1, int(std::floor(x)));
    const double w = x - a;
    return Eigen::Vector3d((1 - w) * V.row(loop[a]).transpose() + w * V.row(loop[(a + 1) % n]).transpose());
  };
  const int rings = std::clamp(int(std::lround(n / (2 * M_PI))), 1, kMaxFillRings);
  std::vector<int> outer = loop;
  for (int r = 1; r < rings; ++r) {
    const int count = std::max(3, int(std::lround(double(n) * (rings - r) / rings)));
    const double toward = double(r) / rings;
    std::vector<int> inner(size_t(count), 0);
    for (int k = 0; k < count; ++k) inner[size_t(k)] = p.add((1 - toward) * on_loop(double(k) / count) + toward * centre);
    stitch_rings(outer, inner, p);
    outer = std::move(inner);
  }
  const int c = p.add(centre);
  for (size_t k = 0; k < outer.size(); ++k) p.faces.push_back({outer[k], outer[(k + 1) % outer.size()], c});
}

// Membrane fairing of the patches' inner vertices: each at the mean of its neighbours, the
// input's vertices held.
void fair_patches(const Eigen::MatrixX3d& V, Patches& p) {
  const int m = int(p.points.size());
  if (m == 0) return;
  std::vector<std::unordered_set<int>> nb(static_cast<size_t>(m));
  for (const auto& t : p.faces)
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      if (a >= p.first_new) nb[size_t(a - p.first_new)].insert(b);
      if (b >= p.first_new) nb[size_t(b - p.first_new)].insert(a);
    }
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(m, 3);
  for (int i = 0; i < m; ++i) {
    entries.emplace_back(i, i, double(nb[size_t(i)].size()));
    for (int j : nb[size_t(i)]) {
      if (j >= p.first_new) entries.emplace_back(i, j - p.first_new, -1.0);
      else rhs.row(i) += V.row(j);
    }
  }
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return;  // keep the rings' initial places
  const Eigen::MatrixX3d X = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !X.allFinite()) return;
  for (int i = 0; i < m; ++i) p.points[size_t(i)] = X.row(i).transpose();
}

}  // namespace

std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixX3i& F, int vertices) {
  std::vector<std::array<int, 3>> triangles(size_t(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) triangles[size_t(f)] = {F(f, 0), F(f, 1), F(f, 2)};
  // The hole's edge b -> a for every face edge a -> b without an opposite.
  std::vector<int> hole_next(size_t(std::max(0, vertices)), -1), starts;
  for (const auto& [a, b, f] : boundary_halfedges(edge_table(triangles, size_t(std::max(0, vertices))))) {
    if (hole_next[size_t(b)] >= 0)
      throw InputError("vertex " + std::to_string(b) + " lies on two boundary loops (a non-manifold vertex); split it first");
    hole_next[size_t(b)] = a, starts.push_back(b);
  }
  std::sort(starts.begin(), starts.end());  // deterministic order of the loops
  std::vector<std::vector<int>> loops;
  std::vector<char> seen(hole_next.size(), 0);
  for (int start : starts) {
    if (seen[size_t(start)]) continue;
    std::vector<int>& loop = loops.emplace_back();
    for (int v = start; !seen[size_t(v)];) {
      seen[size_t(v)] = 1;
      loop.push_back(v);
      if (hole_next[size_t(v)] < 0) throw InputError("a boundary loop through vertex " + std::to_string(v) + " does not close");
      v = hole_next[size_t(v)];
    }
  }
  return loops;
}

FilledMesh fill_holes(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  FilledMesh out;
  out.original_vertices = int(V.rows());
  out.original_faces = int(F.rows());
  const auto loops = boundary_loops(F, int(V.rows()));
  out.loops = int(loops.size());
  Patches p;
  p.first_new = int(V.rows());
  for (const auto& loop : loops) fill_loop(loop, V, p);
  fair_patches(V, p);
  out.V.resize(V.rows() + Eigen::Index(p.points.size()), 3);
  out.V.topRows(V.rows()) = V;
  for (size_t i = 0; i < p.points.size(); ++i) out.V.row(V.rows() + Eigen::Index(i)) = p.points[i].transpose();
  out.F.resize(F.rows() + Eigen::Index(p.faces.size()), 3);
  out.F.topRows(F.rows()) = F;
  for (size_t f = 0; f < p.faces.size(); ++f) out.F.row(F.rows() + Eigen::Index(f)) << p.faces[f][0], p.faces[f][1], p.faces[f][2];
  return out;
}

Mesh fill_holes(const Mesh& mesh) {
  const FilledMesh filled = fill_holes(vertex_matrix(mesh), face_matrix(mesh));
  if (filled.loops == 0) return mesh;
  MeshSoup soup;
  for (Eigen::Index v = 0; v < filled.V.rows(); ++v) soup.points.push_back(filled.V.row(v).transpose());
  for (Eigen::Index f = 0; f < filled.F.rows(); ++f) soup.triangles.push_back({filled.F(f, 0), filled.F(f, 1), filled.F(f, 2)});
  return build_mesh(soup);
}

}  // namespace sdm
