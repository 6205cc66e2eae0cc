#include "ssFrameState.h"

#include "vtkSoftShadowLight.h"

#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkRenderer.h"

#include <cmath>
#include <exception>

namespace ss
{
std::vector<ShadowLight> CollectLights(vtkRenderer* ren, const glm::dvec3& origin)
{
  std::vector<ShadowLight> lights;
  vtkLightCollection* lc = ren->GetLights();
  vtkCollectionSimpleIterator lit;
  int shaderIndex = 0;
  for (lc->InitTraversal(lit); vtkLight* light = lc->GetNextLight(lit);)
  {
    if (light->GetSwitch() <= 0)
    {
      continue;
    }
    ShadowLight sl;
    sl.Light = light;
    sl.ShaderIndex = shaderIndex++;
    sl.Planner.headlight = light->LightTypeIsHeadlight() != 0;
    sl.Planner.castsShadows = vtkSoftShadowLight::GetCastsShadows(light);
    double pos[3], fp[3];
    light->GetTransformedPosition(pos);
    light->GetTransformedFocalPoint(fp);
    try
    {
      const glm::dvec3 p(pos[0], pos[1], pos[2]);
      const glm::dvec3 f(fp[0], fp[1], fp[2]);
      if (light->GetPositional())
      {
        double size[2];
        vtkSoftShadowLight::GetAreaSize(light, size);
        if (size[0] > 0.0 || size[1] > 0.0)
        {
          double up[3] = { 0, 0, 0 };
          vtkSoftShadowLight::GetAreaUp(light, up);
          sl.Frame = MakeRectLightFrame(p - origin, f - p, glm::dvec3(up[0], up[1], up[2]), glm::dvec2(size[0], size[1]));
        }
        else
        {
          sl.Frame = MakePointLightFrame(p - origin);
        }
      }
      else
      {
        const double angle = vtkSoftShadowLight::GetAngularDiameter(light);
        sl.Frame = MakeDirectionalLightFrame(f - p, angle * M_PI / 180.0);
      }
    }
    catch (const std::exception& e)
    {
      sl.Planner.valid = false;
      sl.Planner.invalidReason = e.what();
    }
    sl.Planner.frame = sl.Frame;
    lights.push_back(sl);
  }
  return lights;
}
}
