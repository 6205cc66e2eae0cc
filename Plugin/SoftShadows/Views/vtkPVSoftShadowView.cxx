#include "vtkPVSoftShadowView.h"

#include "vtkAlgorithm.h"
#include "vtkBoundingBox.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkCompositeRepresentation.h"
#include "vtkGeometryRepresentation.h"
#include "vtkHyperTreeGridRepresentation.h"
#include "vtkImageSliceRepresentation.h"
#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkInformationIntegerKey.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkLightKit.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkPVLODActor.h"
#include "vtkPVLODVolume.h"
#include "vtkPVProgressHandler.h"
#include "vtkPVSession.h"
#include "vtkPVSynchronizedRenderer.h"
#include "vtkProcessModule.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkVolumeRepresentation.h"

#include "ssClippingRange.h"

#include <algorithm>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkPVSoftShadowView);
vtkInformationKeyMacro(vtkPVSoftShadowView, LIGHT_SIZE, Double);

vtkPVSoftShadowView::vtkPVSoftShadowView()
  : ShadowPass(vtkSoftShadowPass::New())
{
  this->SynchronizedRenderers->SetRenderPass(this->ShadowPass);
  this->ShadowLightObject->SetLightTypeToSceneLight();
  this->ShadowLightObject->SetPositional(true);
  this->ShadowLightObject->SetConeAngle(90.0);
  this->ShadowLightObject->SetIntensity(0.75);

  this->ShadowPass->AddObserver(vtkCommand::ProgressEvent, this, &vtkPVSoftShadowView::OnPassProgress);
  // the annotation is drawn by the non-composited renderer, after the 3-D
  // one (as vtkPVRenderView's own annotation): the text of the frame drawn
  this->GetRenderer(NON_COMPOSITED_RENDERER)
    ->AddObserver(vtkCommand::StartEvent, this, &vtkPVSoftShadowView::OnRendered);
  this->PlanAnnotation->SetVisibility(false);
  this->PlanAnnotation->GetTextProperty()->SetFontSize(14);
  this->PlanAnnotation->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
  this->PlanAnnotation->GetTextProperty()->SetBackgroundColor(0.0, 0.0, 0.0);
  this->PlanAnnotation->GetTextProperty()->SetBackgroundOpacity(0.5);
  this->PlanAnnotation->SetDisplayPosition(8, 8);
  this->GetRenderer(NON_COMPOSITED_RENDERER)->AddActor2D(this->PlanAnnotation);
  this->ProgressReporter->SetProgressText("Soft shadows");
}

vtkPVSoftShadowView::~vtkPVSoftShadowView()
{
  this->SynchronizedRenderers->SetRenderPass(nullptr);
  this->ShadowPass->RemoveObservers(vtkCommand::ProgressEvent);
  this->ShadowPass->Delete();
}

vtkSoftShadowPass* vtkPVSoftShadowView::GetShadowPass()
{
  return this->ShadowPass;
}

vtkLight* vtkPVSoftShadowView::GetShadowLightObject()
{
  return this->ShadowLightObject;
}

void vtkPVSoftShadowView::SetMethod(int method)
{
  // the pass clamps (VTK's convention); a ParaView user setting an index from
  // Python gets told instead (the enumeration's domain is not checked there)
  vtkSoftShadowPass* pass = this->ShadowPass;
  if (method < pass->GetMethodMinValue() || method > pass->GetMethodMaxValue())
  {
    vtkErrorMacro("Method must be " << pass->GetMethodMinValue() << " to " << pass->GetMethodMaxValue()
                                    << " (or its name), got " << method << "; kept "
                                    << vtkSoftShadowPass::GetMethodName(pass->GetMethod()));
    return;
  }
  this->ShadowPass->SetMethod(method);
  this->Modified();
}

int vtkPVSoftShadowView::GetMethod()
{
  return this->ShadowPass->GetMethod();
}

void vtkPVSoftShadowView::SetLightSize(double size)
{
  if (!(size >= 0.0) || !std::isfinite(size))
  {
    vtkErrorMacro("LightSize must be a finite non-negative number, got " << size << "; kept " << this->LightSize);
    return;
  }
  this->LightSize = size;
  this->Modified();
}

void vtkPVSoftShadowView::SetLightSizeUnits(int units)
{
  if (units != FRACTION_OF_DIAGONAL && units != WORLD_UNITS)
  {
    vtkErrorMacro("LightSizeUnits must be 0 (fraction of the diagonal) or 1 (world units), got " << units);
    return;
  }
  this->LightSizeUnits = units;
  this->Modified();
}

double vtkPVSoftShadowView::GetLightSizeScale()
{
  return this->LightSizeScale;
}

void vtkPVSoftShadowView::SetShadowMapSize(int size)
{
  this->ShadowPass->SetShadowMapSize(size);
  this->Modified();
}

void vtkPVSoftShadowView::SetGearsBackend(int backend)
{
  this->ShadowPass->SetGearsBackend(backend);
  this->Modified();
}

const char* vtkPVSoftShadowView::GetGearsBackendInUse()
{
  return this->ShadowPass->GetLastGearsBackend();
}

bool vtkPVSoftShadowView::SetSolverOption(const char* key, double value)
{
  const bool ok = this->ShadowPass->SetSolverOption(key, value);
  this->Modified();
  return ok;
}

void vtkPVSoftShadowView::SetPVSMQuality(double quality)
{
  this->ShadowPass->SetPVSMQuality(quality);
  this->Modified();
}

void vtkPVSoftShadowView::SetAdaptToFrameBudget(bool on)
{
  this->ShadowPass->SetAdaptToFrameBudget(on);
  this->Modified();
}

const char* vtkPVSoftShadowView::GetStatsJSON()
{
  this->Stats = this->ShadowPass->GetStatsJSON();
  return this->Stats.c_str();
}

const char* vtkPVSoftShadowView::GetPlanDescription()
{
  this->Plan = this->ShadowPass->GetPlanDescription();
  return this->Plan.c_str();
}

void vtkPVSoftShadowView::SetShadowLight(bool on)
{
  this->ShadowLight = on;
  this->Modified();
}

void vtkPVSoftShadowView::SetShadowLightIntensity(double intensity)
{
  if (!(intensity >= 0.0) || !std::isfinite(intensity))
  {
    vtkErrorMacro("ShadowLightIntensity must be a finite non-negative number, got " << intensity);
    return;
  }
  this->ShadowLightObject->SetIntensity(intensity);
  this->Modified();
}

void vtkPVSoftShadowView::SetShadowLightPlacement(int placement)
{
  if (placement != FOLLOW_CAMERA && placement != FIXED_IN_SCENE)
  {
    vtkErrorMacro("ShadowLightPlacement must be 0 (follow camera) or 1 (fixed in scene), got " << placement);
    return;
  }
  this->ShadowLightPlacement = placement;
  this->Modified();
}

void vtkPVSoftShadowView::SetShadowLightDirection(double x, double y, double z)
{
  // Only the direction counts: scaled by its largest component first, so that
  // (1e-300, 0, 0) and (1e300, 1e300, 0) are the directions they name (their
  // length underflows to 0 or overflows to inf in double).
  const double big = std::max({ std::fabs(x), std::fabs(y), std::fabs(z) });
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !(big > 0.0))
  {
    vtkErrorMacro("ShadowLightDirection must be a finite non-zero vector, got (" << x << ", " << y << ", " << z
                                                                                 << ")");
    return;
  }
  this->ShadowLightDirection[0] = x / big;
  this->ShadowLightDirection[1] = y / big;
  this->ShadowLightDirection[2] = z / big;
  this->Modified();
}

double* vtkPVSoftShadowView::GetShadowLightPosition()
{
  return this->ShadowLightObject->GetPosition();
}

void vtkPVSoftShadowView::SetShowPlanAnnotation(bool on)
{
  this->ShowPlanAnnotation = on;
  this->PlanAnnotation->SetVisibility(on);
  this->Modified();
}

void vtkPVSoftShadowView::AbortRender()
{
  if (vtkRenderWindow* win = this->GetRenderWindow())
  {
    win->SetAbortRender(1);
  }
}

//------------------------------------------------------------------------------
namespace
{
// The props a representation draws (the classes ParaView gives access to).
vtkProp* RenderedProp(vtkPVDataRepresentation* rep)
{
  if (auto* geometry = vtkGeometryRepresentation::SafeDownCast(rep))
  {
    return geometry->GetActor();
  }
  if (auto* volume = vtkVolumeRepresentation::SafeDownCast(rep))
  {
    return volume->GetActor();
  }
  if (auto* slice = vtkImageSliceRepresentation::SafeDownCast(rep))
  {
    return slice->GetActor();
  }
  if (auto* htg = vtkHyperTreeGridRepresentation::SafeDownCast(rep))
  {
    return htg->GetActor();
  }
  return nullptr;
}

bool Flag(vtkInformation* info, vtkInformationIntegerKey* key)
{
  return !info->Has(key) || info->Get(key) != 0;
}
}

void vtkPVSoftShadowView::ResetCameraClippingRange()
{
  this->Superclass::ResetCameraClippingRange();
  vtkRenderer* ren = this->GetRenderer();
  if (!ren || this->GetLockBounds() || this->DeferCellWalk)
  {
    return;
  }
  const double aspect = ren->GetTiledAspectRatio();
  if (ss::NearPlaneMayPassVisibleCells(ren, aspect))
  {
    ss::ResetClippingRangeToVisible(ren, aspect);
  }
  ss::ShiftFarReachingMappersToTheFocalPoint(ren);
}

void vtkPVSoftShadowView::Render(bool interactive, bool skip_rendering)
{
  // (the walk over the cells at the start of Render() read the mappers'
  // previous data and was done again before drawing: on the 5M assembly
  // with a lost vertex, twice 40 ms a frame)
  this->DeferCellWalk = true;
  this->Superclass::Render(interactive, skip_rendering);
  this->DeferCellWalk = false;
}

void vtkPVSoftShadowView::ApplyRepresentationFlags(vtkPVDataRepresentation* rep)
{
  vtkInformation* info = rep ? rep->GetInformation() : nullptr;
  if (!info || (!info->Has(vtkSoftShadowPass::CASTS_SHADOWS()) && !info->Has(vtkSoftShadowPass::RECEIVES_SHADOWS())))
  {
    return;
  }
  const bool casts = Flag(info, vtkSoftShadowPass::CASTS_SHADOWS());
  const bool receives = Flag(info, vtkSoftShadowPass::RECEIVES_SHADOWS());
  vtkPVDataRepresentation* target = rep;
  if (auto* composite = vtkCompositeRepresentation::SafeDownCast(rep))
  {
    target = composite->GetActiveRepresentation();
  }
  if (vtkProp* prop = RenderedProp(target))
  {
    // only on change: a prop's keys are part of its MTime, and a changed
    // prop rebuilds the caster set
    if (vtkSoftShadowPass::GetCastsShadows(prop) != casts)
    {
      vtkSoftShadowPass::SetCastsShadows(prop, casts);
    }
    if (vtkSoftShadowPass::GetReceivesShadows(prop) != receives)
    {
      vtkSoftShadowPass::SetReceivesShadows(prop, receives);
    }
  }
}

//------------------------------------------------------------------------------
void vtkPVSoftShadowView::AboutToRenderOnLocalProcess(bool interactive)
{
  this->Superclass::AboutToRenderOnLocalProcess(interactive);
  vtkRenderer* ren = this->GetRenderer();
  // ParaView resets the clipping range at the start of Render(), before the
  // representations hand their data to the mappers: a mesh shown since the
  // last render was not among the cells the range was fitted to, and a broken
  // one (a lost vertex far out) left its first frame empty, the picture a
  // SaveScreenshot after Show() takes (stop 51). So again, with this frame's
  // data; the call at the start of Render() kept ParaView's range (Render).
  this->DeferCellWalk = false;
  this->ResetCameraClippingRange();

  // per object: the representations' Cast / Receive Shadows
  for (int i = 0; i < this->GetNumberOfRepresentations(); ++i)
  {
    ApplyRepresentationFlags(vtkPVDataRepresentation::SafeDownCast(this->GetRepresentation(i)));
  }

  // the data's size: what relative light sizes and the light's distance scale with
  vtkBoundingBox box(this->GeometryBounds);
  if (!box.IsValid())
  {
    double b[6];
    ren->ComputeVisiblePropBounds(b);
    box.SetBounds(b);
  }
  // ... unless the data reaches more than 100 times farther than the
  // casters' bulk (a mesh with a needle to a lost vertex at 1e10): then the
  // bulk's. From the whole bounds the shadow light stood 1.5e10 away, 1e9
  // wide, and the shadow-map methods drew no shadow (stop 50).
  double bulk[6];
  if (box.IsValid() && this->ShadowPass && this->ShadowPass->ComputeCasterBulkBounds(ren, bulk))
  {
    vtkBoundingBox casters(bulk);
    if (box.GetDiagonalLength() > 100.0 * std::max(casters.GetDiagonalLength(), 1e-300))
    {
      box = casters;
    }
  }
  double diagonal = 1.0;
  if (box.IsValid())
  {
    double c[3];
    box.GetCenter(c);
    diagonal = std::max(box.GetDiagonalLength(), 1e-30);
    this->PlaceShadowLight(c, diagonal);
  }
  this->LightSizeScale = this->LightSizeUnits == FRACTION_OF_DIAGONAL ? diagonal : 1.0;

  vtkLightCollection* lights = ren->GetLights();
  const bool present = lights->IsItemPresent(this->ShadowLightObject) != 0;
  if (this->ShadowLight && !present && box.IsValid())
  {
    ren->AddLight(this->ShadowLightObject);
  }
  else if ((!this->ShadowLight || !box.IsValid()) && present)
  {
    ren->RemoveLight(this->ShadowLightObject);
  }
  this->UpdateLights(diagonal);

  // progress: ParaView's progress handler observes vtkAlgorithms only
  if (!this->ProgressRegistered)
  {
    vtkProcessModule* pm = vtkProcessModule::GetProcessModule();
    auto* session = pm ? vtkPVSession::SafeDownCast(pm->GetActiveSession()) : nullptr;
    if (session && session->GetProgressHandler())
    {
      session->GetProgressHandler()->RegisterProgressEvent(this->ProgressReporter, 0);
      this->ProgressRegistered = true;
    }
  }
  this->ProgressReporter->SetProgressText(
    (std::string("Soft shadows (") + vtkSoftShadowPass::GetMethodName(this->GetMethod()) + ")").c_str());
}

void vtkPVSoftShadowView::PlaceShadowLight(const double c[3], double diag)
{
  double dir[3];
  if (this->ShadowLightPlacement == FIXED_IN_SCENE)
  {
    // 1.5 diagonals from the centre along the fixed direction
    const double* d = this->ShadowLightDirection;
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; ++i)
    {
      dir[i] = 1.5 * diag * d[i] / n;
    }
  }
  else
  {
    // 1.5 diagonals along the camera's view-up, half a diagonal towards it
    vtkCamera* cam = this->GetRenderer()->GetActiveCamera();
    double up[3], pos[3], toCam[3];
    cam->GetViewUp(up);
    cam->GetPosition(pos);
    for (int i = 0; i < 3; ++i)
    {
      toCam[i] = pos[i] - c[i];
    }
    const double n = std::sqrt(toCam[0] * toCam[0] + toCam[1] * toCam[1] + toCam[2] * toCam[2]);
    for (int i = 0; i < 3; ++i)
    {
      dir[i] = 1.5 * diag * up[i] + (n > 0 ? 0.5 * diag * toCam[i] / n : 0.0);
    }
  }
  const double p[3] = { c[0] + dir[0], c[1] + dir[1], c[2] + dir[2] };
  double old[3], oldFocal[3];
  this->ShadowLightObject->GetPosition(old);
  this->ShadowLightObject->GetFocalPoint(oldFocal);
  if (old[0] != p[0] || old[1] != p[1] || old[2] != p[2] || oldFocal[0] != c[0] || oldFocal[1] != c[1] ||
    oldFocal[2] != c[2])
  {
    this->ShadowLightObject->SetPosition(p);
    this->ShadowLightObject->SetFocalPoint(c[0], c[1], c[2]);
  }
}

void vtkPVSoftShadowView::UpdateLights(double diagonal)
{
  (void)diagonal;
  // Light policy: only scene lights cast; positional ones get their area
  // size (their own, else LightSize) in world units.
  bool anyShadowLight = false;
  vtkCollectionSimpleIterator it;
  vtkLightCollection* lights = this->GetRenderer()->GetLights();
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    const bool scene = light->LightTypeIsSceneLight() != 0;
    if (vtkSoftShadowLight::GetCastsShadows(light) != scene)
    {
      vtkSoftShadowLight::SetCastsShadows(light, scene);
    }
    anyShadowLight = anyShadowLight || (scene && light->GetSwitch());
    if (scene && light->GetPositional())
    {
      vtkInformation* info = light->GetInformation();
      const double own = (info && info->Has(LIGHT_SIZE())) ? info->Get(LIGHT_SIZE()) : this->LightSize;
      // (a size times the data's diagonal can overflow: the largest double
      // instead, which the pass shadows as 1e30 with its warning; an
      // infinite size was refused and the light kept the last frame's)
      const double s = std::min(
        (light == this->ShadowLightObject.GetPointer() ? this->LightSize : own) * this->LightSizeScale,
        std::numeric_limits<double>::max());
      double size[2];
      vtkSoftShadowLight::GetAreaSize(light, size);
      if (size[0] != s || size[1] != s)
      {
        vtkSoftShadowLight::SetAreaSize(light, s, s);
      }
    }
  }
  this->BalanceLightKit(anyShadowLight);
}

void vtkPVSoftShadowView::BalanceLightKit(bool shadowLightsOn)
{
  if (!this->LightKit)
  {
    return;
  }
  // vtkLightKit::AddLightsToRenderer adds head, key, fill, back, back: the
  // second light of a probe renderer is the kit's key light. Its intensity
  // also sets the others' (by ratios), so it is switched off, not dimmed.
  if (!this->KeyLight)
  {
    vtkNew<vtkRenderer> probe;
    this->LightKit->AddLightsToRenderer(probe);
    this->KeyLight = vtkLight::SafeDownCast(probe->GetLights()->GetItemAsObject(1));
  }
  vtkLight* key = this->KeyLight;
  if (key && key->GetSwitch() != (shadowLightsOn ? 0 : 1))
  {
    key->SetSwitch(shadowLightsOn ? 0 : 1);
  }
}

//------------------------------------------------------------------------------
void vtkPVSoftShadowView::OnPassProgress(vtkObject*, unsigned long, void* callData)
{
  const double p = *static_cast<double*>(callData);
  // in the GUI the progress bar repaints at once (pqProgressWidget::updateUI)
  const bool saved = this->SaveGLContext();
  this->ProgressReporter->UpdateProgress(p);
  this->RestoreGLContext(saved);
}

bool vtkPVSoftShadowView::SaveGLContext()
{
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(this->GetRenderWindow());
  if (!win || !win->IsCurrent())
  {
    return false;
  }
  win->GetState()->PushFramebufferBindings();
  return true;
}

void vtkPVSoftShadowView::RestoreGLContext(bool saved)
{
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(this->GetRenderWindow());
  if (!win || !saved)
  {
    return;
  }
  if (!win->IsCurrent())
  {
    win->MakeCurrent();
  }
  win->GetState()->PopFramebufferBindings();
}

void vtkPVSoftShadowView::OnRendered(vtkObject*, unsigned long, void*)
{
  if (this->ShowPlanAnnotation)
  {
    this->PlanAnnotation->SetInput(("Soft shadows: " + this->ShadowPass->GetPlanSummary()).c_str());
  }
}

void vtkPVSoftShadowView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LightSize: " << this->LightSize
     << (this->LightSizeUnits == FRACTION_OF_DIAGONAL ? " of the diagonal" : " world units") << "\n";
  os << indent << "ShadowLight: " << this->ShadowLight << "\n";
  os << indent << "ShadowLightPlacement: "
     << (this->ShadowLightPlacement == FIXED_IN_SCENE ? "fixed in scene" : "follow camera") << "\n";
  os << indent << "ShowPlanAnnotation: " << this->ShowPlanAnnotation << "\n";
  this->ShadowPass->PrintSelf(os, indent.GetNextIndent());
}
