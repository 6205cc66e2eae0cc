#include "vtkPVSoftShadowView.h"

#include "vtkBoundingBox.h"
#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkLightKit.h"
#include "vtkObjectFactory.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"

#include <cmath>

vtkStandardNewMacro(vtkPVSoftShadowView);

vtkPVSoftShadowView::vtkPVSoftShadowView()
  : ShadowPass(vtkSoftShadowPass::New())
{
  this->SynchronizedRenderers->SetRenderPass(this->ShadowPass);
  this->ShadowLightObject->SetLightTypeToSceneLight();
  this->ShadowLightObject->SetPositional(true);
  this->ShadowLightObject->SetConeAngle(90.0);
  this->ShadowLightObject->SetIntensity(0.75);
}

vtkPVSoftShadowView::~vtkPVSoftShadowView()
{
  this->SynchronizedRenderers->SetRenderPass(nullptr);
  this->ShadowPass->Delete();
}

vtkSoftShadowPass* vtkPVSoftShadowView::GetShadowPass()
{
  return this->ShadowPass;
}

void vtkPVSoftShadowView::SetMethod(int method)
{
  this->ShadowPass->SetMethod(method);
  this->Modified();
}

int vtkPVSoftShadowView::GetMethod()
{
  return this->ShadowPass->GetMethod();
}

void vtkPVSoftShadowView::SetLightSize(double size)
{
  if (!(size >= 0.0) || !std::isfinite(size))
  {
    vtkErrorMacro("LightSize must be a finite non-negative number, got " << size);
    return;
  }
  this->LightSize = size;
  this->Modified();
}

void vtkPVSoftShadowView::SetShadowMapSize(int size)
{
  this->ShadowPass->SetShadowMapSize(size);
  this->Modified();
}

void vtkPVSoftShadowView::SetGearsBackend(int backend)
{
  this->ShadowPass->SetGearsBackend(backend);
  this->Modified();
}

const char* vtkPVSoftShadowView::GetGearsBackendInUse()
{
  return this->ShadowPass->GetLastGearsBackend();
}

void vtkPVSoftShadowView::SetPVSMQuality(double quality)
{
  this->ShadowPass->SetPVSMQuality(quality);
  this->Modified();
}

const char* vtkPVSoftShadowView::GetStatsJSON()
{
  this->Stats = this->ShadowPass->GetStatsJSON();
  return this->Stats.c_str();
}

void vtkPVSoftShadowView::SetShadowLight(bool on)
{
  this->ShadowLight = on;
  this->Modified();
}

void vtkPVSoftShadowView::SetShadowLightIntensity(double intensity)
{
  this->ShadowLightObject->SetIntensity(intensity);
  this->Modified();
}

void vtkPVSoftShadowView::AboutToRenderOnLocalProcess(bool interactive)
{
  this->Superclass::AboutToRenderOnLocalProcess(interactive);
  vtkRenderer* ren = this->GetRenderer();
  vtkLightCollection* lights = ren->GetLights();

  // The shadow light follows the visible data and the camera's up direction.
  const bool present = lights->IsItemPresent(this->ShadowLightObject) != 0;
  if (this->ShadowLight)
  {
    double b[6];
    ren->ComputeVisiblePropBounds(b);
    vtkBoundingBox box(b);
    if (box.IsValid())
    {
      double c[3];
      box.GetCenter(c);
      const double diag = std::max(box.GetDiagonalLength(), 1e-12);
      vtkCamera* cam = ren->GetActiveCamera();
      double up[3], pos[3], toCam[3];
      cam->GetViewUp(up);
      cam->GetPosition(pos);
      for (int i = 0; i < 3; ++i)
      {
        toCam[i] = pos[i] - c[i];
      }
      const double n = std::sqrt(toCam[0] * toCam[0] + toCam[1] * toCam[1] + toCam[2] * toCam[2]);
      double p[3];
      for (int i = 0; i < 3; ++i)
      {
        p[i] = c[i] + 1.5 * diag * up[i] + (n > 0 ? 0.5 * diag * toCam[i] / n : 0.0);
      }
      this->ShadowLightObject->SetPosition(p);
      this->ShadowLightObject->SetFocalPoint(c);
    }
    if (!present)
    {
      ren->AddLight(this->ShadowLightObject);
    }
  }
  else if (present)
  {
    ren->RemoveLight(this->ShadowLightObject);
  }

  // The shadow light takes the place of the light kit's key light (same
  // role, same default intensity), so the picture is not over-exposed.
  if (this->LightKit)
  {
    if (this->ShadowLight && this->LightKit->GetKeyLightIntensity() != 0.0)
    {
      this->SavedKeyLightIntensity = this->LightKit->GetKeyLightIntensity();
      this->LightKit->SetKeyLightIntensity(0.0);
    }
    else if (!this->ShadowLight && this->LightKit->GetKeyLightIntensity() == 0.0 &&
      this->SavedKeyLightIntensity > 0.0)
    {
      this->LightKit->SetKeyLightIntensity(this->SavedKeyLightIntensity);
    }
  }

  // Light policy: only scene lights cast; positional ones get the area size.
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    const bool scene = light->LightTypeIsSceneLight() != 0;
    if (vtkSoftShadowLight::GetCastsShadows(light) != scene)
    {
      vtkSoftShadowLight::SetCastsShadows(light, scene);
    }
    if (scene && light->GetPositional())
    {
      double size[2];
      vtkSoftShadowLight::GetAreaSize(light, size);
      if (size[0] != this->LightSize || size[1] != this->LightSize)
      {
        vtkSoftShadowLight::SetAreaSize(light, this->LightSize, this->LightSize);
      }
    }
  }
}

void vtkPVSoftShadowView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LightSize: " << this->LightSize << "\n";
  os << indent << "ShadowLight: " << this->ShadowLight << "\n";
  this->ShadowPass->PrintSelf(os, indent.GetNextIndent());
}
