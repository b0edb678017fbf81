#pragma once
// Sparse Cholesky (LL^T) of a symmetric positive definite matrix, supernodal and multifrontal:
// columns of L with the same structure are stored and updated as dense blocks. The contraction
// factorises a matrix with the same pattern a dozen times; Eigen's simplicial LDL^T does that
// one scalar at a time, which made it most of the skeleton's time (bottle: 4.8 ms of about 7 ms
// per iteration).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace sdm {

class SupernodalCholesky {
 public:
  // Ordering (AMD, then an elimination-tree postorder) and structure of L, from the pattern of
  // the lower triangle of A (column-major, compressed; the diagonal present).
  void analyze(const Eigen::SparseMatrix<double>& A_lower);
  // Numeric factorisation of a matrix with the analysed pattern; false when it is not positive
  // definite (or not finite).
  bool factorize(const Eigen::SparseMatrix<double>& A_lower);
  // Solves A X = B after a successful factorize().
  Eigen::MatrixX3d solve(const Eigen::MatrixX3d& B) const;

 private:
  // Fills col_start_, col_row_, col_src_ from A under perm_.
  void index_lower_triangle(const Eigen::SparseMatrix<double>& A_lower);

  int n_ = 0;
  std::vector<int> perm_;  // perm_[old] = new index
  // Permuted lower triangle: per new column, its rows and the position of each value in A's
  // value array, so a factorisation reads A without searching it.
  std::vector<int> col_start_, col_row_, col_src_;
  // Supernodes: columns [first, first + width) share the row list rows[row_start..row_end) of
  // L (the block's own columns first); L is stored per supernode as a dense column-major block.
  struct Supernode {
    int first = 0, width = 0;
    int row_start = 0, row_end = 0;
    size_t value_start = 0;
    int parent = -1;
  };
  std::vector<Supernode> sn_;
  std::vector<int> rows_;
  std::vector<double> values_;
};

}  // namespace sdm
