/**
 * @class   vtkPVSoftShadowView
 * @brief   ParaView render view with soft shadows of area lights.
 *
 * A vtkPVRenderView that installs a vtkSoftShadowPass as its render pass
 * (the pass's shading step renders like vtkPVDefaultPass, so translucency,
 * depth peeling, volumes and annotations keep working).
 *
 * Lights: ParaView's light kit and headlight never cast shadows; scene lights
 * (added with AddLight / the Light Inspector, Coords "Scene") do. Positional
 * ones become square area lights of their own size (the Light Inspector's
 * "Shadow Size", LIGHT_SIZE) or else LightSize; directional ones get their
 * "Shadow Angular Diameter". With ShadowLight on (default), the view adds a
 * positional area light of its own: 1.5 bounding-box diagonals from the
 * data centre, either following the camera (along its view-up, shifted half
 * a diagonal towards it) or fixed in the scene (along ShadowLightDirection),
 * aimed at the centre. Sizes are fractions of the data's diagonal by default
 * (LightSizeUnits), so a first render looks the same at any scale. While any
 * light casts shadows, the light kit's key light is switched off (its fill,
 * head and back lights stay): the shadow lights take its role, and the
 * picture is not over-exposed.
 *
 * Per object: the display properties Cast Shadows / Receive Shadows
 * (vtkSISoftShadowProperty) are put on the props of the active
 * sub-representation before every render (ApplyRepresentationFlags).
 *
 * Progress: the pass's progress reaches ParaView's progress bar through a
 * vtkAlgorithm registered with the session's progress handler; AbortRender()
 * stops a long render (vtkRenderWindow::SetAbortRender, polled by the pass).
 * In the GUI, the plugin's pqSoftShadowAbortBehavior calls it from the
 * progress bar's abort button (built-in session).
 * The plan and stats are information properties; ShowPlanAnnotation adds a line
 * of text with the plan and the time to the view.
 */
#ifndef vtkPVSoftShadowView_h
#define vtkPVSoftShadowView_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"
#include "vtkWeakPointer.h"

#include <string>

class vtkAlgorithm;
class vtkInformationDoubleKey;
class vtkLight;
class vtkPVDataRepresentation;
class vtkSoftShadowPass;
class vtkTextActor;

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkPVSoftShadowView : public vtkPVRenderView
{
public:
  static vtkPVSoftShadowView* New();
  vtkTypeMacro(vtkPVSoftShadowView, vtkPVRenderView);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** Visibility solver: 0 auto, 1 hard, 2 pcf, 3 pcss, 4 none, 5 reference, 6 gears, 7 pvsm, 8 hardavg. */
  void SetMethod(int method);
  int GetMethod();

  enum LightSizeUnitsType
  {
    FRACTION_OF_DIAGONAL = 0, ///< sizes are fractions of the visible data's bounding-box diagonal (default)
    WORLD_UNITS = 1
  };
  /**
   * Side of the square area lights that have no size of their own (the
   * view's shadow light; scene lights without a Light Inspector size), in
   * LightSizeUnits; 0 makes point lights. Negative or non-finite values are
   * refused (error; the size is unchanged). Default 0.1 of the diagonal.
   */
  void SetLightSize(double size);
  double GetLightSize() { return this->LightSize; }
  void SetLightSizeUnits(int units);
  int GetLightSizeUnits() { return this->LightSizeUnits; }
  /** What one light-size unit is this frame, in world units (the diagonal, or 1). */
  double GetLightSizeScale();

  /** Shadow map resolution (rounded up to a power of two). */
  void SetShadowMapSize(int size);

  /** Where GEARS runs: 0 CPU, 1 GL compute (vtkSoftShadowPass::SetGearsBackend). */
  void SetGearsBackend(int backend);
  /** The backend GEARS ran on in the last frame: "cpu" or "gl". */
  const char* GetGearsBackendInUse();

  /**
   * A solver option (vtkSoftShadowPass::SetSolverOption): the view's
   * per-method properties, generated from the solver registry, reach the
   * pass through this (vtkSISoftShadowProperty). False when refused.
   */
  bool SetSolverOption(const char* key, double value);

  /** PVSM's quality: scale on the perceptual metric rho (vtkSoftShadowPass::SetPVSMQuality). */
  void SetPVSMQuality(double quality);
  /** Interactive renders fit the method to the frame budget (vtkSoftShadowPass::SetAdaptToFrameBudget). */
  void SetAdaptToFrameBudget(bool on);
  /** The last frame's stats as JSON (vtkSoftShadowPass::GetStatsJSON). */
  const char* GetStatsJSON();
  /** The last frame's plan as lines of text (vtkSoftShadowPass::GetPlanDescription). */
  const char* GetPlanDescription();

  /** Whether the view adds its own shadow (area) light. */
  void SetShadowLight(bool on);
  bool GetShadowLight() { return this->ShadowLight; }
  /** Intensity of the shadow light (default 0.75, the light kit's key light). */
  void SetShadowLightIntensity(double intensity);

  enum ShadowLightPlacementType
  {
    FOLLOW_CAMERA = 0, ///< above the data along the camera's view-up, towards the camera (default)
    FIXED_IN_SCENE = 1 ///< along ShadowLightDirection from the data centre; the camera does not move it
  };
  void SetShadowLightPlacement(int placement);
  int GetShadowLightPlacement() { return this->ShadowLightPlacement; }
  /** Where the view's shadow light was in the last frame (world). */
  double* GetShadowLightPosition() VTK_SIZEHINT(3);
  /** World direction from the data centre towards the fixed shadow light (need not be unit; not zero). */
  void SetShadowLightDirection(double x, double y, double z);
  const double* GetShadowLightDirection() { return this->ShadowLightDirection; }

  /** A line of text in the view's corner: the plan and the time of the frame. */
  void SetShowPlanAnnotation(bool on);

  /** Stops the render in progress (vtkRenderWindow::SetAbortRender); the frame shows no shadows. */
  void AbortRender();

  /**
   * ParaView's clipping range (every render), then, where its near plane may
   * pass visible cells (ss::NearPlaneMayPassVisibleCells: beyond a visible
   * prop wholly in front of the camera, or beyond the focal point while the
   * camera is among a prop's bounds), the range from the cells in view
   * (ss::ResetClippingRangeToVisible): a stray triangle far out of view, or a
   * mesh in view reaching 1e10, emptied the picture (stops 50, 51). It runs
   * again just before the frame is drawn, when the representations have
   * handed this frame's data to the mappers. A mesh reaching from the view
   * far out is drawn shifted to the focal point.
   */
  void ResetCameraClippingRange() override;

  ///@{
  /**
   * Around code that lets Qt handle events in the middle of this view's
   * render (the GUI's progress bar repaint, the abort button's event pump):
   * Qt composes a window that holds a QOpenGLWidget with its own context and
   * binds the widget's framebuffer in the view's context (QOpenGLWidget::
   * makeCurrent), behind VTK's state cache. Save keeps the framebuffer
   * bindings (when the view's context is current); Restore makes the context
   * current again and re-binds them. Without it, the pass went on in the
   * wrong context after a long solve in the GUI ("Error in cache state"
   * warnings, GL errors).
   */
  bool SaveGLContext();
  void RestoreGLContext(bool saved);
  ///@}

  vtkSoftShadowPass* GetShadowPass();
  vtkLight* GetShadowLightObject();

  /** A scene light's own area size (Light Inspector "Shadow Size"), in the view's LightSizeUnits. */
  static vtkInformationDoubleKey* LIGHT_SIZE();

  /**
   * Puts a representation's Cast Shadows / Receive Shadows (kept in its
   * vtkInformation as vtkSoftShadowPass::CASTS_SHADOWS / RECEIVES_SHADOWS)
   * on the props of its active sub-representation.
   */
  static void ApplyRepresentationFlags(vtkPVDataRepresentation* rep);

protected:
  vtkPVSoftShadowView();
  ~vtkPVSoftShadowView() override;

  void AboutToRenderOnLocalProcess(bool interactive) override;
  /**
   * ParaView's Render(): ResetCameraClippingRange at its start, before the
   * representations hand the mappers this frame's data, keeps ParaView's
   * range; the cells are walked once, in AboutToRenderOnLocalProcess.
   */
  void Render(bool interactive, bool skip_rendering) override;

  void PlaceShadowLight(const double center[3], double diagonal);
  void UpdateLights(double diagonal);
  void BalanceLightKit(bool shadowLightsOn);
  void OnPassProgress(vtkObject*, unsigned long, void* callData);
  void OnRendered(vtkObject*, unsigned long, void*);

  double LightSize = 0.1;
  int LightSizeUnits = FRACTION_OF_DIAGONAL;
  double LightSizeScale = 1.0;
  bool ShadowLight = true;
  int ShadowLightPlacement = FOLLOW_CAMERA;
  double ShadowLightDirection[3] = { 0.0, 0.0, 1.0 };
  bool ShowPlanAnnotation = false;
  vtkNew<vtkLight> ShadowLightObject;
  vtkSoftShadowPass* ShadowPass;
  vtkNew<vtkTextActor> PlanAnnotation;
  vtkNew<vtkAlgorithm> ProgressReporter; ///< what ParaView's progress handler observes
  bool ProgressRegistered = false;
  bool DeferCellWalk = false; ///< between the start of Render() and AboutToRenderOnLocalProcess
  vtkWeakPointer<vtkLight> KeyLight; ///< the light kit's key light
  std::string Stats; // backs GetStatsJSON's pointer
  std::string Plan;  // backs GetPlanDescription's pointer

private:
  vtkPVSoftShadowView(const vtkPVSoftShadowView&) = delete;
  void operator=(const vtkPVSoftShadowView&) = delete;
};

#endif
