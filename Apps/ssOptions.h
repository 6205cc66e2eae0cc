// The `--option key=value` keys of `softshadows render` and `bench`: one
// table, from which ApplyOption, the usage text and the unknown-key error
// are all made, so the three cannot disagree (issue 24: `--help` had
// omitted pvsm_tile_culling). The frame-wide keys are rows here; every
// solver's own options come from the solver registry through the pass's
// enumeration (vtkSoftShadowPass::GetSolverOptionKey, ...; issue 19).
#ifndef ssOptions_h
#define ssOptions_h

#include <functional>
#include <string>
#include <vector>

class vtkSoftShadowPass;

namespace ssapp
{
struct PassOption
{
  std::string Key;
  std::string Values; ///< what the value is, for the usage text ("1..32", "edge|lut", ...)
  std::string Help;   ///< what it sets (solver options: the methods and the default too)
  bool Solver;        ///< from the registry (vtkSoftShadowPass::SetSolverOption)
  /// Parses `value` (throws UsageError naming `what`) and sets the pass.
  std::function<void(vtkSoftShadowPass*, const std::string& value, const std::string& what)> Apply;
};

/// Every key, in the order the usage lists them: frame-wide, then the solvers'.
const std::vector<PassOption>& PassOptions();

/// The usage text's "options:" section, one key a line.
std::string PassOptionsUsage();

/// Every key, comma-separated (for the unknown-key error).
std::string PassOptionKeys();
}

#endif
