#include "ssSolverRegistry.h"

#include "ssAVSMSolver.h"
#include "ssASMSolver.h"
#include "ssHardAverageSolver.h"
#include "ssPVSMSolver.h"
#include "ssShadowMapSolver.h"
#include "ssTriangleSolver.h"
#include "ssVPCSSSolver.h"

#include <algorithm>

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
  // planner, not solvers. The options column points at the solver's typed
  // options (its static DeclaredOptions()); the pass, the CLI and the ParaView view
  // enumerate them from here.
  static const std::vector<SolverEntry> table = {
    // name       method               solver factory           planner rule                     translucent casters, receivers; options
    { "auto",      Method::Auto,        nullptr,                 PlannerRule::OnRequest,          false, false, nullptr },
    { "hard",      Method::Hard,        Make<ShadowMapSolver>,   PlannerRule::HardLights,         false, false, ShadowMapSolver::DeclaredOptions },
    { "pcf",       Method::PCF,         Make<ShadowMapSolver>,   PlannerRule::OnRequest,          false, false, ShadowMapSolver::DeclaredOptions },
    { "pcss",      Method::PCSS,        Make<ShadowMapSolver>,   PlannerRule::SoftLights,         false, false, ShadowMapSolver::DeclaredOptions },
    { "pvsm",      Method::PVSM,        Make<PVSMSolver>,        PlannerRule::OnRequest,          false, false, PVSMSolver::DeclaredOptions },
    { "hardavg",   Method::HardAverage, Make<HardAverageSolver>, PlannerRule::OnRequest,          false, false, HardAverageSolver::DeclaredOptions },
    { "asm",       Method::ASM,         Make<ASMSolver>,         PlannerRule::AdaptiveHardLights, false, false, ASMSolver::DeclaredOptions },
    { "reference", Method::Reference,   Make<TriangleSolver>,    PlannerRule::OnRequest,          true,  false, TriangleSolver::DeclaredOptions },
    { "gears",     Method::GEARS,       Make<TriangleSolver>,    PlannerRule::OnRequest,          true,  false, TriangleSolver::DeclaredOptions },
    { "vpcss",     Method::VPCSS,       Make<VPCSSSolver>,       PlannerRule::TranslucentCasters, true,  true,  TranslucentSolver::DeclaredOptions },
    { "avsm",      Method::AVSM,        Make<AVSMSolver>,        PlannerRule::OnRequest,          true,  true,  TranslucentSolver::DeclaredOptions },
    { "none",      Method::None,        nullptr,                 PlannerRule::OnRequest,          false, false, nullptr },
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
    methods.push_back({ e.Method, e.Name, e.Rule, e.TranslucentCasters, e.TranslucentReceivers });
  }
  return methods;
}

const std::vector<RegisteredOption>& RegisteredOptions()
{
  static const std::vector<RegisteredOption> options = [] {
    std::vector<RegisteredOption> all;
    std::vector<SolverOptionsFunction> seen;
    for (const auto& e : SolverRegistry())
    {
      if (!e.Options)
      {
        continue;
      }
      const OptionList& list = e.Options();
      const bool first = std::find(seen.begin(), seen.end(), e.Options) == seen.end();
      for (const auto& d : list)
      {
        if (first)
        {
          all.push_back({ &d, e.Name });
        }
        else
        {
          for (auto& r : all)
          {
            if (r.Descriptor == &d)
            {
              r.Methods += std::string(", ") + e.Name;
            }
          }
        }
      }
      seen.push_back(e.Options);
    }
    return all;
  }();
  return options;
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
