#include "libstm/skeleton/surgery.h"

#include "libstm/skeleton/four_ary_heap.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <limits>

namespace sdm {

namespace {

// A queued collapse of i into j, with the stamps i and j had when it was queued. The keys
// (cost, i, j) are distinct, so any priority queue pops the live entries in the same order.
struct Collapse {
  double cost;
  int i, j;
  unsigned si, sj;
  bool operator<(const Collapse& o) const {
    if (cost != o.cost) return cost < o.cost;
    if (i != o.i) return i < o.i;
    return j < o.j;
  }
};

// The state of one surgery: the complex (faces, neighbours, faces per vertex), the clusters, the
// cost terms, and the queue of collapses.
class Surgery {
 public:
  Surgery(const Eigen::MatrixX3d& O, const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& F, const InsideMesh& in,
          int genus, const SkeletonOptions& opt);
  void run(SkeletonStats& st);
  SkeletonGraph graph() const;

 private:
  void build_complex(const Eigen::MatrixX3i& F);
  void build_quadrics();
  Eigen::Vector3d centroid(int i) const { return Eigen::Vector3d(csum_[i] / ccount_[i]); }
  bool has_face(int i, int j) const;
  bool has_triangle(int i, int j, int k) const;
  void update_ring(int i);
  double cost(int i, int j) const;
  bool keeps_cycles(int i, int j) const;
  bool stale(const Collapse& e) const;
  void queue(int i, int j) { heap_.push({cost(i, j), i, j, stamp_[i], stamp_[j]}); }
  void push(int i, int j) {
    if (has_face(i, j)) queue(i, j);
  }
  void mark_face_neighbours(int k);
  void collapse(int i, int j);
  void move_faces(int i, int j);
  void move_neighbours(int i, int j);
  void requeue_around(int j);
  bool forced_collapse();

  const Eigen::MatrixX3d& P_;
  const InsideMesh& in_;
  const int genus_, n_, m_;
  const SkeletonOptions& opt_;
  std::vector<std::vector<int>> nbr_, vfaces_;  // neighbours (sorted) and faces of each vertex
  std::vector<std::array<int, 3>> faces_;
  std::vector<char> face_alive_, alive_;
  int faces_left_;
  std::vector<Eigen::Matrix4d> Q_;  // edge quadrics
  // Cluster of each vertex: sum and count of its original positions, and the vertex it went into.
  std::vector<Eigen::Vector3d> csum_;
  std::vector<int> ccount_, parent_;
  // Sum of the edge lengths around each vertex (Au et al.'s sampling cost), kept up to date by
  // the collapses: positions never move, so only vertices whose neighbours changed need it anew.
  std::vector<double> ring_length_;
  // A heap with lazy deletion: a collapse invalidates the entries of the vertices it touches
  // (stamps) and queues them anew. Popping a stale entry costs a sift through the whole heap, while
  // a sweep costs a few comparisons per entry: stale entries are swept out as soon as they make up
  // half of the heap (the heap operations are most of the surgery's time; sweeping at three
  // quarters took 25-40 % longer).
  std::vector<unsigned> stamp_;
  FourAryHeap<Collapse> heap_;
  // The vertices sharing a face with k, marked once, so that queueing all of k's edges does not
  // scan k's faces for every one of them.
  std::vector<unsigned> face_mark_;
  unsigned face_marks_ = 0;
  // Scratch of keeps_cycles and move_faces, kept so that a collapse allocates nothing.
  mutable std::vector<int> common_;
  std::vector<int> moving_;
};

Surgery::Surgery(const Eigen::MatrixX3d& O, const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& F, const InsideMesh& in,
                 int genus, const SkeletonOptions& opt)
    : P_(P), in_(in), genus_(genus), n_(int(P.rows())), m_(int(F.rows())), opt_(opt) {
  build_complex(F);
  build_quadrics();
  csum_.resize(n_);
  ccount_.assign(n_, 1);
  parent_.resize(n_);
  for (int i = 0; i < n_; ++i) csum_[i] = O.row(i), parent_[i] = i;
  ring_length_.assign(n_, 0.0);
  for (int i = 0; i < n_; ++i) update_ring(i);
  stamp_.assign(n_, 0);
  face_mark_.assign(n_, 0);
  for (int i = 0; i < n_; ++i)
    for (int j : nbr_[i]) push(i, j);
}

void Surgery::build_complex(const Eigen::MatrixX3i& F) {
  nbr_.resize(n_);
  vfaces_.resize(n_);
  faces_.resize(m_);
  face_alive_.assign(m_, 1);
  alive_.assign(n_, 1);
  for (int f = 0; f < m_; ++f) {
    for (int k = 0; k < 3; ++k) {
      faces_[f][k] = F(f, k);
      vfaces_[F(f, k)].push_back(f);
      nbr_[F(f, k)].push_back(F(f, (k + 1) % 3));
      nbr_[F(f, (k + 1) % 3)].push_back(F(f, k));
    }
  }
  for (auto& v : nbr_) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  faces_left_ = m_;
}

// Q_i = sum over the edges at i of K^T K, with K p the cross product of the edge's direction with
// the vector from i to p: p^T Q_i p is the sum of squared distances from p to the edges' lines.
void Surgery::build_quadrics() {
  Q_.assign(n_, Eigen::Matrix4d::Zero());
  for (int i = 0; i < n_; ++i)
    for (int k : nbr_[i]) {
      Eigen::Vector3d a = P_.row(k) - P_.row(i);
      const double len = a.norm();
      if (!(len > 0)) continue;
      a /= len;
      Eigen::Matrix<double, 3, 4> K;
      K << 0, -a.z(), a.y(), 0, a.z(), 0, -a.x(), 0, -a.y(), a.x(), 0, 0;
      K.col(3) = -a.cross(Eigen::Vector3d(P_.row(i)));
      Q_[i] += K.transpose() * K;
    }
}

bool Surgery::has_face(int i, int j) const {
  for (int f : vfaces_[i])
    if (faces_[f][0] == j || faces_[f][1] == j || faces_[f][2] == j) return true;
  return false;
}

bool Surgery::has_triangle(int i, int j, int k) const {
  for (int f : vfaces_[i]) {
    const auto& t = faces_[f];
    const bool hj = t[0] == j || t[1] == j || t[2] == j, hk = t[0] == k || t[1] == k || t[2] == k;
    if (hj && hk) return true;
  }
  return false;
}

void Surgery::update_ring(int i) {
  double ring = 0;
  for (int k : nbr_[i]) ring += (P_.row(i) - P_.row(k)).norm();
  ring_length_[i] = ring;
}

double Surgery::cost(int i, int j) const {
  const Eigen::Vector4d pj(P_(j, 0), P_(j, 1), P_(j, 2), 1.0);
  const double shape = pj.dot((Q_[i] + Q_[j]) * pj);
  const double sampling = (P_.row(i) - P_.row(j)).norm() * ring_length_[i];
  return opt_.shape_weight * shape + opt_.sampling_weight * sampling;
}

// Collapsing i into j kills the loop i-j-k of every common neighbour k without a triangle ijk.
// Allowed only when the loop bounds a disk inside the volume (a cross-section of a tube), not
// when it goes around a handle: tested on the triangle of the cluster centroids, shrunk a
// little because single-vertex clusters lie on the surface.
bool Surgery::keeps_cycles(int i, int j) const {
  common_.clear();
  std::set_intersection(nbr_[i].begin(), nbr_[i].end(), nbr_[j].begin(), nbr_[j].end(), std::back_inserter(common_));
  for (int k : common_) {
    if (has_triangle(i, j, k)) continue;
    const Eigen::Vector3d a = centroid(i), b = centroid(j), c = centroid(k);
    const Eigen::Vector3d g = (a + b + c) / 3.0;
    if (in_.triangle_crosses(g + 0.9 * (a - g), g + 0.9 * (b - g), g + 0.9 * (c - g))) return false;
  }
  return true;
}

bool Surgery::stale(const Collapse& e) const {
  return !alive_[e.i] || !alive_[e.j] || e.si != stamp_[e.i] || e.sj != stamp_[e.j];
}

void Surgery::mark_face_neighbours(int k) {
  ++face_marks_;
  for (int f : vfaces_[k])
    for (int x : faces_[f]) face_mark_[x] = face_marks_;
}

// i's faces go to j; those that held j, or that become copies of one of j's, die.
void Surgery::move_faces(int i, int j) {
  moving_.assign(vfaces_[i].begin(), vfaces_[i].end());
  for (int f : moving_) {
    auto& t = faces_[f];
    const bool hj = t[0] == j || t[1] == j || t[2] == j;
    bool kill = hj;
    if (!hj) {
      for (int& x : t)
        if (x == i) x = j;
      for (int g : vfaces_[j]) {
        const auto& u = faces_[g];
        if (std::is_permutation(u.begin(), u.end(), t.begin())) kill = true;
      }
    }
    if (kill) {
      face_alive_[f] = 0;
      --faces_left_;
      for (int x : t) {
        auto& vf = vfaces_[x == i ? i : x];
        vf.erase(std::remove(vf.begin(), vf.end(), f), vf.end());
      }
      auto& vi = vfaces_[i];
      vi.erase(std::remove(vi.begin(), vi.end(), f), vi.end());
    } else {
      vfaces_[j].push_back(f);
    }
  }
  vfaces_[i].clear();
}

// i's neighbours become j's; the cluster, quadric and ring lengths follow.
void Surgery::move_neighbours(int i, int j) {
  const std::vector<int> old_nbr = std::move(nbr_[i]);
  for (int k : old_nbr) {
    erase_sorted(nbr_[k], i);
    if (k == j) continue;
    insert_sorted(nbr_[k], j);
    insert_sorted(nbr_[j], k);
  }
  nbr_[i].clear();
  Q_[j] += Q_[i];
  csum_[j] += csum_[i];
  ccount_[j] += ccount_[i];
  parent_[i] = j;
  alive_[i] = 0;
  update_ring(j);
  for (int k : old_nbr)
    if (k != j) update_ring(k);
}

// The costs of j's edges and of its neighbours' changed (their ring lengths did): their queued
// entries go stale and every edge of a face at a neighbour is queued anew.
void Surgery::requeue_around(int j) {
  ++stamp_[j];
  for (int k : nbr_[j]) ++stamp_[k];
  for (int k : nbr_[j]) {
    mark_face_neighbours(k);
    if (face_mark_[j] == face_marks_) queue(j, k), queue(k, j);  // j and k share a face
    for (int l : nbr_[k])
      if (l != j && face_mark_[l] == face_marks_) queue(k, l);
  }
}

void Surgery::collapse(int i, int j) {
  move_faces(i, j);
  move_neighbours(i, j);
  requeue_around(j);
}

// Every remaining collapse would break a cycle: take the cheapest anyway. False when no face edge
// is left to collapse.
bool Surgery::forced_collapse() {
  double best = std::numeric_limits<double>::infinity();
  int bi = -1, bj = -1;
  for (int f = 0; f < m_; ++f) {
    if (!face_alive_[f]) continue;
    for (int k = 0; k < 3; ++k)
      for (int s = 0; s < 2; ++s) {
        const int i = faces_[f][(k + s) % 3], j = faces_[f][(k + 1 - s + 3) % 3];
        const double c = cost(i, j);
        if (c < best || (c == best && std::make_pair(i, j) < std::make_pair(bi, bj))) best = c, bi = i, bj = j;
      }
  }
  if (bi < 0) return false;
  collapse(bi, bj);
  return true;
}

void Surgery::run(SkeletonStats& st) {
  size_t sweep_at = size_t(n_) + 64;
  while (faces_left_ > 0) {
    if (heap_.size() > sweep_at) {
      heap_.sweep([&](const Collapse& e) { return stale(e); });
      sweep_at = std::max(size_t(n_) + 64, 2 * heap_.size());
    }
    if (heap_.empty()) {
      if (!forced_collapse()) break;
      ++st.forced_collapses;
      continue;
    }
    const Collapse e = heap_.pop();
    if (stale(e)) continue;
    if (!has_face(e.i, e.j)) continue;
    // A part of genus 0 has no handle for a loop to go around: every loop bounds a disk.
    if (genus_ > 0 && !keeps_cycles(e.i, e.j)) {
      ++st.refused_collapses;
      continue;
    }
    collapse(e.i, e.j);
  }
}

SkeletonGraph Surgery::graph() const {
  SkeletonGraph g;
  std::vector<int> node_of(n_, -1);
  for (int i = 0; i < n_; ++i)
    if (alive_[i]) {
      node_of[i] = int(g.pos.size());
      g.pos.push_back(centroid(i));
      g.fallback.push_back(P_.row(i));
      g.verts.emplace_back();
    }
  for (int v = 0; v < n_; ++v) {
    int r = v;
    while (parent_[r] != r) r = parent_[r];
    g.verts[node_of[r]].push_back(v);
  }
  for (int i = 0; i < n_; ++i)
    if (alive_[i])
      for (int k : nbr_[i])
        if (i < k) g.edges.insert({node_of[i], node_of[k]});
  return g;
}

}  // namespace

SkeletonGraph connectivity_surgery(const Eigen::MatrixX3d& original, const Eigen::MatrixX3d& contracted,
                                   const Eigen::MatrixX3i& F, const InsideMesh& inside, int genus,
                                   const SkeletonOptions& options, SkeletonStats* stats) {
  Surgery surgery(original, contracted, F, inside, genus, options);
  SkeletonStats st;
  surgery.run(st);
  if (stats) {
    stats->refused_collapses += st.refused_collapses;
    stats->forced_collapses += st.forced_collapses;
  }
  return surgery.graph();
}

}  // namespace sdm
