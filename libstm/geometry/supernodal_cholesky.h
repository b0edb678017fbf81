#pragma once
/// Sparse Cholesky (LL^T) of a symmetric positive definite matrix, supernodal and multifrontal:
/// columns of L with the same structure are stored and updated as dense blocks. The contraction
/// factorises a matrix with the same pattern a dozen times; Eigen's simplicial LDL^T does that
/// one scalar at a time, which made it most of the skeleton's time.
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace sdm {

class SupernodalCholesky {
 public:
  /// Ordering (AMD, then an elimination-tree postorder) and structure of L, from the pattern of
  /// the lower triangle of A (column-major, compressed; the diagonal present). `threads` 1 keeps
  /// every factorisation on the calling thread; 2 lets factorize() use a second one where it pays.
  void analyze(const Eigen::SparseMatrix<double>& A_lower, int threads = 2);
  /// Numeric factorisation of a matrix with the analysed pattern; false when it is not positive
  /// definite (or not finite). Matrices worth it (analyze's plan) are factorised on two threads:
  /// disjoint subtrees of the elimination tree on each, then their ancestors. Every supernode sums
  /// its children's updates in the serial order, so the result is the same bit for bit.
  bool factorize(const Eigen::SparseMatrix<double>& A_lower);
  /// Whether factorize() uses a second thread (analyze's plan).
  bool two_threads() const { return !order_[1].empty(); }
  /// Solves A X = B after a successful factorize().
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B) const;

 private:
  /// Fills col_start_, col_row_, col_src_ from A under perm_.
  void index_lower_triangle(const Eigen::SparseMatrix<double>& A_lower);
  /// Children lists and, for `threads` 2, the two-thread plan, from the supernodes' parents.
  void plan_threads(int threads);
  /// Per-thread scratch of the numeric factorisation.
  struct Scratch {
    std::vector<int> local;     ///< row of L -> row in the current front
    std::vector<double> work;   ///< the front, reused rather than allocated per supernode
    std::vector<int> index;
  };
  /// Assembles supernode `id`'s front from A's values `a` and its children's updates (releasing
  /// them), factorises its columns into values_ and leaves its own update in updates_[id].
  bool factor_supernode(int id, const double* a, Scratch& scratch);

  int n_ = 0;
  std::vector<int> perm_;  ///< perm_[old] = new index
  /// Permuted lower triangle: per new column, its rows and the position of each value in A's
  /// value array, so a factorisation reads A without searching it.
  std::vector<int> col_start_, col_row_, col_src_;
  /// Supernodes: columns [first, first + width) share the row list rows[row_start..row_end) of
  /// L (the block's own columns first); L is stored per supernode as a dense column-major block.
  struct Supernode {
    int first = 0, width = 0;
    int row_start = 0, row_end = 0;
    size_t value_start = 0;
    int parent = -1;
  };
  std::vector<Supernode> sn_;
  std::vector<int> rows_;
  std::vector<double> values_;
  std::vector<std::vector<int>> children_;     ///< per supernode, increasing
  std::vector<Eigen::MatrixXd> updates_;        ///< update matrices not yet added to their parent
  /// The supernodes in the order each list factorises them: [0] on the calling thread and [1] on a
  /// second one (whole subtrees each, children before parents), then [2] (their ancestors) on the
  /// calling thread. Serial: every supernode in [0], [1] and [2] empty.
  std::vector<int> order_[3];
};

/// SupernodalCholesky behind the interface of Eigen's sparse factorisations (analyzePattern,
/// factorize, info, solve), for code written against them (the contraction iterations).
class SupernodalSolver {
 public:
  void analyzePattern(const Eigen::SparseMatrix<double>& A) { llt_.analyze(A); }
  void factorize(const Eigen::SparseMatrix<double>& A) { ok_ = llt_.factorize(A); }
  Eigen::ComputationInfo info() const { return ok_ ? Eigen::Success : Eigen::NumericalIssue; }
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B) const { return llt_.solve(B); }

 private:
  SupernodalCholesky llt_;
  bool ok_ = false;
};

}  // namespace sdm
