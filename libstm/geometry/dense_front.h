#pragma once
/// The dense step of a supernodal Cholesky factorisation (supernodal_cholesky.h): factorise a
/// supernode's front and form its update for the parent. Eigen decides its vector instructions when
/// it is compiled, and the project is built for the x86-64 baseline (SSE2), where the contraction's
/// fronts run slowly; the kernel is therefore also compiled for AVX2 with FMA
/// (dense_front_avx2.cpp, where the compiler can) and the processor picks one at run time
/// (docs/DECISIONS.md, section 2, "Dense kernels for the processor at hand"). Fronts up to 96 rows, and the solve's steps, are loops of
/// our own: Eigen's blocked routines cost more than the arithmetic there (DECISIONS 2, "Small fronts
/// and the solve in level-1 loops").
namespace sdm {

/// Which compiled kernel factor_front runs.
enum class DenseKernels { baseline, avx2 };

/// The kernels factor_front uses on this processor: avx2 when this build has them and the processor
/// has AVX2 and FMA, unless the environment variable SDM_DENSE_KERNELS is "baseline".
DenseKernels dense_kernels();

/// Whether this build carries the AVX2 kernels and this processor can run them.
bool avx2_kernels_available();

/// Factorises a front in place. `front`: m x m, column-major (leading dimension m), its lower
/// triangle assembled; its leading k columns become L's (L11 L11^T = F11, L21 = F21 L11^-T).
/// `update`: (m - k) x (m - k), column-major, receives F22 - L21 L21^T in its lower triangle (its
/// strict upper triangle is not written). The front's last m - k columns may serve as scratch. False
/// when F11 is not positive definite (front then undefined). `which` picks the kernel (the baseline
/// when the AVX2 one is not available).
bool factor_front(double* front, int m, int k, double* update, DenseKernels which = dense_kernels());

/// The two halves of a supernode's step in a solve with three right-hand sides. `L`: the supernode's
/// m x k block of the factor (column-major, leading dimension m: L11 on top, L21 below); `ys`: the
/// supernode's k rows of the right-hand sides, column j at ys + j * ldy; `gathered`: (m - k) x 3,
/// column-major, leading dimension m - k.
/// forward_front: ys <- L11^-1 ys, then gathered <- L21 ys (the caller subtracts it from the rows
/// below). backward_front: ys <- L11^-T (ys - L21^T gathered), gathered holding the solution's rows
/// below.
void forward_front(const double* L, int m, int k, double* ys, long ldy, double* gathered,
                   DenseKernels which = dense_kernels());
void backward_front(const double* L, int m, int k, double* ys, long ldy, const double* gathered,
                    DenseKernels which = dense_kernels());

}  // namespace sdm
