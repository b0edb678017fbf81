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
}  // namespace avx2
#else
namespace avx2 = baseline;  // never chosen: avx2_kernels_available() is false in such a build
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

namespace {

// Whether `which` runs the AVX2 copy: asked for, in this build, and taken by this processor.
bool use_avx2(DenseKernels which) { return which == DenseKernels::avx2 && avx2_kernels_available(); }

}  // namespace

bool factor_front(double* front, int m, int k, double* update, DenseKernels which) {
  return use_avx2(which) ? avx2::factor_front(front, m, k, update) : baseline::factor_front(front, m, k, update);
}

void forward_front(const double* L, int m, int k, double* ys, long ldy, double* gathered, DenseKernels which) {
  if (use_avx2(which)) avx2::forward_front(L, m, k, ys, ldy, gathered);
  else baseline::forward_front(L, m, k, ys, ldy, gathered);
}

void backward_front(const double* L, int m, int k, double* ys, long ldy, const double* gathered, DenseKernels which) {
  if (use_avx2(which)) avx2::backward_front(L, m, k, ys, ldy, gathered);
  else baseline::backward_front(L, m, k, ys, ldy, gathered);
}

}  // namespace sdm
