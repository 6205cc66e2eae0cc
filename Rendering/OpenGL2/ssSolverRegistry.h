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
/// A solver's option list (its static DeclaredOptions(), in its own files).
using SolverOptionsFunction = const OptionList& (*)();

struct SolverEntry
{
  const char* Name;         ///< what SetMethodByName, the CLI and the stats call it
  ss::Method Method;        ///< vtkSoftShadowPass::MethodType's number
  SolverFactory Factory;    ///< null for auto and none, which are not solvers
  PlannerRule Rule;         ///< when the planner uses it on its own
  bool TranslucentCasters;  ///< its solver weighs casters by their opacity
  bool TranslucentReceivers; ///< its solver shades translucent receivers' fragments (FragmentLookup)
  SolverOptionsFunction Options; ///< its solver's typed options (null: none)
};

/// One solver option as the pass, the CLI and ParaView see it: its
/// descriptor and the methods whose lines declare it.
struct RegisteredOption
{
  const OptionDescriptor* Descriptor;
  std::string Methods; ///< "reference, gears"
};

/// Every method, in the order the stats list them.
const std::vector<SolverEntry>& SolverRegistry();
/// The entry of a method (by number or name), or null.
const SolverEntry* FindSolverEntry(Method m);
const SolverEntry* FindSolverEntry(const std::string& name);
/// The registry as the effect planner sees it.
std::vector<MethodInfo> PlannerMethods();
/// Every solver option of the registry, once (lines sharing a solver share
/// its list), in registry order. Keys are unique across the registry
/// (checked by the test python.SolverOptions).
const std::vector<RegisteredOption>& RegisteredOptions();
/// The largest registered method number (vtkSoftShadowPass::SetMethod's range).
int MaxMethodNumber();
}

#endif
