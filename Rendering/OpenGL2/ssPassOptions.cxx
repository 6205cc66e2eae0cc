// vtkSoftShadowPass's solver options (issue 19): the generic API over the
// registry's typed option lists, and the deprecated per-option forwarders
// (SetPVSMQuality, ...) that keep Python scripts, ParaView state files and C++
// callers working. The options themselves are declared in each solver's
// Options() (ssPVSMSolver.cxx, ...).
#include "ssPassInternals.h"
#include "ssSolverRegistry.h"
#include "ssTriangleSet.h"

#include "vtkObjectFactory.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace
{
const ss::OptionDescriptor* Descriptor(int i)
{
  const auto& all = ss::RegisteredOptions();
  return i >= 0 && i < static_cast<int>(all.size()) ? all[i].Descriptor : nullptr;
}

const ss::OptionDescriptor* ByProperty(const char* property)
{
  for (const auto& r : ss::RegisteredOptions())
  {
    if (std::string(property) == r.Descriptor->Property)
    {
      return r.Descriptor;
    }
  }
  return nullptr;
}

double Clamped(const ss::OptionDescriptor& d, double v)
{
  return std::max(d.Min, std::min(v, d.Max));
}
}

void vtkSoftShadowPass::ResetSolverOptions()
{
  std::vector<const ss::OptionDescriptor*> list;
  for (const auto& r : ss::RegisteredOptions())
  {
    list.push_back(r.Descriptor);
  }
  this->Internals->SolverOptions = ss::OptionStore(std::move(list));
  this->Modified();
}

bool vtkSoftShadowPass::SetSolverOption(const char* key, double value)
{
  const std::string k = key ? key : "";
  auto& store = this->Internals->SolverOptions;
  const double before = store.Get(k);
  const std::string err = store.Set(k, value);
  if (!err.empty())
  {
    vtkErrorMacro("SetSolverOption: " << err << (store.Find(k) < 0 ? "" : "; value unchanged"));
    return false;
  }
  if (before != value)
  {
    this->Modified();
  }
  return true;
}

bool vtkSoftShadowPass::SetSolverOption(const char* key, int value)
{
  return this->SetSolverOption(key, static_cast<double>(value));
}

bool vtkSoftShadowPass::SetSolverOption(const char* key, const char* value)
{
  const std::string k = key ? key : "";
  auto& store = this->Internals->SolverOptions;
  const double before = store.Get(k);
  const std::string err = store.SetText(k, value ? value : "");
  if (!err.empty())
  {
    vtkErrorMacro("SetSolverOption: " << err << (store.Find(k) < 0 ? "" : "; value unchanged"));
    return false;
  }
  if (before != store.Get(k))
  {
    this->Modified();
  }
  return true;
}

double vtkSoftShadowPass::GetSolverOption(const char* key)
{
  const std::string k = key ? key : "";
  const int i = this->Internals->SolverOptions.Find(k);
  if (i < 0)
  {
    vtkErrorMacro("GetSolverOption: unknown solver option '" << k << "'");
    return std::numeric_limits<double>::quiet_NaN();
  }
  return this->Internals->SolverOptions.Get(static_cast<std::size_t>(i));
}

std::string vtkSoftShadowPass::GetSolverOptionAsString(const char* key)
{
  const std::string k = key ? key : "";
  const auto& store = this->Internals->SolverOptions;
  const int i = store.Find(k);
  if (i < 0)
  {
    return {};
  }
  const auto& d = store.Descriptor(static_cast<std::size_t>(i));
  const double v = store.Get(static_cast<std::size_t>(i));
  return d.Type == ss::OptionType::Enum ? d.Names[static_cast<std::size_t>(v)] : ss::FormatNumber(v);
}

int vtkSoftShadowPass::GetNumberOfSolverOptions()
{
  return static_cast<int>(ss::RegisteredOptions().size());
}

int vtkSoftShadowPass::FindSolverOption(const char* key)
{
  const auto& all = ss::RegisteredOptions();
  for (std::size_t i = 0; key && i < all.size(); ++i)
  {
    if (std::string(key) == all[i].Descriptor->Key)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

const char* vtkSoftShadowPass::GetSolverOptionKey(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Key : nullptr;
}

const char* vtkSoftShadowPass::GetSolverOptionPropertyName(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Property : nullptr;
}

const char* vtkSoftShadowPass::GetSolverOptionLabel(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Label : nullptr;
}

const char* vtkSoftShadowPass::GetSolverOptionHelp(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Help : nullptr;
}

const char* vtkSoftShadowPass::GetSolverOptionType(int i)
{
  const auto* d = Descriptor(i);
  return d ? ss::OptionTypeName(d->Type) : nullptr;
}

double vtkSoftShadowPass::GetSolverOptionMinimum(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Min : std::numeric_limits<double>::quiet_NaN();
}

double vtkSoftShadowPass::GetSolverOptionMaximum(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Max : std::numeric_limits<double>::quiet_NaN();
}

double vtkSoftShadowPass::GetSolverOptionDefault(int i)
{
  const auto* d = Descriptor(i);
  return d ? d->Default : std::numeric_limits<double>::quiet_NaN();
}

int vtkSoftShadowPass::GetSolverOptionNumberOfNames(int i)
{
  const auto* d = Descriptor(i);
  return d ? static_cast<int>(d->Names.size()) : 0;
}

const char* vtkSoftShadowPass::GetSolverOptionName(int i, int value)
{
  const auto* d = Descriptor(i);
  return d && value >= 0 && value < static_cast<int>(d->Names.size()) ? d->Names[value].c_str() : nullptr;
}

std::string vtkSoftShadowPass::GetSolverOptionValues(int i)
{
  const auto* d = Descriptor(i);
  return d ? ss::DescribeValues(*d) : std::string();
}

std::string vtkSoftShadowPass::GetSolverOptionDefaultAsString(int i)
{
  const auto* d = Descriptor(i);
  if (!d)
  {
    return {};
  }
  return d->Type == ss::OptionType::Enum ? d->Names[static_cast<std::size_t>(d->Default)]
                                         : ss::FormatNumber(d->Default);
}

const char* vtkSoftShadowPass::GetSolverOptionMethods(int i)
{
  const auto& all = ss::RegisteredOptions();
  return i >= 0 && i < static_cast<int>(all.size()) ? all[i].Methods.c_str() : nullptr;
}

// The deprecated forwarders: the option of the same property name, clamped
// to its range as the old vtkSetClampMacro did.
#define ssForwardOption(name, type)                                                                \
  void vtkSoftShadowPass::Set##name(type v)                                                        \
  {                                                                                                \
    const ss::OptionDescriptor* d = ByProperty(#name);                                             \
    this->SetSolverOption(d->Key, Clamped(*d, static_cast<double>(v)));                            \
  }                                                                                                \
  type vtkSoftShadowPass::Get##name()                                                              \
  {                                                                                                \
    return static_cast<type>(this->GetSolverOption(ByProperty(#name)->Key));                       \
  }
#define ssForwardBoolOption(name)                                                                  \
  ssForwardOption(name, bool) void vtkSoftShadowPass::name##On() { this->Set##name(true); }       \
  void vtkSoftShadowPass::name##Off() { this->Set##name(false); }

ssForwardOption(ReferenceSamples, int)
ssForwardOption(ReferencePattern, int)
ssForwardOption(GearsSamples, int)
ssForwardOption(GearsGrid, int)
ssForwardOption(GearsRaster, int)
ssForwardOption(GearsCountNecessary, bool)
ssForwardBoolOption(GearsFindPieces)
ssForwardBoolOption(GearsCellCulling)
ssForwardBoolOption(GearsWinding)
ssForwardOption(GearsGLLayers, int)
ssForwardOption(GearsBackend, int)
ssForwardOption(PVSMLowResolution, int)
ssForwardOption(PVSMGridSize, int)
ssForwardOption(PVSMMaxTileResolution, int)
ssForwardOption(PVSMQuality, double)
ssForwardOption(PVSMMetric, int)
ssForwardBoolOption(PVSMTileCulling)
ssForwardBoolOption(CasterCulling)
ssForwardOption(AverageSamples, int)
ssForwardOption(AVSMNodes, int)
ssForwardOption(AVSMSize, int)
ssForwardOption(AVSMMemory, int)
ssForwardBoolOption(ColoredShadows)
ssForwardOption(VolumeSteps, int)
ssForwardOption(VPCSSFilterQuads, int)
ssForwardOption(ASMMemoryBudget, double)
ssForwardOption(ASMPageSize, int)
ssForwardOption(ASMCells, int)
ssForwardOption(ASMMaxDepth, int)
ssForwardOption(ASMTimeBudget, double)
ssForwardOption(ASMAnalysisStride, int)
ssForwardOption(ASMQuality, double)
ssForwardBoolOption(ASMIDTest)
ssForwardOption(PCFRadius, double)
ssForwardOption(BlockerSearchSamples, int)
ssForwardOption(FilterMaxQuads, int)

// --- frame-wide numbers that are not solver options: NaN and inf refused
// (stop 45's Python sweep: a NaN constant bias turned every pixel of hard
// black, and the clamp macros let NaN through)
namespace
{
// member = value clamped to [lo, hi]; a value that is NaN (or, when lo and hi
// are infinite, inf) is an error naming `what`, and member is kept. Whether
// the member changed.
bool SetChecked(vtkObject* self, const char* what, double& member, double value, double lo, double hi)
{
  if (std::isnan(value) || (std::isinf(value) && (std::isinf(lo) || std::isinf(hi))))
  {
    vtkErrorWithObjectMacro(self, << what << ": " << value << " is not a usable number; " << member << " kept");
    return false;
  }
  value = std::min(std::max(value, lo), hi);
  if (member == value)
  {
    return false;
  }
  member = value;
  return true;
}

constexpr double kAny = std::numeric_limits<double>::infinity();
}

void vtkSoftShadowPass::SetConstantBias(double texels)
{
  if (SetChecked(this, "SetConstantBias", this->ConstantBias, texels, -kAny, kAny))
  {
    this->Modified();
  }
}

void vtkSoftShadowPass::SetSlopeBias(double texels)
{
  if (SetChecked(this, "SetSlopeBias", this->SlopeBias, texels, -kAny, kAny))
  {
    this->Modified();
  }
}

void vtkSoftShadowPass::SetNormalOffset(double texels)
{
  if (SetChecked(this, "SetNormalOffset", this->NormalOffset, texels, 0.0, 16.0))
  {
    this->Modified();
  }
}

void vtkSoftShadowPass::SetInteractiveUpdateRate(double rate)
{
  if (SetChecked(this, "SetInteractiveUpdateRate", this->InteractiveUpdateRate, rate, 1e-6, 1e6))
  {
    this->Modified();
  }
}

void vtkSoftShadowPass::SetPositionsOrigin(double x, double y, double z)
{
  // the G-buffer holds float positions relative to it: beyond 1e30 their
  // squares leave the float range (and NaN positions no surface at all)
  if (!ss::WithinSolverReach(glm::dvec3(x, y, z)))
  {
    vtkErrorMacro("SetPositionsOrigin: (" << x << ", " << y << ", " << z
                                          << ") is not a finite point within 1e30 of the world origin; ("
                                          << this->PositionsOrigin[0] << ", " << this->PositionsOrigin[1] << ", "
                                          << this->PositionsOrigin[2] << ") kept");
    return;
  }
  if (this->PositionsOrigin[0] != x || this->PositionsOrigin[1] != y || this->PositionsOrigin[2] != z)
  {
    this->PositionsOrigin[0] = x;
    this->PositionsOrigin[1] = y;
    this->PositionsOrigin[2] = z;
    this->Modified();
  }
}
