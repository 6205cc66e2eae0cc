// The regression-image helper of ssRenderTestUtilities.h, compiled into every
// render test (RenderTests.cmake).
#include "ssRenderTestUtilities.h"

#include "vtkWindowToImageFilter.h"

#ifndef SS_BASELINE_DIR
#error "SS_BASELINE_DIR must be defined"
#endif
#ifndef SS_TEMP_DIR
#error "SS_TEMP_DIR must be defined"
#endif

namespace sstest
{
int CompareWithBaseline(vtkRenderWindow* win, const std::string& name, double threshold)
{
  vtkNew<vtkTesting> testing;
  testing->AddArgument("-V");
  const std::string baseline = std::string(SS_BASELINE_DIR) + "/" + name + ".png";
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(SS_TEMP_DIR);
  testing->SetRenderWindow(win);
  const int result = testing->RegressionTest(threshold);
  if (result != vtkTesting::PASSED)
  {
    // Keep the picture so it can be looked at (and, on purpose, become the baseline).
    vtkNew<vtkWindowToImageFilter> w2i;
    w2i->SetInput(win);
    w2i->ReadFrontBufferOff();
    w2i->Update();
    testing->SetValidImageFileName(baseline.c_str());
  }
  return result;
}
}

