#include "ssOptions.h"

#include "ssBench.h"

#include "vtkSoftShadowPass.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace
{
using ssapp::ParseInt;
using ssapp::UsageError;

double ParseDouble(const std::string& s, const std::string& what, double lo, double hi)
{
  double v = 0.0;
  try
  {
    std::size_t used = 0;
    v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v))
    {
      throw std::out_of_range(s);
    }
  }
  catch (const std::exception&)
  {
    throw UsageError(what + ": expected a number, got '" + s + "'");
  }
  if (!(v >= lo && v <= hi))
  {
    std::ostringstream o;
    o << what << ": expected a value in [" << lo << ", " << hi << "], got '" << s << "'";
    throw UsageError(o.str());
  }
  return v;
}

// The index of `v` in `choices` (throws UsageError listing them).
int ParseChoice(const std::string& v, const std::string& what, const std::vector<std::string>& choices)
{
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i)
  {
    if (choices[i] == v)
    {
      return static_cast<int>(i);
    }
    list += (i == 0 ? "" : (i + 1 == choices.size() ? " or " : ", ")) + choices[i];
  }
  throw UsageError(what + ": expected " + list + ", got '" + v + "'");
}

constexpr double Unbounded = 1e300;

}

namespace ssapp
{
const std::vector<PassOption>& PassOptions()
{
  using P = vtkSoftShadowPass;
  using S = const std::string&;
  static const std::vector<PassOption> options = [] {
    // frame-wide: the pass's own properties, shared by every method
    std::vector<PassOption> all = {
      { "shadow_map_size", "64..16384", "shadow map texels a side", false,
        [](P* p, S v, S w) { p->SetShadowMapSize(ParseInt(v, w, 64, 16384)); } },
      { "constant_bias", "number", "depth bias, shadow-map texels", false,
        [](P* p, S v, S w) { p->SetConstantBias(ParseDouble(v, w, -Unbounded, Unbounded)); } },
      { "slope_bias", "number", "slope-scaled depth bias, texels (hard, asm, avsm, vpcss; pcf, pcss and pvsm test the receiver's plane instead)", false,
        [](P* p, S v, S w) { p->SetSlopeBias(ParseDouble(v, w, -Unbounded, Unbounded)); } },
      { "normal_offset", "0..16", "normal-offset lookup, texels along the triangle's normal (0: off)", false,
        [](P* p, S v, S w) { p->SetNormalOffset(ParseDouble(v, w, 0.0, 16.0)); } },
      { "list_translucent_fragments", "0|1",
        "translucent receivers' V once per fragment into lists (0: in their shading, every peel)", false,
        [](P* p, S v, S w) { p->SetListTranslucentFragments(ParseInt(v, w, 0, 1) != 0); } },
      { "fit_views_to_visible", "0|1", "shadow-map views cut to the receivers the camera sees (0: the bounds)",
        false, [](P* p, S v, S w) { p->SetFitViewsToVisibleReceivers(ParseInt(v, w, 0, 1) != 0); } },
      { "frame_budget", "0|1", "interactive frames (DesiredUpdateRate >= 0.1/s) fit the method to the budget",
        false, [](P* p, S v, S w) { p->SetAdaptToFrameBudget(ParseInt(v, w, 0, 1) != 0); } },
      { "keep_requested_method", "0|1", "no equivalent stand-in for the requested method (vpcss, opaque casters: pcss)",
        false, [](P* p, S v, S w) { p->SetKeepRequestedMethod(ParseInt(v, w, 0, 1) != 0); } },
    };
    // each solver's own: declared in its files, enumerated from the registry
    for (int i = 0; i < P::GetNumberOfSolverOptions(); ++i)
    {
      const std::string type = P::GetSolverOptionType(i);
      const double lo = P::GetSolverOptionMinimum(i), hi = P::GetSolverOptionMaximum(i);
      std::vector<std::string> names;
      for (int n = 0; n < P::GetSolverOptionNumberOfNames(i); ++n)
      {
        names.emplace_back(P::GetSolverOptionName(i, n));
      }
      const std::string values = P::GetSolverOptionValues(i);
      const std::string defText = P::GetSolverOptionDefaultAsString(i);
      const std::string key = P::GetSolverOptionKey(i);
      const std::string help = std::string(P::GetSolverOptionHelp(i)) + " [" + P::GetSolverOptionMethods(i) +
        "; default " + defText + "]";
      all.push_back({ key, values, help, true, [key, type, lo, hi, names](P* p, S v, S w) {
                       double x = 0.0;
                       if (type == "enum")
                       {
                         x = ParseChoice(v, w, names);
                       }
                       else if (type == "double")
                       {
                         x = ParseDouble(v, w, lo, hi);
                       }
                       else
                       {
                         x = ParseInt(v, w, static_cast<int>(lo), static_cast<int>(hi));
                       }
                       if (!p->SetSolverOption(key.c_str(), x))
                       {
                         throw UsageError(w + ": refused by the pass");
                       }
                     } });
    }
    return all;
  }();
  return options;
}

std::string PassOptionsUsage()
{
  std::ostringstream o;
  o << "options (--option key=value):\n";
  bool solvers = false;
  for (const auto& opt : PassOptions())
  {
    if (opt.Solver && !solvers)
    {
      o << " each method's own (its solver's options; vtkSoftShadowPass::SetSolverOption):\n";
      solvers = true;
    }
    std::string head = "  " + opt.Key + " (" + opt.Values + ")";
    if (head.size() < 40)
    {
      head.resize(40, ' ');
    }
    o << head << " " << opt.Help << "\n";
  }
  return o.str();
}

std::string PassOptionKeys()
{
  std::string keys;
  for (const auto& opt : PassOptions())
  {
    keys += (keys.empty() ? "" : ", ") + opt.Key;
  }
  return keys;
}

void ApplyOption(vtkSoftShadowPass* pass, const std::string& kv)
{
  const auto eq = kv.find('=');
  if (eq == std::string::npos)
  {
    throw UsageError("--option: expected key=value, got '" + kv + "'");
  }
  const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
  for (const auto& opt : PassOptions())
  {
    if (k == opt.Key)
    {
      opt.Apply(pass, v, "--option " + k);
      return;
    }
  }
  throw UsageError("--option: unknown key '" + k + "' (expected " + PassOptionKeys() + ")");
}
}
