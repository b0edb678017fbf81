#include "libstm/geometry/supernodal_cholesky.h"

#include "libstm/core/parallel.h"
#include "libstm/geometry/dense_front.h"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <cmath>

namespace sdm {

namespace {

// A symmetric pattern by rows of its strict upper triangle: row k lists the columns i < k.
struct UpperRows {
  std::vector<int> start, cols;
  int size() const { return int(start.size()) - 1; }
};

// Elimination tree (Liu's algorithm with path compression).
std::vector<int> elimination_tree(const UpperRows& up) {
  const int n = up.size();
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k)
    for (int q = up.start[k]; q < up.start[k + 1]; ++q)
      for (int r = up.cols[q]; r != -1 && r < k;) {
        const int next = ancestor[r];
        ancestor[r] = k;
        if (next == -1) parent[r] = k;
        r = next;
      }
  return parent;
}

// Postorder of a forest: order[t] is the node visited t-th; children in increasing order.
std::vector<int> postorder(const std::vector<int>& parent) {
  const int n = int(parent.size());
  std::vector<std::vector<int>> children(n);
  for (int j = 0; j < n; ++j)
    if (parent[j] >= 0) children[parent[j]].push_back(j);
  std::vector<int> order;
  order.reserve(n);
  std::vector<std::pair<int, size_t>> stack;
  for (int root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back({root, 0});
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < children[node].size()) {
        const int c = children[node][next++];
        stack.push_back({c, 0});
      } else {
        order.push_back(node);
        stack.pop_back();
      }
    }
  }
  return order;
}

// Fill-reducing order: AMD on the symmetric pattern, as Eigen's simplicial factorisations use;
// amd[old] = new index.
std::vector<int> amd_order(const Eigen::SparseMatrix<double>& A) {
  const int n = int(A.rows());
  std::vector<int> amd(n);
  // Through the self-adjoint view the ordering expands the lower triangle once; given the full
  // matrix, it formed A^T + A of it again (a third of the ordering's time).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  Eigen::AMDOrdering<int>()(A.selfadjointView<Eigen::Lower>(), inverse);
  for (int k = 0; k < n; ++k) amd[inverse.indices()(k)] = k;
  return amd;
}

// The strict upper triangle of A (lower triangle given) by rows, under the order p (p[old] = new).
UpperRows upper_rows(const Eigen::SparseMatrix<double>& A, const std::vector<int>& p) {
  const int n = int(A.rows());
  UpperRows up;
  up.start.assign(n + 1, 0);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
      if (it.row() != j) ++up.start[std::max(p[it.row()], p[j]) + 1];
  for (int k = 0; k < n; ++k) up.start[k + 1] += up.start[k];
  up.cols.resize(up.start[n]);
  std::vector<int> fill(up.start.begin(), up.start.end() - 1);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
      if (it.row() != j) {
        const int a = p[it.row()], b = p[j];
        up.cols[fill[std::max(a, b)]++] = std::min(a, b);
      }
  return up;
}

// The order `amd` followed by a postorder of its elimination tree: the same fill, and chains of
// columns with one structure (supernodes) contiguous, children before parents.
std::vector<int> postordered(const Eigen::SparseMatrix<double>& A, const std::vector<int>& amd) {
  const int n = int(amd.size());
  const std::vector<int> order = postorder(elimination_tree(upper_rows(A, amd)));
  std::vector<int> rank(n);
  for (int t = 0; t < n; ++t) rank[order[t]] = t;
  std::vector<int> perm(n);
  for (int i = 0; i < n; ++i) perm[i] = rank[amd[i]];
  return perm;
}

// The structure of L by columns: column j's rows are rows[start[j]..start[j + 1]), sorted.
struct ColumnStructure {
  std::vector<int> start, rows;
  int count(int j) const { return start[j + 1] - start[j]; }
};

// Row k of L is the subtree of the elimination tree spanned by row k of A; walking it for k in
// increasing order appends k to each column it meets, so every column's rows come out sorted
// (two passes: count, then fill).
ColumnStructure column_structure(const UpperRows& up, const std::vector<int>& parent) {
  const int n = up.size();
  ColumnStructure L;
  L.start.assign(n + 1, 0);
  std::vector<int> mark(n, -1);
  auto walk_rows = [&](auto&& visit) {
    std::fill(mark.begin(), mark.end(), -1);
    for (int k = 0; k < n; ++k) {
      mark[k] = k;
      visit(k, k);
      for (int q = up.start[k]; q < up.start[k + 1]; ++q)
        for (int j = up.cols[q]; mark[j] != k; j = parent[j]) {
          mark[j] = k;
          visit(j, k);
        }
    }
  };
  walk_rows([&](int j, int) { ++L.start[j + 1]; });
  for (int j = 0; j < n; ++j) L.start[j + 1] += L.start[j];
  L.rows.resize(L.start[n]);
  std::vector<int> fill(L.start.begin(), L.start.end() - 1);
  walk_rows([&](int j, int k) { L.rows[fill[j]++] = k; });
  return L;
}

// Columns [first, first + width) of L with the row list `rows` (the block's own columns first).
struct Group {
  int first, width;
  std::vector<int> rows;
  double zeros;  // explicit zeros of L taken on by merging (relaxed_supernodes)
};

// Fundamental supernodes: j + 1 joins j's when it is j's parent and has j's structure less j.
std::vector<Group> fundamental_supernodes(const ColumnStructure& L, const std::vector<int>& parent) {
  const int n = int(parent.size());
  std::vector<Group> groups;
  for (int j = 0; j < n;) {
    int last = j;
    while (last + 1 < n && parent[last] == last + 1 && L.count(last + 1) + 1 == L.count(last)) ++last;
    groups.push_back({j, last - j + 1, std::vector<int>(L.rows.begin() + L.start[j], L.rows.begin() + L.start[j + 1]), 0.0});
    j = last + 1;
  }
  return groups;
}

// Relaxed supernodes: a supernode absorbs its last child (the columns just before it) when few
// explicit zeros come with it. Dense blocks of a few columns more cost little, while very
// narrow ones spend their time in bookkeeping (thresholds as CHOLMOD's defaults).
std::vector<Group> relaxed_supernodes(std::vector<Group> groups, const std::vector<int>& parent) {
  std::vector<Group> merged;
  for (auto& g : groups) {
    if (!merged.empty() && g.first > 0 && parent[g.first - 1] == g.first) {
      Group& c = merged.back();
      const double width = c.width + g.width, rows = c.width + double(g.rows.size());
      const double zeros = c.zeros + g.zeros + c.width * (rows - double(c.rows.size()));
      const double entries = width * rows - width * (width - 1) / 2;
      const double z = zeros / entries;
      if (width <= 4 || (width <= 16 && z < 0.8) || (width <= 48 && z < 0.1) || z < 0.05) {
        c.rows.resize(c.width);
        c.rows.insert(c.rows.end(), g.rows.begin(), g.rows.end());
        c.width = int(width);
        c.zeros = zeros;
        continue;
      }
    }
    merged.push_back(std::move(g));
  }
  return merged;
}

}  // namespace

void SupernodalCholesky::analyze(const Eigen::SparseMatrix<double>& A, int threads) {
  n_ = int(A.rows());
  perm_ = postordered(A, amd_order(A));
  const UpperRows up = upper_rows(A, perm_);
  const std::vector<int> parent = elimination_tree(up);
  index_lower_triangle(A);
  const std::vector<Group> groups = relaxed_supernodes(fundamental_supernodes(column_structure(up, parent), parent), parent);
  sn_.clear();
  rows_.clear();
  std::vector<int> sn_of(n_, -1);
  size_t values = 0;
  for (const auto& g : groups) {
    Supernode s;
    s.first = g.first;
    s.width = g.width;
    s.row_start = int(rows_.size());
    rows_.insert(rows_.end(), g.rows.begin(), g.rows.end());
    s.row_end = int(rows_.size());
    s.value_start = values;
    values += size_t(s.row_end - s.row_start) * s.width;
    for (int c = g.first; c < g.first + g.width; ++c) sn_of[c] = int(sn_.size());
    sn_.push_back(s);
  }
  for (auto& s : sn_) {
    const int p = parent[s.first + s.width - 1];
    s.parent = p >= 0 ? sn_of[p] : -1;
  }
  values_.assign(values, 0.0);
  plan_threads(threads);
}

// Below this many floating-point operations a factorisation stays on one thread: a thread's start
// costs tens of microseconds. The ypsilon's 476 unknowns need 6.5e5, the bottle's 1566 1.2e7.
constexpr double kParallelFlops = 4e6;

// The subtrees for two threads: starting from the roots, the largest subtree is split (its root
// moved to the ancestors) while that shortens the estimated time, max(thread work) + ancestors,
// with the subtrees dealt largest first to the thread with less work.
void SupernodalCholesky::plan_threads(int threads) {
  const int count = int(sn_.size());
  children_.assign(count, {});
  std::vector<double> work(count, 0.0);
  std::vector<int> first(count);
  double total = 0;
  for (int id = 0; id < count; ++id) {
    const Supernode& s = sn_[id];
    const double k = s.width, r = double(s.row_end - s.row_start) - k;
    work[id] += k * k * k / 3 + r * k * k + r * r * k;
    first[id] = children_[id].empty() ? id : first[children_[id].front()];
    if (s.parent >= 0) children_[s.parent].push_back(id), work[s.parent] += work[id];
    else total += work[id];
  }
  for (auto& ids : order_) ids.clear();
  if (threads < 2 || total < kParallelFlops) {
    for (int id = 0; id < count; ++id) order_[0].push_back(id);
    return;
  }
  std::vector<int> frontier, top;
  for (int id = 0; id < count; ++id)
    if (sn_[id].parent < 0) frontier.push_back(id);
  std::vector<std::pair<int, int>> subtrees[2];  // the best plan's, as ranges [first, last]
  double best = total;
  for (int step = 0; step < 256 && !frontier.empty(); ++step) {
    std::sort(frontier.begin(), frontier.end(), [&](int a, int b) { return work[a] > work[b] || (work[a] == work[b] && a < b); });
    double load[2] = {0, 0};
    std::vector<std::pair<int, int>> bins[2];
    for (int id : frontier) {
      const int t = load[1] < load[0] ? 1 : 0;
      load[t] += work[id];
      bins[t].push_back({first[id], id});
    }
    const double time = std::max(load[0], load[1]) + (total - load[0] - load[1]);
    if (time < best) {
      best = time;
      for (int t = 0; t < 2; ++t) subtrees[t] = bins[t];
      order_[2] = top;
    }
    const int split = frontier.front();
    frontier.erase(frontier.begin());
    top.push_back(split);
    frontier.insert(frontier.end(), children_[split].begin(), children_[split].end());
  }
  if (subtrees[1].empty()) {  // no split paid: serial
    order_[2].clear();
    for (int id = 0; id < count; ++id) order_[0].push_back(id);
    return;
  }
  for (int t = 0; t < 2; ++t) {
    std::sort(subtrees[t].begin(), subtrees[t].end());
    for (const auto& [from, to] : subtrees[t])
      for (int id = from; id <= to; ++id) order_[t].push_back(id);
  }
  std::sort(order_[2].begin(), order_[2].end());
}

void SupernodalCholesky::index_lower_triangle(const Eigen::SparseMatrix<double>& A) {
  col_start_.assign(n_ + 1, 0);
  for (int j = 0; j < n_; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) ++col_start_[std::min(perm_[it.row()], perm_[j]) + 1];
  for (int j = 0; j < n_; ++j) col_start_[j + 1] += col_start_[j];
  col_row_.resize(col_start_[n_]);
  col_src_.resize(col_start_[n_]);
  std::vector<int> fill(col_start_.begin(), col_start_.end() - 1);
  for (int j = 0; j < n_; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      const int a = perm_[it.row()], b = perm_[j];
      const int q = fill[std::min(a, b)]++;
      col_row_[q] = std::max(a, b);
      col_src_[q] = int(&it.value() - A.valuePtr());
    }
}

bool SupernodalCholesky::factor_supernode(int id, const double* a, Scratch& sc) {
  const Supernode& s = sn_[id];
  const int k = s.width, m = s.row_end - s.row_start;
  const int* rows = rows_.data() + s.row_start;
  for (int t = 0; t < m; ++t) sc.local[rows[t]] = t;
  if (sc.work.size() < size_t(m) * m) sc.work.resize(size_t(m) * m);
  Eigen::Map<Eigen::MatrixXd> front(sc.work.data(), m, m);
  front.setZero();
  for (int c = 0; c < k; ++c) {
    const int j = s.first + c;
    for (int q = col_start_[j]; q < col_start_[j + 1]; ++q) front(sc.local[col_row_[q]], c) += a[col_src_[q]];
  }
  // The children's updates, the last child first (the order a serial stack pops them in).
  for (auto child = children_[id].rbegin(); child != children_[id].rend(); ++child) {
    Eigen::MatrixXd& u = updates_[*child];
    const Supernode& c = sn_[*child];
    const int r = int(u.rows());
    sc.index.resize(r);
    for (int t = 0; t < r; ++t) sc.index[t] = sc.local[rows_[c.row_start + c.width + t]];
    for (int y = 0; y < r; ++y) {
      double* dst = front.col(sc.index[y]).data();
      const double* src = u.col(y).data();
      for (int x = y; x < r; ++x) dst[sc.index[x]] += src[x];
    }
    u = Eigen::MatrixXd();
  }
  if (m > k) updates_[id].resize(m - k, m - k);
  if (!factor_front(front.data(), m, k, updates_[id].data())) return false;
  Eigen::Map<Eigen::MatrixXd>(values_.data() + s.value_start, m, k) = front.leftCols(k);
  return true;
}

bool SupernodalCholesky::factorize(const Eigen::SparseMatrix<double>& A) {
  const double* a = A.valuePtr();
  updates_.assign(sn_.size(), Eigen::MatrixXd());
  auto run = [&](const std::vector<int>& ids) {
    Scratch sc;
    sc.local.assign(n_, -1);
    for (int id : ids)
      if (!factor_supernode(id, a, sc)) return false;
    return true;
  };
  bool ok0 = true, ok1 = true;
  if (two_threads()) run_concurrently([&] { ok1 = run(order_[1]); }, [&] { ok0 = run(order_[0]); });
  else ok0 = run(order_[0]);
  const bool ok = ok0 && ok1 && run(order_[2]);
  updates_.clear();
  return ok && std::all_of(values_.begin(), values_.end(), [](double v) { return std::isfinite(v); });
}

Eigen::MatrixX3d SupernodalCholesky::solve(const Eigen::MatrixX3d& B) const {
  Eigen::MatrixX3d y(n_, 3);
  for (int i = 0; i < n_; ++i) y.row(perm_[i]) = B.row(i);
  std::vector<double> gathered;
  auto block = [&](const Supernode& s) { return values_.data() + s.value_start; };
  for (const Supernode& s : sn_) {
    const int k = s.width, below = s.row_end - s.row_start - k;
    gathered.resize(size_t(3) * below);
    forward_front(block(s), k + below, k, &y(s.first, 0), n_, gathered.data());
    for (int t = 0; t < below; ++t)
      for (int j = 0; j < 3; ++j) y(rows_[s.row_start + k + t], j) -= gathered[size_t(j) * below + t];
  }
  for (auto it = sn_.rbegin(); it != sn_.rend(); ++it) {
    const Supernode& s = *it;
    const int k = s.width, below = s.row_end - s.row_start - k;
    gathered.resize(size_t(3) * below);
    for (int t = 0; t < below; ++t)
      for (int j = 0; j < 3; ++j) gathered[size_t(j) * below + t] = y(rows_[s.row_start + k + t], j);
    backward_front(block(s), k + below, k, &y(s.first, 0), n_, gathered.data());
  }
  Eigen::MatrixX3d x(n_, 3);
  for (int i = 0; i < n_; ++i) x.row(i) = y.row(perm_[i]);
  return x;
}

}  // namespace sdm
