#include "ssEffectPlanner.h"

#include "ssClusterBounds.h"

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

LightPlan Planned(Method m, const std::string& reason, const std::string& name)
{
  LightPlan p;
  p.method = m;
  p.reason = reason;
  p.name = name;
  return p;
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
    << ", \"reuse\": " << (reuse ? "true" : "false") << ", \"interactive\": " << (interactive ? "true" : "false")
    << ", \"degraded\": " << (degraded ? "true" : "false") << ", \"aborted\": " << (aborted ? "true" : "false");
  if (interactive)
  {
    o << ", \"frame_budget_ms\": " << frameBudgetMs << ", \"estimated_ms\": " << estimatedMs;
  }
  o << ", \"reason\": \"" << JSONEscape(reason) << "\", \"lights\": [";
  for (std::size_t i = 0; i < lights.size(); ++i)
  {
    o << (i ? ", " : "") << "{\"method\": \"" << JSONEscape(lights[i].name)
      << "\", \"reason\": \"" << JSONEscape(lights[i].reason) << "\"";
    if (lights[i].stillMethod != Method::None)
    {
      o << ", \"still_method\": \"" << JSONEscape(lights[i].stillName) << "\"";
    }
    o << "}";
  }
  o << "]}";
  return o.str();
}

std::string EffectPlan::ToText() const
{
  std::ostringstream o;
  o << "shadow work: " << (shadowWork ? "yes" : "no") << (reuse ? " (reused)" : "")
    << (degraded ? " (interactive: faster methods stand in)" : "") << (aborted ? " (aborted)" : "") << " - "
    << reason;
  for (std::size_t i = 0; i < lights.size(); ++i)
  {
    o << "\n  light " << i << ": " << lights[i].name << " - " << lights[i].reason;
  }
  return o.str();
}

std::string EffectPlan::Summary() const
{
  if (!shadowWork)
  {
    return "none: " + reason.substr(0, reason.find(';'));
  }
  std::vector<std::string> names, still;
  for (const auto& l : lights)
  {
    if (l.method != Method::None && std::find(names.begin(), names.end(), l.name) == names.end())
    {
      names.push_back(l.name);
    }
    if (l.stillMethod != Method::None && std::find(still.begin(), still.end(), l.stillName) == still.end())
    {
      still.push_back(l.stillName);
    }
  }
  auto join = [](const std::vector<std::string>& v) {
    std::string o;
    for (const auto& n : v)
    {
      o += (o.empty() ? "" : ", ") + n;
    }
    return o;
  };
  std::string o = join(names);
  if (degraded)
  {
    o += " (interactive: stands in for " + join(still) + ")";
  }
  o += reuse ? " (reused)" : "";
  o += aborted ? " (aborted)" : "";
  return o;
}

namespace
{
std::string Ms(double ms)
{
  std::ostringstream o;
  o.precision(ms < 10.0 ? 2 : 0);
  o << std::fixed << ms << " ms";
  return o.str();
}

// An interactive frame (VTK's DesiredUpdateRate, ParaView's interactive
// render): while the estimated shadow work exceeds the budget, the light
// whose next step saves the most moves one step down its chain (its method
// -> the SoftLights rule's, soft lights only -> the HardLights rule's; a
// step to a dearer method is skipped). (A point light's step to hard shadows loses
// nothing and usually goes first.) A method of unknown cost counts as 0: it
// runs and is measured.
void FitBudget(const PlannerInput& in, EffectPlan& plan)
{
  plan.interactive = true;
  plan.frameBudgetMs = in.frameBudgetMs;
  const MethodInfo* soft = ForRule(in.methods, PlannerRule::SoftLights);
  const MethodInfo* hard = ForRule(in.methods, PlannerRule::HardLights);
  auto cost = [&](Method m) {
    const MethodInfo* info = FindMethod(in.methods, m);
    return info ? info->estimatedMs : -1.0;
  };
  std::vector<std::vector<Method>> chain(plan.lights.size());
  std::vector<std::size_t> step(plan.lights.size(), 0);
  for (std::size_t i = 0; i < plan.lights.size(); ++i)
  {
    const Method m = plan.lights[i].method;
    if (m == Method::None)
    {
      continue;
    }
    chain[i].push_back(m);
    auto add = [&](const MethodInfo* info) {
      if (info && std::find(chain[i].begin(), chain[i].end(), info->method) == chain[i].end())
      {
        chain[i].push_back(info->method);
      }
    };
    if (in.lights[i].frame.IsSoft())
    {
      add(soft);
    }
    add(hard);
  }
  double total = 0.0;
  bool known = true;
  for (;;)
  {
    total = 0.0;
    known = true;
    std::size_t best = plan.lights.size(); // the light whose step saves the most
    std::size_t bestTarget = 0;
    double bestSaving = 0.0;
    for (std::size_t i = 0; i < chain.size(); ++i)
    {
      if (chain[i].empty())
      {
        continue;
      }
      const double c = cost(chain[i][step[i]]);
      known = known && c >= 0.0;
      total += std::max(c, 0.0);
      // its next step: the first method further down the chain that is
      // cheaper (an unmeasured one counts as 0); a dearer one is skipped.
      // One step at a time, so a light keeps as much softness as the budget
      // allows.
      for (std::size_t j = step[i] + 1; j < chain[i].size(); ++j)
      {
        const double saving = std::max(c, 0.0) - std::max(cost(chain[i][j]), 0.0);
        if (saving > 0.0)
        {
          if (saving > bestSaving)
          {
            best = i;
            bestTarget = j;
            bestSaving = saving;
          }
          break;
        }
      }
    }
    if (total <= in.frameBudgetMs || best == plan.lights.size())
    {
      break;
    }
    step[best] = bestTarget;
  }
  plan.estimatedMs = known ? total : -1.0;
  for (std::size_t i = 0; i < chain.size(); ++i)
  {
    if (step[i] == 0)
    {
      continue;
    }
    LightPlan& p = plan.lights[i];
    const Method m = chain[i][step[i]];
    const double from = cost(p.method), to = cost(m);
    p.reason = "interactive frame (budget " + Ms(in.frameBudgetMs) + "): " + p.name + " takes ~" +
      Ms(from) + ", " + NameOf(in.methods, m) + " stands in" + (to >= 0.0 ? " (~" + Ms(to) + ")" : "") +
      "; the still frame uses " + p.name;
    p.stillMethod = p.method;
    p.stillName = p.name;
    p.method = m;
    p.name = NameOf(in.methods, m);
    plan.degraded = true;
  }
  const bool fits = total <= in.frameBudgetMs;
  plan.reason += "; interactive frame: budget " + Ms(in.frameBudgetMs) + ", shadow work estimated " +
    (known ? Ms(total) : std::string("unknown (not every method measured yet)")) +
    (plan.degraded ? ": faster methods stand in" : "") +
    (fits ? (plan.degraded ? "" : ": fits") : (plan.degraded ? ", still over" : ": nothing faster to use"));
}
}

EffectPlan MakeEffectPlan(const PlannerInput& in)
{
  EffectPlan plan;
  const std::string none = NameOf(in.methods, Method::None);
  plan.lights.resize(in.lights.size(), Planned(Method::None, std::string(), none));
  auto off = [&](LightPlan& p, const std::string& why) {
    p = Planned(Method::None, why, none);
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
  else if (in.casterTriangles == 0 && in.casterVolumes == 0)
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
        p = Planned(in.requested, "requested " + info->name, info->name);
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
        // VPCSS over casters that are all opaque: every transmittance is 0 or
        // 1 and eqs. 6-8 are PCSS's (vpcss.md), so the light gets PCSS, which
        // is exact for that case and cheaper (the AVSM build has nothing to
        // compress); the reason says so. Not where a translucent receiver is
        // in its view: PCSS leaves it unshadowed.
        const MethodInfo* pcss = FindMethod(in.methods, Method::PCSS);
        if (in.requested == Method::VPCSS && l.translucentInView.empty() && !l.translucentReceiversInView && pcss &&
          !in.keepRequested)
        {
          p = Planned(Method::PCSS,
            "requested " + info->name + "; no translucent caster in this light's view, where VPCSS is PCSS: " +
              pcss->name,
            pcss->name);
        }
      }
    }
    // --- method auto: the rules, one branch each (PlannerRule)
    else if (!l.translucentInView.empty() && ForRule(in.methods, PlannerRule::TranslucentCasters))
    {
      const MethodInfo* info = ForRule(in.methods, PlannerRule::TranslucentCasters);
      p = Planned(info->method,
        std::string(l.frame.IsSoft() ? "area light" : "light without extent") + " with translucent casters in its view (" +
          l.translucentInView + "): transmittance-weighted " + (l.frame.IsSoft() ? "soft" : "hard") + " shadows (" +
          Upper(info->name) + ")",
        info->name);
    }
    else if (l.translucentReceiversInView && ForRule(in.methods, PlannerRule::TranslucentCasters))
    {
      // the casters are opaque, but a translucent prop receives their
      // shadows: it is not in the G-buffer, and only this rule's method
      // shades its fragments
      const MethodInfo* info = ForRule(in.methods, PlannerRule::TranslucentCasters);
      p = Planned(info->method,
        std::string(l.frame.IsSoft() ? "area light" : "light without extent") +
          " with translucent receivers in its view: their fragments take their own " +
          (l.frame.IsSoft() ? "soft" : "hard") + " shadows (" + Upper(info->name) + ")",
        info->name);
    }
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
        p = Planned(info->method, why, info->name);
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
        p = Planned(info->method, "area light: soft shadows (" + Upper(info->name) + ")", info->name);
      }
      else
      {
        off(p, "area light: soft shadows, but no method is registered for them");
      }
    }
    plan.shadowWork = plan.shadowWork || p.method != Method::None;
  }
  plan.reason = plan.shadowWork ? std::to_string(in.casterTriangles) + " caster triangles" +
      (in.casterVolumes ? ", " + std::to_string(in.casterVolumes) + " caster volume(s)" : std::string())
                                : "no light casts shadows";
  if (plan.shadowWork && (in.translucentCasters || in.casterVolumes > 0))
  {
    std::string opaqueOnly;
    for (const auto& l : plan.lights)
    {
      const MethodInfo* info = FindMethod(in.methods, l.method);
      if (l.method != Method::None && !(info && info->translucentCasters) &&
        opaqueOnly.find(l.name) == std::string::npos)
      {
        opaqueOnly += (opaqueOnly.empty() ? "" : ", ") + l.name;
      }
    }
    if (!opaqueOnly.empty())
    {
      plan.reason += in.translucentCasters ? "; translucent casters are treated as opaque" : "";
      plan.reason += in.casterVolumes ? std::string(in.translucentCasters ? " and" : ";") + " volumes cast no shadows"
                                      : "";
      plan.reason += " by " + opaqueOnly;
    }
  }
  if (plan.shadowWork)
  {
    std::string unshaded; // methods that leave a light's translucent receivers unshadowed
    for (std::size_t i = 0; i < plan.lights.size() && i < in.lights.size(); ++i)
    {
      const LightPlan& l = plan.lights[i];
      const MethodInfo* info = FindMethod(in.methods, l.method);
      if (in.lights[i].translucentReceiversInView && l.method != Method::None &&
        !(info && info->translucentReceivers) && unshaded.find(l.name) == std::string::npos)
      {
        unshaded += (unshaded.empty() ? "" : ", ") + l.name;
      }
    }
    if (!unshaded.empty())
    {
      plan.reason += "; translucent receivers get no shadows from " + unshaded;
    }
  }
  if (plan.shadowWork && in.frameBudgetMs > 0.0)
  {
    FitBudget(in, plan);
  }
  bool sameMethods = in.lastMethods.size() == plan.lights.size();
  for (std::size_t i = 0; sameMethods && i < plan.lights.size(); ++i)
  {
    sameMethods = in.lastMethods[i] == plan.lights[i].method;
  }
  if (plan.shadowWork && in.unchangedSinceLastFrame && sameMethods && !in.refining.empty())
  {
    // a progressive solver's last frame is not final: a still view re-rendered refines
    plan.reason += "; the view is unchanged but " + in.refining + " is still refining: solved again";
  }
  else if (plan.shadowWork && in.unchangedSinceLastFrame && sameMethods)
  {
    plan.reuse = true;
    plan.reason += "; nothing changed since the last frame: visibility reused";
  }
  return plan;
}

bool CastersMayShadow(const LightFrame& light, const Box& casters, const Box& receivers)
{
  if (casters.Empty() || receivers.Empty())
  {
    return false;
  }
  ClusterBounds b;
  b.aabb = casters;
  b.obb.center = casters.Center();
  b.obb.half = 0.5 * (casters.max - casters.min);
  return ClusterMayShadowBox(b, light, receivers);
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
