// Interactive frames (issue 24): the budget VTK's interactive-render
// convention gives a frame, and what each method's shadow work measured on
// earlier frames, for the effect planner to fit the budget with
// (ssEffectPlanner, PlannerInput::frameBudgetMs and MethodInfo::estimatedMs).
#ifndef ssFrameBudget_h
#define ssFrameBudget_h

#include "ssEffectPlanner.h"

#include <map>
#include <string>
#include <vector>

class vtkObject;
class vtkRenderWindow;

namespace ss
{
struct ShadowLight;

/// Milliseconds a frame may take: 1000 / the window's DesiredUpdateRate
/// when that rate is at least `interactiveRate` (VTK's interactor sets 15
/// frames per second while the user interacts and 0.0001 after; ParaView's
/// interactive render 5, its still render 0.002); else 0: a still frame.
double FrameBudgetMs(vtkRenderWindow* win, double interactiveRate);

/// The shadow work (G-buffer, shadow maps, solves; the pass finishes the GPU
/// before it reads the clock) of the frames solved so far, per light and per
/// method: the last frame whose shadow lights all used one method gives
/// that method's cost. Scaled by pixels for the frame being planned, as the
/// per-pixel solvers (reference, gears, filtering) scale.
class MethodCosts
{
public:
  /// A solved frame of `pixels` whose shadow work took `workMs`.
  void Record(const std::vector<ShadowLight>& lights, double workMs, double pixels);
  /// Fills `estimatedMs` of the methods measured so far, for `pixels`.
  void Estimate(std::vector<MethodInfo>& methods, double pixels) const;
  void Clear() { this->Costs.clear(); }

private:
  struct Sample
  {
    double msPerLight = 0.0;
    double pixels = 1.0;
  };
  std::map<Method, Sample> Costs;
};

/// Progress and abort of one frame's solves: Report invokes
/// vtkCommand::ProgressEvent on `reporter` (call data: a double* in [0, 1]
/// over all `lights`) and polls the window's CheckAbortStatus; false once the
/// render is aborted.
class FrameProgress
{
public:
  FrameProgress(vtkObject* reporter, vtkRenderWindow* win, int lights);
  bool Report(double fractionOfLight);
  /// A light's solve returned; it counts as solved unless the render was
  /// aborted during it (the plan said "1 of 1 solved" for a stopped solve).
  void LightDone()
  {
    if (!this->Aborted)
    {
      ++this->Solved;
    }
  }
  /// Progress 1, or (aborted) the plan says so; returns whether aborted.
  bool Finish(EffectPlan& plan);

private:
  vtkObject* Reporter;
  vtkRenderWindow* Window;
  int Lights;
  int Solved = 0;
  bool Aborted = false;
};

/// One line for an annotation: the plan's summary and the frame's time.
std::string PlanSummary(const EffectPlan& plan, double ms);
}

#endif
