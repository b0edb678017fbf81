#include "libstm/geometry/dense_front.h"

#define SDM_DENSE_KERNEL_NS baseline
#include "libstm/geometry/dense_front_kernel.h"

#include <cstdlib>
#include <cstring>

namespace sdm {

#ifdef SDM_HAVE_AVX2_KERNELS
namespace avx2 {
bool factor_front(double* front, int m, int k, double* update);
void forward_front(const double* L, int m, int k, double* ys, long ldy, double* gathered);
void backward_front(const double* L, int m, int k, double* ys, long ldy, const double* gathered);
}
#endif

bool avx2_kernels_available() {
#ifdef SDM_HAVE_AVX2_KERNELS
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
#else
  return false;
#endif
}

DenseKernels dense_kernels() {
  static const DenseKernels chosen = [] {
    const char* forced = std::getenv("SDM_DENSE_KERNELS");
    if (forced && std::strcmp(forced, "baseline") == 0) return DenseKernels::baseline;
    return avx2_kernels_available() ? DenseKernels::avx2 : DenseKernels::baseline;
  }();
  return chosen;
}

bool factor_front(double* front, int m, int k, double* update, DenseKernels which) {
#ifdef SDM_HAVE_AVX2_KERNELS
  if (which == DenseKernels::avx2 && avx2_kernels_available()) return avx2::factor_front(front, m, k, update);
#else
  (void)which;
#endif
  return baseline::factor_front(front, m, k, update);
}

void forward_front(const double* L, int m, int k, double* ys, long ldy, double* gathered, DenseKernels which) {
#ifdef SDM_HAVE_AVX2_KERNELS
  if (which == DenseKernels::avx2 && avx2_kernels_available()) return avx2::forward_front(L, m, k, ys, ldy, gathered);
#else
  (void)which;
#endif
  baseline::forward_front(L, m, k, ys, ldy, gathered);
}

void backward_front(const double* L, int m, int k, double* ys, long ldy, const double* gathered, DenseKernels which) {
#ifdef SDM_HAVE_AVX2_KERNELS
  if (which == DenseKernels::avx2 && avx2_kernels_available()) return avx2::backward_front(L, m, k, ys, ldy, gathered);
#else
  (void)which;
#endif
  baseline::backward_front(L, m, k, ys, ldy, gathered);
}

}  // namespace sdm
