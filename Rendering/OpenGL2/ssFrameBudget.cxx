#include "ssFrameBudget.h"

#include "ssFrameState.h"

#include "vtkRenderWindow.h"

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
}
