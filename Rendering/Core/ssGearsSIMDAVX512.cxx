// The GEARS per-pixel kernels (ssGearsKernels.h) compiled for AVX-512 (F, VL,
// BW, DQ), 512-bit vectors. Only the functions defined after the pragma get
// the instruction set; the solver calls them only on CPUs that have it
// (ResolveIsa).
#include "ssGearsKernels.h"

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq,prefer-vector-width=512")
#define SS_GEARS_LANES 16
#define SS_GEARS_KERNEL_NAMESPACE avx512
#include "ssGearsKernels.h"
#undef SS_GEARS_KERNEL_NAMESPACE
#undef SS_GEARS_LANES

namespace ss
{
namespace gears
{
const KernelTable& KernelsAVX512()
{
  return avx512::Table("avx512");
}
}
}
#pragma GCC pop_options
