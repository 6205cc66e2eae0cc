// The `--option key=value` keys of `softshadows render` and `bench`: one
// table, from which ApplyOption, the usage text and the unknown-key error
// are all made, so the three cannot disagree (issue 24: `--help` had
// omitted pvsm_tile_culling).
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
  const char* Key;
  const char* Values; ///< what the value is, for the usage text ("1..32", "edge|lut", ...)
  const char* Help;   ///< what it sets
  /// Parses `value` (throws UsageError naming `what`) and sets the pass.
  std::function<void(vtkSoftShadowPass*, const std::string& value, const std::string& what)> Apply;
};

/// Every key, in the order the usage lists them.
const std::vector<PassOption>& PassOptions();

/// The usage text's "options:" section, one key a line.
std::string PassOptionsUsage();

/// Every key, comma-separated (for the unknown-key error).
std::string PassOptionKeys();
}

#endif
