#include "ssSolverRegistry.h"

#include "ssAVSMSolver.h"
#include "ssASMSolver.h"
#include "ssHardAverageSolver.h"
#include "ssPVSMSolver.h"
#include "ssShadowMapSolver.h"
#include "ssTriangleSolver.h"
#include "ssVPCSSSolver.h"

namespace ss
{
namespace
{
template <class SolverType>
std::unique_ptr<VisibilitySolver> Make(Method m)
{
  return std::unique_ptr<VisibilitySolver>(new SolverType(m));
}
}

const std::vector<SolverEntry>& SolverRegistry()
{
  // One line per method, in the order the CLI lists them and the stats
  // report them. The planner rule says when method auto picks it
  // (ssEffectPlanner.cxx, MakeEffectPlan): one method per rule; OnRequest
  // methods run only when asked for by name. auto and none are modes of the
  // planner, not solvers.
  static const std::vector<SolverEntry> table = {
    // name       method               solver factory           planner rule              translucent casters
    { "auto",      Method::Auto,        nullptr,                 PlannerRule::OnRequest,   false },
    { "hard",      Method::Hard,        Make<ShadowMapSolver>,   PlannerRule::HardLights,  false },
    { "pcf",       Method::PCF,         Make<ShadowMapSolver>,   PlannerRule::OnRequest,   false },
    { "pcss",      Method::PCSS,        Make<ShadowMapSolver>,   PlannerRule::SoftLights,  false },
    { "pvsm",      Method::PVSM,        Make<PVSMSolver>,        PlannerRule::OnRequest,   false },
    { "hardavg",   Method::HardAverage, Make<HardAverageSolver>, PlannerRule::OnRequest,   false },
    { "asm",       Method::ASM,         Make<ASMSolver>,         PlannerRule::AdaptiveHardLights, false },
    { "reference", Method::Reference,   Make<TriangleSolver>,    PlannerRule::OnRequest,   true },
    { "gears",     Method::GEARS,       Make<TriangleSolver>,    PlannerRule::OnRequest,   true },
    { "vpcss",     Method::VPCSS,       Make<VPCSSSolver>,       PlannerRule::TranslucentCasters, true },
    { "avsm",      Method::AVSM,        Make<AVSMSolver>,        PlannerRule::OnRequest,   true },
    { "none",      Method::None,        nullptr,                 PlannerRule::OnRequest,   false },
  };
  return table;
}

const SolverEntry* FindSolverEntry(Method m)
{
  for (const auto& e : SolverRegistry())
  {
    if (e.Method == m)
    {
      return &e;
    }
  }
  return nullptr;
}

const SolverEntry* FindSolverEntry(const std::string& name)
{
  for (const auto& e : SolverRegistry())
  {
    if (name == e.Name)
    {
      return &e;
    }
  }
  return nullptr;
}

std::vector<MethodInfo> PlannerMethods()
{
  std::vector<MethodInfo> methods;
  for (const auto& e : SolverRegistry())
  {
    methods.push_back({ e.Method, e.Name, e.Rule, e.TranslucentCasters });
  }
  return methods;
}

int MaxMethodNumber()
{
  int m = 0;
  for (const auto& e : SolverRegistry())
  {
    m = std::max(m, static_cast<int>(e.Method));
  }
  return m;
}
}
