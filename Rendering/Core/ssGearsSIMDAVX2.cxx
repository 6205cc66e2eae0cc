// The GEARS per-pixel kernels (ssGearsKernels.h) compiled for AVX2. Only the
// functions defined after the pragma get the instruction set; the solver
// calls them only on CPUs that have it (ResolveIsa).
#include "ssGearsKernels.h"

#pragma GCC push_options
#pragma GCC target("avx2")
#define SS_GEARS_LANES 8
#define SS_GEARS_KERNEL_NAMESPACE avx2
#include "ssGearsKernels.h"
#undef SS_GEARS_KERNEL_NAMESPACE
#undef SS_GEARS_LANES

namespace ss
{
namespace gears
{
const KernelTable& KernelsAVX2()
{
  return avx2::Table("avx2");
}
}
}
#pragma GCC pop_options
