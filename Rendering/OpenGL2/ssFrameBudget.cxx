#include "ssFrameBudget.h"

#include "ssFrameState.h"

#include "vtkCommand.h"
#include "vtkRenderWindow.h"

#include <algorithm>
#include <sstream>

namespace ss
{
double FrameBudgetMs(vtkRenderWindow* win, double interactiveRate)
{
  const double rate = win ? win->GetDesiredUpdateRate() : 0.0;
  return (rate > 0.0 && rate >= interactiveRate) ? 1000.0 / rate : 0.0;
}

void MethodCosts::Record(const std::vector<ShadowLight>& lights, double workMs, double pixels)
{
  Method method = Method::None;
  int n = 0;
  for (const auto& l : lights)
  {
    if (l.Layer < 0)
    {
      continue;
    }
    if (n > 0 && l.Method != method)
    {
      return; // several methods: no single method's cost to learn
    }
    method = l.Method;
    ++n;
  }
  if (n > 0 && pixels > 0.0 && workMs >= 0.0)
  {
    this->Costs[method] = { workMs / n, pixels };
  }
}

void MethodCosts::Estimate(std::vector<MethodInfo>& methods, double pixels) const
{
  for (auto& info : methods)
  {
    const auto it = this->Costs.find(info.method);
    info.estimatedMs = it == this->Costs.end() ? -1.0 : it->second.msPerLight * pixels / it->second.pixels;
  }
}

FrameProgress::FrameProgress(vtkObject* reporter, vtkRenderWindow* win, int lights)
  : Reporter(reporter)
  , Window(win)
  , Lights(std::max(lights, 1))
{
}

bool FrameProgress::Report(double fractionOfLight)
{
  double p = std::min(1.0, (this->Solved + fractionOfLight) / this->Lights);
  this->Reporter->InvokeEvent(vtkCommand::ProgressEvent, &p);
  this->Aborted = this->Aborted || (this->Window && this->Window->CheckAbortStatus() != 0);
  return !this->Aborted;
}

bool FrameProgress::Finish(EffectPlan& plan)
{
  if (!this->Aborted)
  {
    double done = 1.0;
    this->Reporter->InvokeEvent(vtkCommand::ProgressEvent, &done);
    return false;
  }
  plan.aborted = true;
  plan.reason += "; render aborted (vtkRenderWindow AbortRender) with " + std::to_string(this->Solved) + " of " +
    std::to_string(this->Lights) + " shadow lights solved: no shadows this frame";
  return true;
}

std::string PlanSummary(const EffectPlan& plan, double ms)
{
  std::ostringstream o;
  o << std::fixed;
  o.precision(ms < 10.0 ? 1 : 0);
  o << plan.Summary() << ", " << ms << " ms";
  return o.str();
}
}
