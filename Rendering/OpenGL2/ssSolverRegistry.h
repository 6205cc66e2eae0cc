// The one table of visibility methods: name, enum, solver factory, and the
// planner rule that uses it (see ssSolverRegistry.cxx and
// Documentation/architecture.md, "How to add a method").
#ifndef ssSolverRegistry_h
#define ssSolverRegistry_h

#include "ssEffectPlanner.h"
#include "ssVisibilitySolver.h"

#include <memory>
#include <string>
#include <vector>

namespace ss
{
using SolverFactory = std::unique_ptr<VisibilitySolver> (*)(Method);

struct SolverEntry
{
  const char* Name;         ///< what SetMethodByName, the CLI and the stats call it
  ss::Method Method;        ///< vtkSoftShadowPass::MethodType's number
  SolverFactory Factory;    ///< null for auto and none, which are not solvers
  PlannerRule Rule;         ///< when the planner uses it on its own
  bool TranslucentCasters;  ///< its solver weighs casters by their opacity
};

/// Every method, in the order the stats list them.
const std::vector<SolverEntry>& SolverRegistry();
/// The entry of a method (by number or name), or null.
const SolverEntry* FindSolverEntry(Method m);
const SolverEntry* FindSolverEntry(const std::string& name);
/// The registry as the effect planner sees it.
std::vector<MethodInfo> PlannerMethods();
/// The largest registered method number (vtkSoftShadowPass::SetMethod's range).
int MaxMethodNumber();
}

#endif
