// The contraction with each sparse Cholesky (ContractOptions::solver): Eigen's simplicial LDL^T
// and, where the build found SuiteSparse, CHOLMOD's supernodal LL^T give the supernodal solver's
// contraction up to rounding. Speed is compared by `sdm bench --solvers`, not here.
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/contract_mesh.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <catch2/catch.hpp>

TEST_CASE("Every available sparse solver gives the supernodal contraction", "[contract_mesh][supernodal_cholesky]") {
  const sdm::Mesh m = sdm::make_primitive("ypsilon");
  const Eigen::MatrixX3d V = sdm::vertex_matrix(m);
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  CHECK(sdm::sparse_solver_available(sdm::SparseSolver::supernodal));
  CHECK(sdm::sparse_solver_available(sdm::SparseSolver::eigen));
#ifdef SDM_HAVE_CHOLMOD
  CHECK(sdm::sparse_solver_available(sdm::SparseSolver::cholmod));
#else
  CHECK_FALSE(sdm::sparse_solver_available(sdm::SparseSolver::cholmod));
#endif
  // The raw options (uniform weights) and the proxy's (cotangent weights). The cotangent weights are
  // recomputed from the contracted shape each iteration, on triangles that degenerate, which
  // amplifies the solvers' rounding differences (ypsilon, as a fraction of the diagonal: about
  // 1e-13 uniform, up to 1.3e-8 cotangent).
  for (sdm::ContractOptions opt : {sdm::uniform_contraction(), sdm::ContractOptions{}}) {
    const double tolerance = opt.cotangent ? 1e-6 : 1e-10;
    const sdm::ContractResult ref = sdm::contract_mesh(m, opt);
    REQUIRE(ref.iterations > 0);
    for (auto solver : {sdm::SparseSolver::eigen, sdm::SparseSolver::cholmod}) {
      if (!sdm::sparse_solver_available(solver)) continue;
      opt.solver = solver;
      const sdm::ContractResult res = sdm::contract_mesh(m, opt);
      INFO("solver " << int(solver) << ", cotangent " << opt.cotangent);
      CHECK(res.iterations == ref.iterations);
      CHECK(res.factor_seconds > 0);
      REQUIRE(res.positions.rows() == ref.positions.rows());
      const double difference = (res.positions - ref.positions).rowwise().norm().maxCoeff() / diagonal;
      INFO("max difference / diagonal " << difference);
      CHECK(difference <= tolerance);
    }
  }
}
