// Helpers shared by the render-pass tests: small scenes built from plain VTK
// objects (as a VTK application would), offscreen rendering, readback of the
// pass's visibility/positions, and regression images against Data/Baseline.
#ifndef ssRenderTestUtilities_h
#define ssRenderTestUtilities_h

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCubeSource.h"
#include "vtkFloatArray.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"
#include "vtkSphereSource.h"
#include "vtkTesting.h"

#include <cmath>
#include <string>
#include <vector>

namespace sstest
{
struct Frame
{
  int width = 0, height = 0;
  std::vector<float> V;   // width*height, NaN background
  std::vector<float> P;   // 3*width*height, relative to origin
  double origin[3] = { 0, 0, 0 };
};

// An actor drawing `pd` as it is (VTK's default material).
inline vtkSmartPointer<vtkActor> ActorOf(vtkPolyData* pd)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(pd);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

inline vtkSmartPointer<vtkActor> MakeActor(vtkPolyDataAlgorithm* src, double r = 0.8, double g = 0.8,
  double b = 0.8)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(src->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(r, g, b);
  actor->GetProperty()->SetAmbient(0.15);
  actor->GetProperty()->SetDiffuse(0.85);
  return actor;
}

inline vtkSmartPointer<vtkActor> Ground(double half = 4.0, double z = 0.0, int res = 1)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-half, -half, z);
  plane->SetPoint1(half, -half, z);
  plane->SetPoint2(-half, half, z);
  plane->SetResolution(res, res);
  return MakeActor(plane, 0.9, 0.9, 0.9);
}

inline vtkSmartPointer<vtkActor> Sphere(double cx, double cy, double cz, double radius)
{
  vtkNew<vtkSphereSource> s;
  s->SetCenter(cx, cy, cz);
  s->SetRadius(radius);
  s->SetThetaResolution(64);
  s->SetPhiResolution(32);
  return MakeActor(s, 0.85, 0.3, 0.25);
}

// A horizontal square of side `side` centred at (cx, cy, z), opacity `alpha`.
inline vtkSmartPointer<vtkActor> Quad(double cx, double cy, double z, double side, double alpha)
{
  vtkNew<vtkPlaneSource> q;
  q->SetOrigin(cx - side / 2, cy - side / 2, z);
  q->SetPoint1(cx + side / 2, cy - side / 2, z);
  q->SetPoint2(cx - side / 2, cy + side / 2, z);
  auto a = MakeActor(q, 0.9, 0.9, 0.9);
  a->GetProperty()->SetOpacity(alpha);
  return a;
}

inline vtkSmartPointer<vtkActor> Box(
  double cx, double cy, double cz, double sx, double sy, double sz)
{
  vtkNew<vtkCubeSource> c;
  c->SetCenter(cx, cy, cz);
  c->SetXLength(sx);
  c->SetYLength(sy);
  c->SetZLength(sz);
  return MakeActor(c, 0.3, 0.5, 0.85);
}

inline vtkSmartPointer<vtkLight> RectLight(double cx, double cy, double cz, double fx, double fy,
  double fz, double w, double h, double intensity = 1.0)
{
  auto light = vtkSmartPointer<vtkLight>::New();
  light->SetLightTypeToSceneLight();
  light->SetPositional(true);
  light->SetPosition(cx, cy, cz);
  light->SetFocalPoint(fx, fy, fz);
  light->SetConeAngle(90.0);
  light->SetIntensity(intensity);
  vtkSoftShadowLight::SetAreaSize(light, w, h);
  return light;
}

struct Scene
{
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkSoftShadowPass> pass;

  Scene(int w = 400, int h = 300)
  {
    window->SetOffScreenRendering(1);
    window->SetSize(w, h);
    window->SetMultiSamples(0);
    window->AddRenderer(renderer);
    renderer->AutomaticLightCreationOff();
    renderer->SetBackground(1, 1, 1);
    renderer->SetPass(pass);
  }

  void Camera(double px, double py, double pz, double fx = 0, double fy = 0, double fz = 0,
    double angle = 30)
  {
    vtkCamera* c = renderer->GetActiveCamera();
    c->SetPosition(px, py, pz);
    c->SetFocalPoint(fx, fy, fz);
    c->SetViewUp(0, 0, 1);
    c->SetViewAngle(angle);
    renderer->ResetCameraClippingRange();
  }

  Frame Render(int light = 0)
  {
    window->Render();
    Frame f;
    f.width = pass->GetLastWidth();
    f.height = pass->GetLastHeight();
    pass->GetLastPositionsOrigin(f.origin);
    vtkNew<vtkFloatArray> v, p;
    if (pass->GetVisibilityImage(light, v))
    {
      f.V.assign(v->GetPointer(0), v->GetPointer(0) + v->GetNumberOfValues());
    }
    if (pass->GetPositionsImage(p))
    {
      f.P.assign(p->GetPointer(0), p->GetPointer(0) + p->GetNumberOfValues());
    }
    return f;
  }
};

/// vtkTesting regression against Data/Baseline/<name>.png (threshold as in VTK's tests).
int CompareWithBaseline(vtkRenderWindow* win, const std::string& name, double threshold = 0.15);
}

#endif
