// factor_front's AVX2 + FMA copy (dense_front.h). CMake compiles this file with -mavx2 -mfma where
// the compiler takes them; otherwise it is empty and only the baseline exists.
#if defined(__AVX2__) && defined(__FMA__)
// Eigen's namespace renamed for this file: its inline functions and templates, compiled here with
// AVX2, get names of their own, so the linker never merges them with the baseline's copies.
#define Eigen sdm_avx2_eigen
#define SDM_DENSE_KERNEL_NS avx2
#include "libstm/geometry/dense_front_kernel.h"
#endif
