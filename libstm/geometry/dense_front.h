#pragma once
// The dense step of a supernodal Cholesky factorisation (supernodal_cholesky.h): factorise a
// supernode's front and form its update for the parent. Eigen decides its vector instructions when
// it is compiled, and the project is built for the x86-64 baseline (SSE2), where the contraction's
// fronts ran at 1-2 GFlop/s; the kernel is therefore also compiled for AVX2 with FMA
// (dense_front_avx2.cpp, where the compiler can) and the processor picks one at run time. Measured
// on the fronts of the CGAL meshes' contractions: 1.5-2.4 times faster (docs/DESIGN.md 6, "Dense
// kernels for the processor at hand").
namespace sdm {

// Which compiled kernel factor_front runs.
enum class DenseKernels { baseline, avx2 };

// The kernels factor_front uses on this processor: avx2 when this build has them and the processor
// has AVX2 and FMA, unless the environment variable SDM_DENSE_KERNELS is "baseline".
DenseKernels dense_kernels();

// Whether this build carries the AVX2 kernels and this processor can run them.
bool avx2_kernels_available();

// Factorises a front in place. `front`: m x m, column-major (leading dimension m), its lower
// triangle assembled; its leading k columns become L's (L11 L11^T = F11, L21 = F21 L11^-T).
// `update`: (m - k) x (m - k), column-major, receives F22 - L21 L21^T in its lower triangle (its
// strict upper triangle is left as F22's). False when F11 is not positive definite (front then
// undefined). `which` picks the kernel (the baseline when the AVX2 one is not available).
bool factor_front(double* front, int m, int k, double* update, DenseKernels which = dense_kernels());

}  // namespace sdm
