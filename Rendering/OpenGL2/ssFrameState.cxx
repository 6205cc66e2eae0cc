#include "ssFrameState.h"

#include "ssCasterSet.h"

#include "vtkSoftShadowLight.h"

#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkRenderState.h"
#include "vtkRenderer.h"
#include "vtkWindow.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <exception>
#include <sstream>

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
    try
    {
      const double o[3] = { origin.x, origin.y, origin.z };
      sl.Frame = vtkSoftShadowLight::MakeLightFrame(light, o);
    }
    catch (const std::exception& e)
    {
      sl.Planner.valid = false;
      sl.Planner.invalidReason = e.what();
    }
    sl.Planner.frame = sl.Frame;
    sl.TrueFrame = sl.Frame;
    lights.push_back(sl);
  }
  return lights;
}

std::string CheckFarAndOverflowingLights(
  std::vector<ShadowLight>& lights, const Box& scene, const glm::dvec3& origin)
{
  std::ostringstream out;
  auto sep = [&out]() -> std::ostream& { return out << (out.tellp() > 0 ? "; " : ""); };
  bool far = false;
  for (auto& l : lights)
  {
    if (!l.Planner.valid && l.Planner.castsShadows && !l.Planner.headlight)
    {
      // (the plan said it; stop 45's Python sweep found a light whose position
      // is its focal point unshadowed with nothing printed)
      sep() << "light " << l.ShaderIndex << " casts no shadow: " << l.Planner.invalidReason;
    }
    LightFrame d;
    l.TrueFrame = l.Frame;
    if (l.Planner.valid && !scene.Empty() && FarLightAsDirectional(l.Frame, scene.Center(), scene.Diagonal(), d))
    {
      // (the index counts every light of the renderer, as VTK does: in
      // ParaView the light kit's too; the position tells which one it is)
      const glm::dvec3 at = l.Frame.center + origin;
      sep() << "light " << l.ShaderIndex << " at (" << at.x << ", " << at.y << ", " << at.z << ") is "
            << glm::length(l.Frame.center - scene.Center()) / scene.Diagonal() << " scene sizes away";
      l.Frame = d;
      l.Planner.frame = d;
      far = true;
    }
    const double w = l.Frame.width, h = l.Frame.height;
    if (l.Planner.valid)
    {
      ClampRectLightSize(l.TrueFrame); // (the same shadow in double)
    }
    if (l.Planner.valid && ClampRectLightSize(l.Frame))
    {
      sep() << "light " << l.ShaderIndex << " of size " << w << " x " << h << " is shadowed as one of "
            << l.Frame.width << " x " << l.Frame.height << " (" << kMaxRectLightSize
            << " is the largest side the float shaders hold; the shadow is the same)";
      l.Planner.frame = l.Frame;
    }
    double rgb[3];
    l.Light->GetDiffuseColor(rgb);
    const double intensity = l.Light->GetIntensity();
    if (std::isnan(intensity) || std::isnan(rgb[0]) || std::isnan(rgb[1]) || std::isnan(rgb[2]))
    {
      // VTK shades with it all the same: NaN in every lit pixel, drawn black
      sep() << "light " << l.ShaderIndex << " has an intensity or a colour that is not a number"
            << " (VTK's shading turns every lit pixel black)";
    }
    else if (intensity * std::max({ rgb[0], rgb[1], rgb[2], 1e-30 }) > FLT_MAX)
    {
      // VTK's shaders get colour x intensity as a float: inf, then NaN
      sep() << "light " << l.ShaderIndex << " has intensity " << l.Light->GetIntensity()
            << ", beyond the float range VTK's shading computes in (black picture)";
    }
  }
  if (far)
  {
    out << " (beyond " << kFarLightRatio
        << " scene sizes the shadow-map methods shadow a light as a directional one: float light-space depths "
           "cannot separate the scene's surfaces from there; gears on the CPU and the reference solve it as it is)";
  }
  return out.str();
}

bool UpdateFrameState(FrameState& frame, const vtkRenderState* s, const double* fixedOrigin)
{
  vtkRenderer* ren = s->GetRenderer();
  int w, h, x0 = 0, y0 = 0;
  if (auto* fbo = vtkOpenGLFramebufferObject::SafeDownCast(s->GetFrameBuffer()))
  {
    int size[2];
    fbo->GetLastSize(size);
    w = size[0];
    h = size[1];
  }
  else
  {
    ren->GetTiledSizeAndOrigin(&w, &h, &x0, &y0);
  }
  if (w <= 0 || h <= 0)
  {
    return false;
  }
  frame.Width = w;
  frame.Height = h;
  frame.ViewportOrigin[0] = x0;
  frame.ViewportOrigin[1] = y0;
  // A tiled render (vtkWindowToImageFilter::SetScale, ParaView screenshots
  // larger than the view) draws the frame TileScale times larger, one tile
  // of the window's size at a time, through the window's tile viewport (in
  // units of the whole frame). The renderer's part of the whole frame is
  // TileScale times its viewport; this tile's place in it follows.
  frame.FrameSize[0] = w;
  frame.FrameSize[1] = h;
  frame.TileOrigin[0] = frame.TileOrigin[1] = 0;
  if (vtkWindow* win = ren->GetVTKWindow())
  {
    int scale[2];
    double tile[4];
    win->GetTileScale(scale);
    win->GetTileViewport(tile);
    const double* vp = ren->GetViewport();
    const int* size = win->GetSize();
    for (int i = 0; i < 2; ++i)
    {
      const double part = (vp[i + 2] - vp[i]) * size[i] * scale[i];
      frame.FrameSize[i] = std::max(static_cast<int>(std::lround(part)), i == 0 ? w : h);
      frame.TileOrigin[i] =
        std::max(0, static_cast<int>(std::lround((std::max(tile[i], vp[i]) - vp[i]) * size[i] * scale[i])));
    }
  }
  vtkCamera* cam = ren->GetActiveCamera();
  const double* o = fixedOrigin ? fixedOrigin : cam->GetFocalPoint();
  frame.Origin = glm::dvec3(o[0], o[1], o[2]);
  frame.Eye = glm::dvec3(cam->GetPosition()[0], cam->GetPosition()[1], cam->GetPosition()[2]) - frame.Origin;
  return true;
}

std::string FrameSignature(vtkRenderer* ren, const FrameState& frame, const CasterSet& casters,
  unsigned long long settingsTime)
{
  vtkCamera* cam = ren->GetActiveCamera();
  std::ostringstream sig;
  double vm[16];
  vtkMatrix4x4::DeepCopy(vm, cam->GetModelViewTransformMatrix());
  sig.precision(17);
  for (double v : vm)
  {
    sig << v << ',';
  }
  // the projection as drawn (tiled renders shift it per tile; window centre)
  vtkMatrix4x4::DeepCopy(vm, cam->GetProjectionTransformMatrix(ren));
  for (double v : vm)
  {
    sig << v << ',';
  }
  sig << cam->GetViewAngle() << ',' << cam->GetParallelProjection() << ',' << cam->GetParallelScale() << ','
      << ren->GetTiledAspectRatio() << ',' << frame.Width << 'x' << frame.Height << ',' << casters.Version << ','
      // the tile: a tiled render's tiles share the camera but not the pixels
      // (issue 17: each tile reused the first tile's visibility)
      << frame.FrameSize[0] << 'x' << frame.FrameSize[1] << '+' << frame.TileOrigin[0] << '+' << frame.TileOrigin[1]
      << ',' << frame.ViewportOrigin[0] << '+' << frame.ViewportOrigin[1] << ','
      << casters.VolumeVersion << ','
      << settingsTime << ',' << frame.Origin.x << ',' << frame.Origin.y << ',' << frame.Origin.z;
  for (const auto& l : frame.Lights)
  {
    sig << ',' << l.Light << ':' << l.Light->GetMTime();
  }
  for (const auto& k : casters.Keys)
  {
    sig << ',' << std::get<0>(k) << ':' << std::get<3>(k) << ':' << std::get<4>(k);
  }
  return sig.str();
}
}
