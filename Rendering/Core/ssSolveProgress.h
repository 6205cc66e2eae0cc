// Progress and abort of the CPU solvers (ssReference, ssGEARS), without VTK:
// the caller (vtkSoftShadowPass) turns the calls into VTK's ProgressEvent and
// polls vtkRenderWindow::CheckAbortStatus.
#ifndef ssSolveProgress_h
#define ssSolveProgress_h

#include <functional>

namespace ss
{
/// Called by a solver on the thread that called Solve, between chunks of
/// work, with the fraction done in [0, 1]; returning false stops the solve
/// (the pixels not reached stay NaN). An empty function is never called.
using SolveProgress = std::function<bool(double fractionDone)>;

/// `progress` seen by a part of the work that spans [from, to] of it: the
/// part's fraction f is reported as from + (to - from) f. Empty when
/// `progress` is (so the part skips its calls). `progress` must outlive it.
inline SolveProgress SubProgress(const SolveProgress& progress, double from, double to)
{
  if (!progress)
  {
    return {};
  }
  return [&progress, from, to](double f) { return progress(from + (to - from) * f); };
}
}

#endif
