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
}

#endif
