// A sphere over a floor, lit by one 1 x 1 area light, rendered offscreen with
// vtkSoftShadowPass and saved as demo.png (or the file named on the command
// line). Needs an X display (or xvfb-run -a). Exits 1 if nothing is in shadow.
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkFloatArray.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPlaneSource.h>
#include <vtkPolyDataMapper.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSoftShadowLight.h>
#include <vtkSoftShadowPass.h>
#include <vtkSphereSource.h>
#include <vtkWindowToImageFilter.h>

#include <iostream>

int main(int argc, char* argv[])
{
  vtkNew<vtkSphereSource> sphere;   sphere->SetCenter(0, 0, 1.2); sphere->SetRadius(0.6);
  sphere->SetThetaResolution(48);   sphere->SetPhiResolution(24);
  vtkNew<vtkPlaneSource> ground;    ground->SetOrigin(-4, -4, 0);
  ground->SetPoint1(4, -4, 0);      ground->SetPoint2(-4, 4, 0);
  vtkNew<vtkRenderer> renderer;     renderer->SetBackground(1, 1, 1);
  for (vtkPolyDataAlgorithm* src : { static_cast<vtkPolyDataAlgorithm*>(sphere),
                                     static_cast<vtkPolyDataAlgorithm*>(ground) })
  {
    vtkNew<vtkPolyDataMapper> mapper; mapper->SetInputConnection(src->GetOutputPort());
    vtkNew<vtkActor> actor;           actor->SetMapper(mapper);
    renderer->AddActor(actor);
  }
  vtkNew<vtkLight> light;           // a 1 x 1 rectangle at (1,-1,5) facing the origin
  light->SetLightTypeToSceneLight(); light->SetPositional(true); light->SetConeAngle(90);
  light->SetPosition(1, -1, 5);      light->SetFocalPoint(0, 0, 0);
  vtkSoftShadowLight::SetAreaSize(light, 1.0, 1.0);
  renderer->AddLight(light);
  vtkNew<vtkSoftShadowPass> shadows; // method: auto (the effect planner decides)
  renderer->SetPass(shadows);
  vtkNew<vtkRenderWindow> window;   window->AddRenderer(renderer); window->SetSize(640, 480);
  window->SetOffScreenRendering(1);
  renderer->GetActiveCamera()->SetPosition(3, -6, 4);
  renderer->GetActiveCamera()->SetFocalPoint(0, 0, 0.6);
  renderer->GetActiveCamera()->SetViewUp(0, 0, 1);
  renderer->ResetCameraClippingRange();
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab; grab->SetInput(window);
  vtkNew<vtkPNGWriter> png;          png->SetInputConnection(grab->GetOutputPort());
  png->SetFileName(argc > 1 ? argv[1] : "demo.png");
  png->Write();
  std::cout << shadows->GetPlanDescription() << "\n";

  vtkNew<vtkFloatArray> v;           // light 0's visible fraction per pixel
  shadows->GetVisibilityImage(0, v);
  vtkIdType shadowed = 0;
  for (vtkIdType i = 0; i < v->GetNumberOfTuples(); ++i)
  {
    shadowed += v->GetValue(i) < 0.5f ? 1 : 0;
  }
  std::cout << "saved " << png->GetFileName() << "; " << shadowed << " pixels in shadow\n";
  return shadowed > 0 ? 0 : 1;
}
