#include "ssEffectPlanner.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace ss
{
const MethodInfo* FindMethod(const std::vector<MethodInfo>& methods, Method m)
{
  for (const auto& info : methods)
  {
    if (info.method == m)
    {
      return &info;
    }
  }
  return nullptr;
}

namespace
{
std::string NameOf(const std::vector<MethodInfo>& methods, Method m)
{
  const MethodInfo* info = FindMethod(methods, m);
  return info ? info->name : "method " + std::to_string(static_cast<int>(m));
}

// The method that serves `rule`, or null when none is registered for it.
const MethodInfo* ForRule(const std::vector<MethodInfo>& methods, PlannerRule rule)
{
  for (const auto& info : methods)
  {
    if (info.rule == rule)
    {
      return &info;
    }
  }
  return nullptr;
}

std::string Upper(std::string s)
{
  for (char& c : s)
  {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return s;
}
}

std::string JSONEscape(const std::string& s)
{
  std::string o;
  for (char c : s)
  {
    if (c == '"' || c == '\\')
    {
      o += '\\';
      o += c;
    }
    else if (c == '\n')
    {
      o += "\\n";
    }
    else if (static_cast<unsigned char>(c) >= 0x20)
    {
      o += c;
    }
  }
  return o;
}

std::string EffectPlan::ToJSON() const
{
  std::ostringstream o;
  o << "{\"shadow_work\": " << (shadowWork ? "true" : "false")
    << ", \"reuse\": " << (reuse ? "true" : "false") << ", \"reason\": \"" << JSONEscape(reason)
    << "\", \"lights\": [";
  for (std::size_t i = 0; i < lights.size(); ++i)
  {
    o << (i ? ", " : "") << "{\"method\": \"" << JSONEscape(lights[i].name)
      << "\", \"reason\": \"" << JSONEscape(lights[i].reason) << "\"}";
  }
  o << "]}";
  return o.str();
}

std::string EffectPlan::ToText() const
{
  std::ostringstream o;
  o << "shadow work: " << (shadowWork ? "yes" : "no") << (reuse ? " (reused)" : "") << " - "
    << reason;
  for (std::size_t i = 0; i < lights.size(); ++i)
  {
    o << "\n  light " << i << ": " << lights[i].name << " - " << lights[i].reason;
  }
  return o.str();
}

EffectPlan MakeEffectPlan(const PlannerInput& in)
{
  EffectPlan plan;
  const std::string none = NameOf(in.methods, Method::None);
  plan.lights.resize(in.lights.size(), LightPlan{ Method::None, std::string(), none });
  auto off = [&](LightPlan& p, const std::string& why) {
    p = { Method::None, why, none };
  };
  std::string frameReason;
  if (in.requested == Method::None)
  {
    frameReason = "shadows switched off (method none)";
  }
  else if (in.lights.empty())
  {
    frameReason = "no lights";
  }
  else if (in.casterTriangles == 0)
  {
    frameReason = "no shadow casters";
  }
  else if (in.receiverProps == 0)
  {
    frameReason = "no shadow receivers";
  }
  if (!frameReason.empty())
  {
    plan.reason = frameReason;
    for (auto& l : plan.lights)
    {
      off(l, frameReason);
    }
    return plan;
  }
  for (std::size_t i = 0; i < in.lights.size(); ++i)
  {
    const PlannerLight& l = in.lights[i];
    LightPlan& p = plan.lights[i];
    if (l.headlight)
    {
      off(p, "headlight: never casts shadows");
    }
    else if (!l.castsShadows)
    {
      off(p, "light does not cast shadows");
    }
    else if (!l.valid)
    {
      off(p, "invalid light: " + l.invalidReason);
    }
    else if (in.requested != Method::Auto)
    {
      const MethodInfo* info = FindMethod(in.methods, in.requested);
      if (!info)
      {
        off(p, NameOf(in.methods, in.requested) + " is not a registered method");
      }
      else
      {
        p = { in.requested, "requested " + info->name, info->name };
        if (in.requested == Method::PCSS && !l.frame.IsSoft())
        {
          p.reason += " (point/zero-size light: PCSS degenerates to an antialiased hard shadow)";
        }
        if (in.requested == Method::HardAverage && !l.frame.IsSoft())
        {
          p.reason += " (point/zero-size light: every sample is the same, one hard map)";
        }
        if (in.requested == Method::ASM && l.frame.IsSoft())
        {
          p.reason += " (area light: ASM gives the hard shadow of its centre)";
        }
      }
    }
    // --- method auto: the rules, one branch each (PlannerRule)
    else if (!l.frame.IsSoft())
    {
      const MethodInfo* uniform = ForRule(in.methods, PlannerRule::HardLights);
      const MethodInfo* adaptive = ForRule(in.methods, PlannerRule::AdaptiveHardLights);
      const bool directional = l.frame.type == LightType::Directional;
      std::string why = directional ? "directional light without angular size: hard shadows"
                                    : "point/zero-size light: hard shadows";
      const MethodInfo* info = uniform;
      if (adaptive && !directional)
      {
        // point and spot lights: the receivers around them need resolution
        // where the view is close, which no single map gives (ASM §1)
        info = adaptive;
        why += ", refined where the view needs it (" + Upper(adaptive->name) + ")";
      }
      else if (adaptive && NeedsAdaptiveMap(l.receiverTexels, in.shadowMapSize))
      {
        std::ostringstream o;
        o << why << "; the receivers span " << static_cast<long long>(l.receiverTexels)
          << " texels at the view's pixel size, more than " << kAdaptiveFactor << " x a map of "
          << in.shadowMapSize << " (" << Upper(adaptive->name) << ")";
        why = o.str();
        info = adaptive;
      }
      if (info)
      {
        p = { info->method, why, info->name };
      }
      else
      {
        off(p, why + ", but no method is registered for them");
      }
    }
    else
    {
      const MethodInfo* info = ForRule(in.methods, PlannerRule::SoftLights);
      if (info)
      {
        p = { info->method, "area light: soft shadows (" + Upper(info->name) + ")", info->name };
      }
      else
      {
        off(p, "area light: soft shadows, but no method is registered for them");
      }
    }
    plan.shadowWork = plan.shadowWork || p.method != Method::None;
  }
  plan.reason = plan.shadowWork ? std::to_string(in.casterTriangles) + " caster triangles"
                                : "no light casts shadows";
  if (plan.shadowWork && in.translucentCasters)
  {
    bool opaqueOnly = false;
    for (const auto& l : plan.lights)
    {
      const MethodInfo* info = FindMethod(in.methods, l.method);
      opaqueOnly = opaqueOnly || (l.method != Method::None && !(info && info->translucentCasters));
    }
    if (opaqueOnly)
    {
      plan.reason += "; translucent casters are treated as opaque by shadow-map methods (planner v1)";
    }
  }
  if (plan.shadowWork && in.unchangedSinceLastFrame && !in.refining.empty())
  {
    // a progressive solver's last frame is not final: a still view re-rendered refines
    plan.reason += "; the view is unchanged but " + in.refining + " is still refining: solved again";
  }
  else if (plan.shadowWork && in.unchangedSinceLastFrame)
  {
    plan.reuse = true;
    plan.reason += "; nothing changed since the last frame: visibility reused";
  }
  return plan;
}

bool NeedsAdaptiveMap(double receiverTexels, int shadowMapSize)
{
  return receiverTexels > kAdaptiveFactor * std::max(1, shadowMapSize);
}

double ReceiverTexelsAtPixelSize(
  const LightFrame& light, const Box& receivers, const glm::dvec3& eye, double pixelAngle, double parallelPixel)
{
  if (light.type != LightType::Directional || receivers.Empty())
  {
    return 0.0;
  }
  // the receivers' extent across the light (an orthographic view along it)
  ShadowView v;
  v.orthographic = true;
  v.n = light.n;
  v.v = FallbackUp(light.n);
  v.u = glm::normalize(glm::cross(v.v, v.n));
  const Rect r = FitOrthographicExtent(v, receivers, 0.0, 0.0);
  const double extent = std::max(r.x1 - r.x0, r.y1 - r.y0);
  // a pixel's size at the receivers' nearest point
  double pixel = parallelPixel;
  if (pixelAngle > 0.0)
  {
    const glm::dvec3 nearest = glm::clamp(eye, receivers.min, receivers.max);
    const double d = std::max(glm::length(nearest - eye), 1e-6 * receivers.Diagonal());
    pixel = d * pixelAngle;
  }
  return pixel > 0.0 ? extent / pixel : 0.0;
}
}
