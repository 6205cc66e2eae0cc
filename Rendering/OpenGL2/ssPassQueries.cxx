// vtkSoftShadowPass's queries of the last frame: visibility and G-buffer
// readbacks, the solvers' own results, the plan, the stats and PrintSelf.
// They read the state the frame left in vtkInternals (ssPassInternals.h).
#include "ssPassInternals.h"

#include "ssPVSMSolver.h"
#include "ssTriangleSolver.h"

#include "vtkActor.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkFloatArray.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPropCollection.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTextureObject.h"

#include <algorithm>
#include <sstream>
#include <vector>

using ss::ShadowLight;

//------------------------------------------------------------------------------
// Results of the last frame
int vtkSoftShadowPass::GetNumberOfShadowLights()
{
  int n = 0;
  if (this->Internals->HaveResults)
  {
    for (const auto& l : this->Internals->Frame.Lights)
    {
      n += l.Layer >= 0 ? 1 : 0;
    }
  }
  return n;
}

bool vtkSoftShadowPass::GetVisibilityImage(int shadowLight, vtkFloatArray* out)
{
  auto& in = *this->Internals;
  if (!out || !in.HaveResults || !in.Window || shadowLight < 0 || shadowLight >= this->GetNumberOfShadowLights())
  {
    return false;
  }
  std::vector<float> v;
  if (in.Visibility.GetWidth() != in.Frame.Width || in.Visibility.GetHeight() != in.Frame.Height ||
    !in.Visibility.Read(in.Window, in.FBO, shadowLight, v))
  {
    return false;
  }
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(static_cast<vtkIdType>(v.size()));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    out->SetValue(static_cast<vtkIdType>(i), v[i] < 0.0f ? nan : v[i]);
  }
  return true;
}

bool vtkSoftShadowPass::GetColorVisibilityImage(int shadowLight, vtkFloatArray* out)
{
  auto& in = *this->Internals;
  const ShadowLight* light = nullptr;
  for (const auto& l : in.Frame.Lights)
  {
    light = (l.Layer == shadowLight && l.ColorLayer >= 0) ? &l : light;
  }
  std::vector<float> rgb;
  if (!out || !light || !in.HaveResults || !in.Window || !in.Visibility.ReadColor(in.Window, in.FBO, light->ColorLayer, rgb))
  {
    return false;
  }
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(static_cast<vtkIdType>(rgb.size() / 3));
  std::copy(rgb.begin(), rgb.end(), out->GetPointer(0));
  return true;
}

bool vtkSoftShadowPass::GetPositionsImage(vtkFloatArray* out)
{
  auto& in = *this->Internals;
  std::vector<float> v;
  if (!out || !in.HaveResults || !in.Window || !in.GBuf.Read(in.Window, in.FBO, 0, in.Frame.Width, in.Frame.Height, v))
  {
    return false;
  }
  const std::size_t n = v.size() / 4;
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(static_cast<vtkIdType>(n));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < n; ++i)
  {
    const bool fg = v[4 * i + 3] > 0.0f;
    for (int c = 0; c < 3; ++c)
    {
      out->SetComponent(static_cast<vtkIdType>(i), c, fg ? v[4 * i + c] : nan);
    }
  }
  return true;
}

bool vtkSoftShadowPass::GetDiffuseCosineImage(int shadowLight, vtkFloatArray* out)
{
  auto& in = *this->Internals;
  const ShadowLight* light = nullptr;
  for (const auto& l : in.Frame.Lights)
  {
    light = (l.Layer == shadowLight && shadowLight >= 0) ? &l : light;
  }
  std::vector<float> p, nrm;
  if (!out || !light || !in.HaveResults || !in.Window ||
    !in.GBuf.Read(in.Window, in.FBO, 0, in.Frame.Width, in.Frame.Height, p) ||
    !in.GBuf.Read(in.Window, in.FBO, 1, in.Frame.Width, in.Frame.Height, nrm) || p.size() != nrm.size())
  {
    return false;
  }
  const std::size_t n = p.size() / 4;
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i)
  {
    const glm::dvec3 x(p[4 * i], p[4 * i + 1], p[4 * i + 2]), nv(nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]);
    const double c = p[4 * i + 3] > 0.0f ? ss::DiffuseCosine(light->Frame, x, nv, in.Frame.Eye)
                                         : std::numeric_limits<double>::quiet_NaN();
    out->SetValue(static_cast<vtkIdType>(i), static_cast<float>(c));
  }
  return true;
}

bool vtkSoftShadowPass::GetTranslucentReceiverImages(
  vtkFloatArray* visibility, vtkFloatArray* positions, vtkFloatArray* normals)
{
  auto& in = *this->Internals;
  std::vector<float> V, p, n;
  if (!visibility || !positions || !normals || !in.Window || !in.Capture.Read(in.Window, in.FBO, V, p, n))
  {
    return false;
  }
  auto fill = [](vtkFloatArray* out, const std::vector<float>& values, int comps) {
    out->SetNumberOfComponents(comps);
    out->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / comps));
    std::copy(values.begin(), values.end(), out->GetPointer(0));
  };
  fill(visibility, V, 1);
  fill(positions, p, 3);
  fill(normals, n, 3);
  return true;
}

int vtkSoftShadowPass::GetLastPVSMTileGridLevels()
{
  auto* pvsm = dynamic_cast<ss::PVSMSolver*>(this->Internals->SolverFor(ss::Method::PVSM));
  return pvsm ? static_cast<int>(pvsm->GetLastTileGridLevels().size()) : 0;
}

bool vtkSoftShadowPass::GetLastPVSMTileGridLevel(int level, vtkFloatArray* out)
{
  auto* pvsm = dynamic_cast<ss::PVSMSolver*>(this->Internals->SolverFor(ss::Method::PVSM));
  if (!pvsm || !out || level < 0 || level >= static_cast<int>(pvsm->GetLastTileGridLevels().size()))
  {
    return false;
  }
  const std::vector<float>& l = pvsm->GetLastTileGridLevels()[static_cast<std::size_t>(level)];
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(l.size() / 2));
  std::copy(l.begin(), l.end(), out->GetPointer(0));
  return true;
}

bool vtkSoftShadowPass::GetASMRefining()
{
  const ss::VisibilitySolver* solver = this->Internals->SolverFor(ss::Method::ASM);
  return solver && solver->IsRefining();
}

bool vtkSoftShadowPass::ComputeCasterBulkBounds(vtkRenderer* ren, double bounds[6])
{
  if (!ren || !bounds)
  {
    return false;
  }
  vtkInternals& in = *this->Internals;
  in.Casters.Update(ren, this);
  const ss::Box& b = in.Casters.BulkBounds;
  if (b.Empty())
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] = b.min[a];
    bounds[2 * a + 1] = b.max[a];
  }
  return true;
}

const char* vtkSoftShadowPass::GetLastGearsBackend()
{
  auto* gears = dynamic_cast<ss::TriangleSolver*>(this->Internals->SolverFor(ss::Method::GEARS));
  return gears ? gears->GetLastBackend().c_str() : "none";
}

bool vtkSoftShadowPass::GetShadowMapLayer(vtkRenderWindow* win, int layer, vtkFloatArray* out)
{
  vtkInternals& in = *this->Internals;
  auto* ow = vtkOpenGLRenderWindow::SafeDownCast(win);
  const ss::TextureArray& maps = in.Maps.GetArray();
  if (!ow || !out || !in.FBO || !maps.Handle || layer < 0 || layer >= maps.Layers)
  {
    return false;
  }
  out->SetNumberOfComponents(2);
  out->SetNumberOfTuples(static_cast<vtkIdType>(maps.Size) * maps.Size);
  return in.Maps.Read(ow, in.FBO, layer, out->GetPointer(0));
}

bool vtkSoftShadowPass::GetLastFrameAborted()
{
  return this->Internals->Aborted;
}

int vtkSoftShadowPass::GetLastWidth()
{
  return this->Internals->Frame.Width;
}

int vtkSoftShadowPass::GetLastHeight()
{
  return this->Internals->Frame.Height;
}

void vtkSoftShadowPass::GetLastPositionsOrigin(double origin[3])
{
  for (int i = 0; i < 3; ++i)
  {
    origin[i] = this->Internals->Frame.Origin[i];
  }
}

int vtkSoftShadowPass::GetLastNumberOfCasterTriangles()
{
  return static_cast<int>(this->Internals->Casters.NumberOfTriangles());
}

std::string vtkSoftShadowPass::GetPlanDescription()
{
  return this->Internals->Plan.ToText();
}

std::string vtkSoftShadowPass::GetPlanSummary()
{
  return ss::PlanSummary(this->Internals->Plan, this->Internals->Timings.Get("pass_total"));
}

std::string vtkSoftShadowPass::GetStatsJSON()
{
  auto& in = *this->Internals;
  ss::FrameStats st;
  st.PlanJSON = in.Plan.ToJSON();
  st.Timings = &in.Timings;
  st.MemoryBytes = in.MemoryBytes();
  st.CasterTriangles = in.Casters.NumberOfTriangles();
  st.SkippedTriangles = in.Casters.Skipped;
  for (const auto& solver : in.Solvers)
  {
    solver->Configure(this); // the settings the fragment reports are the current ones
    const std::string fragment = solver->GetStatsJSON();
    if (!fragment.empty())
    {
      st.Solvers.emplace_back(GetMethodName(static_cast<int>(solver->GetMethod())), fragment);
    }
  }
  {
    // where the translucent receivers' V came from (ListTranslucentFragments)
    std::ostringstream o;
    o << "{\"props\": " << in.FrameTranslucent.size() << ", \"lookups\": " << in.FrameLookups << ", \"listed\": " << (in.ShadeListed ? "true" : "false")
      << ", \"fragments\": " << (in.ShadeListed ? in.Lists.Fragments() : 0)
      << ", \"list_bytes\": " << in.Lists.Bytes() << ", \"misses\": " << in.ListMisses << ", \"note\": \""
      << ss::JSONEscape(in.ListsNote) << "\"}";
    st.Solvers.emplace_back("translucent_receivers", o.str());
  }
  st.ShadowMapSize = in.Maps.GetArray().Size;
  st.ShadowMapSizeNote = in.Maps.GetSizeNote();
  for (const auto& l : in.Frame.Lights)
  {
    std::ostringstream o;
    o << "{\"shader_index\": " << l.ShaderIndex << ", \"method\": \"" << GetMethodName(static_cast<int>(l.Method))
      << "\", \"views\": " << l.Views.size() << ", \"cube\": " << (l.ViewInfo.cube ? "true" : "false")
      << ", \"clamped\": " << (l.ViewInfo.clamped ? "true" : "false")
      << ", \"side_views\": " << (l.ViewInfo.sideViews ? "true" : "false")
      << ", \"fitted_to_visible\": " << (l.ViewInfo.fitted ? "true" : "false");
    if (!l.Views.empty())
    {
      // the main view's window (unit-plane or orthographic units): its texel density
      const ss::Rect& e = l.Views.front().extent;
      o << ", \"extent\": [" << e.x0 << ", " << e.y0 << ", " << e.x1 << ", " << e.y1 << "]";
    }
    o << "}";
    st.Lights.push_back(o.str());
  }
  return ss::StatsToJSON(st);
}

//------------------------------------------------------------------------------
void vtkSoftShadowPass::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << GetMethodName(this->Method) << "\n";
  os << indent << "ShadowMapSize: " << this->ShadowMapSize << "\n";
  os << indent << "ConstantBias: " << this->ConstantBias << "\n";
  os << indent << "SlopeBias: " << this->SlopeBias << "\n";
  // the solver options (their keys, as the CLI names them)
  for (int i = 0; i < GetNumberOfSolverOptions(); ++i)
  {
    os << indent << GetSolverOptionKey(i) << ": " << this->GetSolverOptionAsString(GetSolverOptionKey(i)) << "\n";
  }
  os << indent << "AutomaticPositionsOrigin: " << this->AutomaticPositionsOrigin << "\n";
  os << indent << "AdaptToFrameBudget: " << this->AdaptToFrameBudget << "\n";
  os << indent << "NormalOffset: " << this->NormalOffset << "\n";
  os << indent << "FitViewsToVisibleReceivers: " << (this->FitViewsToVisibleReceivers ? "on" : "off") << "\n";
  os << indent << "KeepRequestedMethod: " << (this->KeepRequestedMethod ? "on" : "off") << "\n";
  os << indent << "CaptureTranslucentReceivers: " << this->CaptureTranslucentReceivers << "\n";
  os << indent << "InteractiveUpdateRate: " << this->InteractiveUpdateRate << "\n";
  os << indent << "DelegatePass: " << this->DelegatePass << "\n";
  os << indent << "Plan:\n" << this->Internals->Plan.ToText() << "\n";
}

void vtkSoftShadowPass::ForEachVisibleActor(
  vtkRenderer* ren, const std::function<void(vtkActor*, vtkMatrix4x4*)>& f)
{
  vtkPropCollection* props = ren->GetViewProps();
  vtkCollectionSimpleIterator pit;
  props->InitTraversal(pit);
  while (vtkProp* prop = props->GetNextProp(pit))
  {
    if (!prop->GetVisibility())
    {
      continue;
    }
    prop->InitPathTraversal();
    while (vtkAssemblyPath* path = prop->GetNextPath())
    {
      vtkAssemblyNode* node = path->GetLastNode();
      vtkActor* actor = vtkActor::SafeDownCast(node->GetViewProp());
      if (actor && actor->GetVisibility() && actor->GetMapper())
      {
        f(actor, node->GetMatrix() ? node->GetMatrix() : actor->GetMatrix());
      }
    }
  }
}
