#include "libstm/registration/zoomout.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/discrete_map_energy.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace sdm {

LaplaceBasis mesh_laplace_basis(const Mesh& mesh, int k) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) points.push_back(point(mesh, v));
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(mesh.n_faces());
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int c = 0;
    for (auto v : mesh.fv_range(f)) t[size_t(c++)] = v.idx();
    triangles.push_back(t);
  }
  return laplace_basis(points, triangles, k);
}

namespace {

// The functions and embeddings in single precision: the nearest rows and the small products
// between them need no more, and take half the time (DECISIONS 5, "Spectral refinement").
using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The first k functions of a basis at unit area (M-orthonormal for the mass over the area).
RowMatrix unit_functions(const LaplaceBasis& basis, int k) {
  return RowMatrix((basis.vectors.leftCols(k) * std::sqrt(basis.mass.sum())).cast<float>());
}

// Per query point, the indices of `points` within `window` of it: a uniform grid of cell `window`.
std::vector<std::vector<int>> search_windows(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& queries,
                                             double window) {
  struct CellHash {
    size_t operator()(const Eigen::Vector3i& c) const { return size_t(c.x()) * 73856093u ^ size_t(c.y()) * 19349663u ^ size_t(c.z()) * 83492791u; }
  };
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash> grid;
  auto cell = [&](const Eigen::Vector3d& p) { return Eigen::Vector3i((p / window).array().floor().cast<int>()); };
  for (size_t i = 0; i < points.size(); ++i) grid[cell(points[i])].push_back(int(i));
  std::vector<std::vector<int>> out(queries.size());
  for (size_t t = 0; t < queries.size(); ++t) {
    const Eigen::Vector3i c = cell(queries[t]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(c + Eigen::Vector3i(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int s : it->second)
            if ((points[size_t(s)] - queries[t]).norm() <= window) out[t].push_back(s);
        }
    std::sort(out[t].begin(), out[t].end());
  }
  return out;
}

// Rows [w * spatial, phi * C] (C empty: phi alone), the spatial part left out when w = 0. The
// spatial part first: it is most of the distance to a far candidate, so a partial sum over it
// rules most candidates out (nearest_rows).
// Intrinsic features (ZoomOutFeatures: a few columns per vertex, already weighted) follow the
// spatial part.
RowMatrix with_position(const RowMatrix& spectral, const std::vector<Eigen::Vector3d>& spatial, double w, const RowMatrix& features = {}) {
  const int d = w > 0 ? 3 : 0;
  const Eigen::Index m = features.rows() == spectral.rows() ? features.cols() : 0, k = spectral.cols();
  RowMatrix e(spectral.rows(), k + d + m);
  e.rightCols(k) = spectral;
  if (w > 0)
    for (Eigen::Index i = 0; i < e.rows(); ++i) e.row(i).head(3) = (w * spatial[size_t(i)]).cast<float>().transpose();
  if (m) e.middleCols(d, m) = features;
  return e;
}

RowMatrix embedding(const RowMatrix& phi, int k, const Eigen::MatrixXf& C, const std::vector<Eigen::Vector3d>& spatial, double w,
                    const RowMatrix& features = {}) {
  return with_position(C.size() ? RowMatrix(phi.leftCols(k) * C) : RowMatrix(phi.leftCols(k)), spatial, w, features);
}

// A vertex as a source point: a face around it, weight 1 at its corner.
SourcePoint vertex_point(const Mesh& mesh, int vertex) {
  const auto vh = mesh.vertex_handle(vertex);
  const auto f = *mesh.vf_range(vh).begin();
  int c = 0, at = 0;
  for (auto v : mesh.fv_range(f)) at = v == vh ? c : at, ++c;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  b[at] = 1;
  return {f.idx(), b};
}

// Pi Phi_S: per target vertex, the source functions at its source point (barycentric blend).
RowMatrix pulled_back(const Mesh& source, const std::vector<SourcePoint>& map, const RowMatrix& phi_s, int k) {
  RowMatrix g = RowMatrix::Zero(Eigen::Index(map.size()), k);
  for (size_t t = 0; t < map.size(); ++t) {
    int c = 0;
    for (auto v : source.fv_range(source.face_handle(map[t].face))) g.row(Eigen::Index(t)) += float(map[t].barycentric[c++]) * phi_s.row(v.idx()).head(k);
  }
  return g;
}

// The source vertex nearest to each query row among `candidates` (all when empty). Ties go to the
// lower index. Among candidates the rows are compared in single precision, a block of columns at
// a time, and a candidate is given up once its partial sum reaches the best distance so far.
std::vector<int> nearest_rows(const RowMatrix& queries, const RowMatrix& database, const std::vector<std::vector<int>>& candidates,
                              int threads) {
  const int n = int(queries.rows());
  std::vector<int> best(size_t(n), 0);
  if (!candidates.empty()) {
    const RowMatrix& q = queries;
    const RowMatrix& db = database;
    const Eigen::Index dims = db.cols();
    constexpr Eigen::Index kBlock = 16;
    parallel_for(n, 256, [&](int t) {
      float best_d = INFINITY;
      for (int s : candidates[size_t(t)]) {
        float d = 0;
        for (Eigen::Index c = 0; c < dims && d < best_d; c += kBlock) {
          const Eigen::Index w = std::min(kBlock, dims - c);
          d += (db.row(s).segment(c, w) - q.row(t).segment(c, w)).squaredNorm();
        }
        if (d < best_d) best_d = d, best[size_t(t)] = s;
      }
      // An empty window (a start point further than the window from every vertex): every row.
      if (candidates[size_t(t)].empty()) (database.rowwise() - queries.row(t)).rowwise().squaredNorm().minCoeff(&best[size_t(t)]);
    }, threads);
    return best;
  }
  const Eigen::VectorXf dn = database.rowwise().squaredNorm();
  const int block = 256;
  parallel_for((n + block - 1) / block, 1, [&](int b) {
    const int from = b * block, rows = std::min(block, n - from);
    const Eigen::MatrixXf cross = queries.middleRows(from, rows) * database.transpose();
    for (int r = 0; r < rows; ++r) {
      Eigen::Index at;
      (dn.transpose() - 2 * cross.row(r)).minCoeff(&at);
      best[size_t(from + r)] = int(at);
    }
  }, threads);
  return best;
}

// The point of the faces around source vertex s nearest to q in the rows' coordinates (the
// triangle each face spans there), as a source point.
SourcePoint nearest_point_around(const Mesh& source, int s, const Eigen::RowVectorXf& q, const RowMatrix& database) {
  SourcePoint best_point;
  double best_d = INFINITY;
  for (auto f : source.vf_range(source.vertex_handle(s))) {
    int corner[3], c = 0;
    for (auto v : source.fv_range(f)) corner[c++] = v.idx();
    const Eigen::RowVectorXd a = database.row(corner[0]).cast<double>();
    const Eigen::RowVectorXd e1 = database.row(corner[1]).cast<double>() - a, e2 = database.row(corner[2]).cast<double>() - a;
    const Eigen::RowVectorXd r = q.cast<double>() - a;
    const double m11 = e1.squaredNorm(), m12 = e1.dot(e2), m22 = e2.squaredNorm(), r1 = e1.dot(r), r2 = e2.dot(r);
    const double det = m11 * m22 - m12 * m12;
    // Candidates: the interior optimum when inside, else the best point of each edge.
    std::vector<Eigen::Vector2d> tries;
    if (det > 1e-300) {
      const double b = (m22 * r1 - m12 * r2) / det, g = (m11 * r2 - m12 * r1) / det;
      if (b >= 0 && g >= 0 && b + g <= 1) tries.emplace_back(b, g);
    }
    if (tries.empty()) {
      tries.emplace_back(m11 > 0 ? std::clamp(r1 / m11, 0.0, 1.0) : 0.0, 0.0);
      tries.emplace_back(0.0, m22 > 0 ? std::clamp(r2 / m22, 0.0, 1.0) : 0.0);
      const Eigen::RowVectorXd e3 = e2 - e1;  // from corner 1 to corner 2
      const double m33 = e3.squaredNorm();
      const double u = m33 > 0 ? std::clamp((r - e1).dot(e3) / m33, 0.0, 1.0) : 0.0;
      tries.emplace_back(1 - u, u);
    }
    for (const auto& bg : tries) {
      const double d = (r - bg[0] * e1 - bg[1] * e2).squaredNorm();
      if (d < best_d) best_d = d, best_point = {f.idx(), Eigen::Vector3d(1 - bg[0] - bg[1], bg[0], bg[1])};
    }
  }
  return best_point;
}

// The step's functional maps: C12 = Phi_T^+ Pi Phi_S from the map and (with s2t) C21 = Phi_S^+
// Pi' Phi_T from the source's map. `apart` (the discrete solver's pair, Ren et al. 2021) keeps them
// apart; else C12 is their mean (C21^T beside C12) and C21 = C12^T. Each made orthogonal (U V^T of its
// SVD: an isometry's functional map) with `orthogonal`.
std::pair<Eigen::MatrixXf, Eigen::MatrixXf> step_maps(const Mesh& source, const std::vector<SourcePoint>& map, const std::vector<int>& s2t,
                                                      const RowMatrix& phi_s, const RowMatrix& phi_t, const Eigen::VectorXf& mass_s,
                                                      const Eigen::VectorXf& mass_t, int k, bool apart, bool orthogonal) {
  const auto nearest_orthogonal = [&](Eigen::MatrixXf& C) {
    if (!orthogonal) return;
    const Eigen::BDCSVD<Eigen::MatrixXf> svd(C, Eigen::ComputeThinU | Eigen::ComputeThinV);
    C = svd.matrixU() * svd.matrixV().transpose();
  };
  Eigen::MatrixXf C12 = phi_t.leftCols(k).transpose() * (mass_t.asDiagonal() * pulled_back(source, map, phi_s, k)), C21;
  if (!s2t.empty()) {
    RowMatrix g(Eigen::Index(s2t.size()), k);
    for (size_t s = 0; s < s2t.size(); ++s) g.row(Eigen::Index(s)) = phi_t.row(s2t[s]).head(k);
    C21 = phi_s.leftCols(k).transpose() * (mass_s.asDiagonal() * g);
    if (!apart) C12 = 0.5f * (C12 + C21.transpose());
  }
  nearest_orthogonal(C12);
  if (C21.size() && apart) nearest_orthogonal(C21);
  else C21 = C12.transpose();
  return {C12, C21};
}

// The spectral part of the rows for mapping Q's vertices onto D's: Phi_Q C_qd against Phi_D, or with
// `discrete`, the discrete solver's stacked rows (discrete_map_energy.h).
DiscreteMapRows spectral_rows(const RowMatrix& phi_q, const Eigen::VectorXf& lambda_q, const RowMatrix& phi_d, const Eigen::VectorXf& lambda_d,
                              const Eigen::MatrixXf& c_qd, const Eigen::MatrixXf& c_dq, int k, const DiscreteMapWeights* discrete) {
  if (!discrete) return {RowMatrix(phi_q.leftCols(k) * c_qd), RowMatrix(phi_d.leftCols(k))};
  return discrete_map_rows(phi_q.leftCols(k), lambda_q.head(k), phi_d.leftCols(k), lambda_d.head(k), c_qd, c_dq, *discrete);
}

void check_zoomout_input(const Mesh& source, const LaplaceBasis& sb, const Mesh& target, const LaplaceBasis& tb,
                         const std::vector<SourcePoint>& start, const ZoomOutOptions& o) {
  if (start.size() != target.n_vertices())
    throw InputError("zoomout: " + std::to_string(start.size()) + " start points for " + std::to_string(target.n_vertices()) + " target vertices");
  if (sb.vectors.rows() != Eigen::Index(source.n_vertices()) || tb.vectors.rows() != Eigen::Index(target.n_vertices()))
    throw InputError("zoomout: a Laplace basis does not belong to its mesh");
  if (o.k_start < 1 || o.step < 1 || sb.vectors.cols() < o.k_end || tb.vectors.cols() < o.k_end)
    throw InputError("zoomout: the bases need k_end = " + std::to_string(o.k_end) + " functions and 1 <= k_start");
  for (const auto& p : start)
    if (p.face < 0 || p.face >= int(source.n_faces())) throw InputError("zoomout: a start point lies on no source face");
}

}  // namespace

std::vector<SourcePoint> zoomout(const Mesh& source, const LaplaceBasis& source_basis, const Mesh& target,
                                 const LaplaceBasis& target_basis, const std::vector<SourcePoint>& start, const ZoomOutOptions& o,
                                 const ZoomOutFeatures& features) {
  check_zoomout_input(source, source_basis, target, target_basis, start, o);
  const bool featured = features.source.cols() > 0 && o.feature_weight > 0;
  if (featured && (features.source.rows() != Eigen::Index(source.n_vertices()) || features.target.rows() != Eigen::Index(target.n_vertices()) ||
                   features.source.cols() != features.target.cols()))
    throw InputError("zoomout: the features do not have one row per vertex of each mesh and as many columns on both");
  const RowMatrix unit_f_s = featured ? RowMatrix(features.source.cast<float>()) : RowMatrix(),
                  unit_f_t = featured ? RowMatrix(features.target.cast<float>()) : RowMatrix();
  const int nt = int(target.n_vertices()), k_end = o.k_end;
  const RowMatrix phi_s = unit_functions(source_basis, k_end), phi_t = unit_functions(target_basis, k_end);
  const Eigen::VectorXf mass_t = (target_basis.mass / target_basis.mass.sum()).cast<float>(), mass_s = (source_basis.mass / source_basis.mass.sum()).cast<float>();
  const double source_scale = std::sqrt(source_basis.mass.sum());
  // The eigenvalues at unit area, and the discrete solver's weights when it is on.
  const Eigen::VectorXf lambda_s = (source_basis.values.head(k_end) * source_basis.mass.sum()).cast<float>(),
                        lambda_t = (target_basis.values.head(k_end) * target_basis.mass.sum()).cast<float>();
  const DiscreteMapWeights discrete_weights{1, o.bijectivity_weight, o.orthogonality_weight, o.commutativity_weight};
  const DiscreteMapWeights* discrete =
      o.bijectivity_weight > 0 || o.orthogonality_weight > 0 || o.commutativity_weight > 0 ? &discrete_weights : nullptr;
  // Spatial coordinates on the source: the start's points for the target's vertices (with `follow`,
  // each step's map's).
  std::vector<Eigen::Vector3d> start_points, source_points;
  for (const auto& p : start) start_points.push_back(position_of(source, p));
  for (auto v : source.vertices()) source_points.push_back(point(source, v));
  std::vector<Eigen::Vector3d> anchors = start_points;
  std::vector<std::vector<int>> t_windows, s_windows;
  const auto set_windows = [&](double window) {
    t_windows.clear(), s_windows.clear();
    if (window > 0) t_windows = search_windows(source_points, anchors, window * source_scale);
    if (window > 0 && o.bidirectional) s_windows = search_windows(anchors, source_points, window * source_scale);
  };
  set_windows(o.window);
  double window_now = o.window;
  std::vector<SourcePoint> map = start;
  // The source's vertices' target vertices (bidirectional): at first the target vertex whose start
  // point is nearest.
  std::vector<int> s2t;
  if (o.bidirectional) {
    const RowMatrix none_s(Eigen::Index(source_points.size()), 0), none_t(nt, 0);
    s2t = nearest_rows(embedding(none_s, 0, {}, source_points, 1), embedding(none_t, 0, {}, start_points, 1), s_windows, o.threads);
  }
  std::vector<int> sizes;
  for (int k = std::min(o.k_start, k_end);; k = std::min(k + o.step, k_end)) {
    sizes.push_back(k);
    if (k == k_end) break;
  }
  sizes.insert(sizes.end(), size_t(std::max(0, o.final_steps)), k_end);
  for (size_t i = 0; i < sizes.size(); ++i) {
    const int k = sizes[i];
    const double at = k_end > o.k_start ? double(k - o.k_start) / (k_end - o.k_start) : 1.0;
    const double window = o.window_end >= 0 ? (1 - at) * o.window + at * o.window_end : o.window;
    const bool follow = o.follow > 0 && i > 0;
    if (follow)
      for (size_t t = 0; t < size_t(nt); ++t) anchors[t] = start_points[t] + o.follow * (position_of(source, map[t]) - start_points[t]);
    if (follow || window != window_now) set_windows(window), window_now = window;
    const double w_end = o.spatial_weight_end >= 0 ? o.spatial_weight_end : o.spatial_weight;
    const double w = ((1 - at) * o.spatial_weight + at * w_end) / source_scale;
    const double fw_end = o.feature_weight_end >= 0 ? o.feature_weight_end : o.feature_weight;
    const float fw = float((1 - at) * o.feature_weight + at * fw_end);
    const RowMatrix f_s = featured ? RowMatrix(fw * unit_f_s) : RowMatrix(), f_t = featured ? RowMatrix(fw * unit_f_t) : RowMatrix();
    // C = Phi_T^T M_T Pi Phi_S (k x k), then Pi Phi_S ~ Phi_T C row by row (step_maps).
    const auto [C, C21] = step_maps(source, map, s2t, phi_s, phi_t, mass_s, mass_t, k, discrete != nullptr, o.orthogonal);
    const DiscreteMapRows rows = spectral_rows(phi_t, lambda_t, phi_s, lambda_s, C, C21, k, discrete);
    const RowMatrix queries = with_position(rows.queries, anchors, w, f_t), database = with_position(rows.database, source_points, w, f_s);
    const std::vector<int> nearest = nearest_rows(queries, database, t_windows, o.threads);
    if (i + 1 == sizes.size()) {
      parallel_for(nt, 256, [&](int t) { map[size_t(t)] = nearest_point_around(source, nearest[size_t(t)], queries.row(t), database); }, o.threads);
      return map;
    }
    for (int t = 0; t < nt; ++t) map[size_t(t)] = vertex_point(source, nearest[size_t(t)]);
    if (o.bidirectional) {
      const DiscreteMapRows back = spectral_rows(phi_s, lambda_s, phi_t, lambda_t, C21, C, k, discrete);
      s2t = nearest_rows(with_position(back.queries, source_points, w, f_s), with_position(back.database, anchors, w, f_t), s_windows, o.threads);
    }
  }
  return map;
}

std::vector<SourcePoint> refine_correspondence(const Mesh& source, const Mesh& target, const std::vector<SourcePoint>& start,
                                               const ZoomOutOptions& options) {
  LaplaceBasis sb, tb;
  run_concurrently([&] { sb = mesh_laplace_basis(source, options.k_end); }, [&] { tb = mesh_laplace_basis(target, options.k_end); });
  return zoomout(source, sb, target, tb, start, options, {});
}

}  // namespace sdm
