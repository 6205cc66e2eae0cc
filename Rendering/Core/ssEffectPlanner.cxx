#include "ssEffectPlanner.h"

#include <sstream>

namespace ss
{
const char* MethodName(Method m)
{
  switch (m)
  {
    case Method::Auto:
      return "auto";
    case Method::Hard:
      return "hard";
    case Method::PCF:
      return "pcf";
    case Method::PCSS:
      return "pcss";
    case Method::None:
      return "none";
    case Method::Reference:
      return "reference";
    case Method::GEARS:
      return "gears";
    case Method::PVSM:
      return "pvsm";
    case Method::HardAverage:
      return "hardavg";
  }
  return "none";
}

bool MethodFromName(const std::string& s, Method& out)
{
  for (Method m : { Method::Auto, Method::Hard, Method::PCF, Method::PCSS, Method::None, Method::Reference,
         Method::GEARS, Method::PVSM, Method::HardAverage })
  {
    if (s == MethodName(m))
    {
      out = m;
      return true;
    }
  }
  return false;
}

bool IsTriangleSolver(Method m)
{
  return m == Method::Reference || m == Method::GEARS;
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
    o << (i ? ", " : "") << "{\"method\": \"" << MethodName(lights[i].method)
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
    o << "\n  light " << i << ": " << MethodName(lights[i].method) << " - " << lights[i].reason;
  }
  return o.str();
}

EffectPlan MakeEffectPlan(const PlannerInput& in)
{
  EffectPlan plan;
  plan.lights.resize(in.lights.size());
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
      l = { Method::None, frameReason };
    }
    return plan;
  }
  for (std::size_t i = 0; i < in.lights.size(); ++i)
  {
    const PlannerLight& l = in.lights[i];
    LightPlan& p = plan.lights[i];
    if (l.headlight)
    {
      p = { Method::None, "headlight: never casts shadows" };
    }
    else if (!l.castsShadows)
    {
      p = { Method::None, "light does not cast shadows" };
    }
    else if (!l.valid)
    {
      p = { Method::None, "invalid light: " + l.invalidReason };
    }
    else if (in.requested != Method::Auto)
    {
      p.method = in.requested;
      p.reason = std::string("requested ") + MethodName(in.requested);
      if (in.requested == Method::PCSS && !l.frame.IsSoft())
      {
        p.reason += " (point/zero-size light: PCSS degenerates to an antialiased hard shadow)";
      }
      if (in.requested == Method::HardAverage && !l.frame.IsSoft())
      {
        p.reason += " (point/zero-size light: every sample is the same, one hard map)";
      }
    }
    else if (!l.frame.IsSoft())
    {
      p = { Method::Hard, l.frame.type == LightType::Directional
          ? "directional light without angular size: hard shadows"
          : "point/zero-size light: hard shadows" };
    }
    else
    {
      p = { Method::PCSS, "area light: soft shadows (PCSS)" };
    }
    plan.shadowWork = plan.shadowWork || p.method != Method::None;
  }
  plan.reason = plan.shadowWork ? std::to_string(in.casterTriangles) + " caster triangles"
                                : "no light casts shadows";
  if (plan.shadowWork && in.translucentCasters)
  {
    bool mapSolver = false;
    for (const auto& l : plan.lights)
    {
      mapSolver = mapSolver || (l.method != Method::None && !IsTriangleSolver(l.method));
    }
    if (mapSolver)
    {
      plan.reason += "; translucent casters are treated as opaque by shadow-map methods (planner v1)";
    }
  }
  if (plan.shadowWork && in.unchangedSinceLastFrame)
  {
    plan.reuse = true;
    plan.reason += "; nothing changed since the last frame: visibility reused";
  }
  return plan;
}
}
