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
  static const std::vector<PassOption> options = {
    { "shadow_map_size", "64..16384", "shadow map texels a side",
      [](P* p, S v, S w) { p->SetShadowMapSize(ParseInt(v, w, 64, 16384)); } },
    { "pcf_radius", "0.5..64", "pcf filter radius, texels",
      [](P* p, S v, S w) { p->SetPCFRadius(ParseDouble(v, w, 0.5, 64.0)); } },
    { "blocker_samples", "2..32", "PCSS blocker-search samples per axis",
      [](P* p, S v, S w) { p->SetBlockerSearchSamples(ParseInt(v, w, 2, 32)); } },
    { "filter_max_quads", "2..128", "coverage filter: texel quads per axis at most",
      [](P* p, S v, S w) { p->SetFilterMaxQuads(ParseInt(v, w, 2, 128)); } },
    { "constant_bias", "number", "depth bias, shadow-map texels",
      [](P* p, S v, S w) { p->SetConstantBias(ParseDouble(v, w, -Unbounded, Unbounded)); } },
    { "slope_bias", "number", "slope-scaled depth bias, texels",
      [](P* p, S v, S w) { p->SetSlopeBias(ParseDouble(v, w, -Unbounded, Unbounded)); } },
    { "normal_offset", "0..16", "normal-offset lookup along the facet normal, texels (0: off)",
      [](P* p, S v, S w) { p->SetNormalOffset(ParseDouble(v, w, 0.0, 16.0)); } },
    { "reference_samples", "1..64", "reference: k x k light samples",
      [](P* p, S v, S w) { p->SetReferenceSamples(ParseInt(v, w, 1, 64)); } },
    { "reference_pattern", "regular|stratified", "reference: light sample pattern",
      [](P* p, S v, S w) { p->SetReferencePattern(ParseChoice(v, w, { "regular", "stratified" })); } },
    { "gears_samples", "1..32", "gears: k x k light samples",
      [](P* p, S v, S w) { p->SetGearsSamples(ParseInt(v, w, 1, 32)); } },
    { "gears_grid", "8..1024", "gears: grid cells a side",
      [](P* p, S v, S w) { p->SetGearsGrid(ParseInt(v, w, 8, 1024)); } },
    { "gears_raster", "edge|lut", "gears: exact edge planes or the lookup table",
      [](P* p, S v, S w) { p->SetGearsRaster(ParseChoice(v, w, { "edge", "lut" })); } },
    { "gears_backend", "cpu|gl", "gears: CPU (TBB) or GL 4.3 compute",
      [](P* p, S v, S w) { p->SetGearsBackend(ParseChoice(v, w, { "cpu", "gl" })); } },
    { "gears_necessary", "0|1", "gears: count Table 9's necessary assignments (slower)",
      [](P* p, S v, S w) { p->SetGearsCountNecessary(ParseInt(v, w, 0, 1) != 0); } },
    { "pvsm_quality", "0.05..64", "pvsm: scale on the perceptual metric rho",
      [](P* p, S v, S w) { p->SetPVSMQuality(ParseDouble(v, w, 0.05, 64.0)); } },
    { "pvsm_metric", "auto|dynamic|static", "pvsm: which metric of section 5.1",
      [](P* p, S v, S w) { p->SetPVSMMetric(ParseChoice(v, w, { "auto", "dynamic", "static" })); } },
    { "pvsm_grid", "4..256", "pvsm: shadow-map tile grid",
      [](P* p, S v, S w) { p->SetPVSMGridSize(ParseInt(v, w, 4, 256)); } },
    { "pvsm_max_tile", "64..16384", "pvsm: largest tile, texels a side",
      [](P* p, S v, S w) { p->SetPVSMMaxTileResolution(ParseInt(v, w, 64, 16384)); } },
    { "pvsm_low_resolution", "64..8192", "pvsm: conservative low-resolution map",
      [](P* p, S v, S w) { p->SetPVSMLowResolution(ParseInt(v, w, 64, 8192)); } },
    { "pvsm_tile_culling", "0|1", "pvsm: draw only the caster clusters reaching a tile",
      [](P* p, S v, S w) { p->SetPVSMTileCulling(ParseInt(v, w, 0, 1) != 0); } },
    { "average_samples", "1..32", "hardavg: k x k hard maps",
      [](P* p, S v, S w) { p->SetAverageSamples(ParseInt(v, w, 1, 32)); } },
    { "avsm_nodes", "4..16", "avsm, vpcss: nodes per texel of the adaptive volumetric shadow map",
      [](P* p, S v, S w) { p->SetAVSMNodes(ParseInt(v, w, 4, 16)); } },
    { "avsm_size", "64..8192", "avsm, vpcss: map texels a side",
      [](P* p, S v, S w) { p->SetAVSMSize(ParseInt(v, w, 64, 8192)); } },
    { "avsm_memory", "16..65536", "avsm, vpcss: MB for the maps, their buffers and the fragment lists",
      [](P* p, S v, S w) { p->SetAVSMMemory(ParseInt(v, w, 16, 65536)); } },
    { "colored_shadows", "0|1", "avsm, vpcss: coloured transmittance of tinted casters",
      [](P* p, S v, S w) { p->SetColoredShadows(ParseInt(v, w, 0, 1) != 0); } },
    { "volume_steps", "8..4096", "avsm, vpcss: march steps through a volume",
      [](P* p, S v, S w) { p->SetVolumeSteps(ParseInt(v, w, 8, 4096)); } },
    { "vpcss_filter_quads", "2..64", "vpcss: largest filter, quads a side",
      [](P* p, S v, S w) { p->SetVPCSSFilterQuads(ParseInt(v, w, 2, 64)); } },
    { "asm_memory_mb", "0.0625..4096", "asm: memory budget of the page pool, megabytes",
      [](P* p, S v, S w) { p->SetASMMemoryBudget(ParseDouble(v, w, 0.0625, 4096.0)); } },
    { "asm_page_size", "16..4096", "asm: page texels a side",
      [](P* p, S v, S w) { p->SetASMPageSize(ParseInt(v, w, 16, 4096)); } },
    { "asm_cells", "2|4|8", "asm: cells a side a node splits into",
      [](P* p, S v, S w) { p->SetASMCells(2 << ParseChoice(v, w, { "2", "4", "8" })); } },
    { "asm_max_depth", "0..20", "asm: deepest level of the hierarchy",
      [](P* p, S v, S w) { p->SetASMMaxDepth(ParseInt(v, w, 0, 20)); } },
    { "asm_time_budget_ms", "0..100000", "asm: refinement time a frame, ms",
      [](P* p, S v, S w) { p->SetASMTimeBudget(ParseDouble(v, w, 0.0, 1.0e5)); } },
    { "asm_stride", "1..64", "asm: one pixel in N analysed a frame",
      [](P* p, S v, S w) { p->SetASMAnalysisStride(ParseInt(v, w, 1, 64)); } },
    { "asm_quality", "0.125..16", "asm: texels per pixel side",
      [](P* p, S v, S w) { p->SetASMQuality(ParseDouble(v, w, 0.125, 16.0)); } },
    { "asm_id_test", "0|1", "asm: the ID+depth test",
      [](P* p, S v, S w) { p->SetASMIDTest(ParseInt(v, w, 0, 1) != 0); } },
    { "frame_budget", "0|1", "interactive frames (DesiredUpdateRate >= 0.1/s) fit the method to the budget",
      [](P* p, S v, S w) { p->SetAdaptToFrameBudget(ParseInt(v, w, 0, 1) != 0); } },
  };
  return options;
}

std::string PassOptionsUsage()
{
  std::ostringstream o;
  o << "options (--option key=value):\n";
  for (const auto& opt : PassOptions())
  {
    std::string head = std::string("  ") + opt.Key + " (" + opt.Values + ")";
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
    keys += (keys.empty() ? "" : ", ") + std::string(opt.Key);
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
