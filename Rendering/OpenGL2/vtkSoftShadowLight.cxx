#include "vtkSoftShadowLight.h"

#include "ssLightFrame.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationDoubleVectorKey.h"
#include "vtkInformationIntegerKey.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

vtkStandardNewMacro(vtkSoftShadowLight);
vtkInformationKeyRestrictedMacro(vtkSoftShadowLight, AREA_SIZE, DoubleVector, 2);
vtkInformationKeyRestrictedMacro(vtkSoftShadowLight, AREA_UP, DoubleVector, 3);
vtkInformationKeyMacro(vtkSoftShadowLight, ANGULAR_DIAMETER, Double);
vtkInformationKeyMacro(vtkSoftShadowLight, CASTS_SHADOWS, Integer);

namespace
{
vtkInformation* LightInfo(vtkLight* light)
{
  if (!light->GetInformation())
  {
    vtkNew<vtkInformation> info;
    light->SetInformation(info);
  }
  return light->GetInformation();
}
}

void vtkSoftShadowLight::SetAreaSize(vtkLight* light, double width, double height)
{
  if (!light)
  {
    return;
  }
  if (!std::isfinite(width) || !std::isfinite(height) || width < 0.0 || height < 0.0)
  {
    vtkGenericWarningMacro("vtkSoftShadowLight::SetAreaSize: expected two finite non-negative "
                           "numbers, got "
      << width << " x " << height << "; light unchanged.");
    return;
  }
  double v[2] = { width, height };
  LightInfo(light)->Set(AREA_SIZE(), v, 2);
  light->Modified();
}

void vtkSoftShadowLight::GetAreaSize(vtkLight* light, double size[2])
{
  size[0] = size[1] = 0.0;
  if (light && light->GetInformation() && light->GetInformation()->Has(AREA_SIZE()))
  {
    const double* v = light->GetInformation()->Get(AREA_SIZE());
    size[0] = v[0];
    size[1] = v[1];
  }
}

void vtkSoftShadowLight::SetAreaUp(vtkLight* light, double x, double y, double z)
{
  if (!light)
  {
    return;
  }
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
  {
    vtkGenericWarningMacro("vtkSoftShadowLight::SetAreaUp: non-finite vector; light unchanged.");
    return;
  }
  double v[3] = { x, y, z };
  LightInfo(light)->Set(AREA_UP(), v, 3);
  light->Modified();
}

bool vtkSoftShadowLight::GetAreaUp(vtkLight* light, double up[3])
{
  if (light && light->GetInformation() && light->GetInformation()->Has(AREA_UP()))
  {
    const double* v = light->GetInformation()->Get(AREA_UP());
    up[0] = v[0];
    up[1] = v[1];
    up[2] = v[2];
    return true;
  }
  return false;
}

void vtkSoftShadowLight::SetAngularDiameter(vtkLight* light, double degrees)
{
  if (!light)
  {
    return;
  }
  if (!std::isfinite(degrees) || degrees < 0.0 || degrees > 30.0)
  {
    vtkGenericWarningMacro("vtkSoftShadowLight::SetAngularDiameter: expected degrees in [0, 30], got "
      << degrees << "; light unchanged.");
    return;
  }
  LightInfo(light)->Set(ANGULAR_DIAMETER(), degrees);
  light->Modified();
}

double vtkSoftShadowLight::GetAngularDiameter(vtkLight* light)
{
  if (light && light->GetInformation() && light->GetInformation()->Has(ANGULAR_DIAMETER()))
  {
    return light->GetInformation()->Get(ANGULAR_DIAMETER());
  }
  return 0.0;
}

void vtkSoftShadowLight::SetCastsShadows(vtkLight* light, bool casts)
{
  if (light)
  {
    LightInfo(light)->Set(CASTS_SHADOWS(), casts ? 1 : 0);
    light->Modified();
  }
}

bool vtkSoftShadowLight::GetCastsShadows(vtkLight* light)
{
  if (!light || light->LightTypeIsHeadlight())
  {
    return false;
  }
  if (light->GetInformation() && light->GetInformation()->Has(CASTS_SHADOWS()))
  {
    return light->GetInformation()->Get(CASTS_SHADOWS()) != 0;
  }
  return true;
}

ss::LightFrame vtkSoftShadowLight::MakeLightFrame(vtkLight* light, const double origin[3])
{
  double pos[3], fp[3];
  light->GetTransformedPosition(pos);
  light->GetTransformedFocalPoint(fp);
  const glm::dvec3 p(pos[0], pos[1], pos[2]), f(fp[0], fp[1], fp[2]);
  const glm::dvec3 o = origin ? glm::dvec3(origin[0], origin[1], origin[2]) : glm::dvec3(0.0);
  if (!light->GetPositional())
  {
    return ss::MakeDirectionalLightFrame(f - p, vtkSoftShadowLight::GetAngularDiameter(light) * M_PI / 180.0);
  }
  double size[2];
  vtkSoftShadowLight::GetAreaSize(light, size);
  try
  {
    // a zero side is a point light (scene-format.md; the planner's rule too)
    if (size[0] > 0.0 && size[1] > 0.0)
    {
      double up[3] = { 0, 0, 0 };
      vtkSoftShadowLight::GetAreaUp(light, up);
      return ss::MakeRectLightFrame(p - o, f - p, glm::dvec3(up[0], up[1], up[2]), glm::dvec2(size[0], size[1]));
    }
    return ss::MakePointLightFrame(p - o);
  }
  catch (const std::exception& e)
  {
    // (the frames' messages give coordinates relative to the float origin:
    // the world's are what the user set)
    std::ostringstream msg;
    msg << e.what() << " (the light at (" << p.x << ", " << p.y << ", " << p.z << ") towards (" << f.x << ", "
        << f.y << ", " << f.z << ") in world coordinates)";
    throw std::invalid_argument(msg.str());
  }
}

void vtkSoftShadowLight::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
