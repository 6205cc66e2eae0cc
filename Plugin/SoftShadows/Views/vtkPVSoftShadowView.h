/**
 * @class   vtkPVSoftShadowView
 * @brief   ParaView render view with soft shadows of area lights.
 *
 * A vtkPVRenderView that installs a vtkSoftShadowPass as its render pass
 * (the pass's shading step renders like vtkPVDefaultPass, so translucency,
 * depth peeling, volumes and annotations keep working).
 *
 * Light policy: ParaView's light kit and headlight never cast shadows; scene
 * lights (added with AddLight / the Light Inspector, Coords "Scene") do, and
 * positional ones become square area lights of side LightSize. With ShadowLight
 * on (default), the view adds one positional area light of its own above the
 * visible data (1.5 bounding-box diagonals along the camera's view-up from the
 * data centre, shifted half a diagonal towards the camera, aimed at the
 * centre), so showing data in this view gives soft shadows with no setup;
 * it takes the place of the light kit's key light (whose intensity is set to
 * 0 while the shadow light is on).
 */
#ifndef vtkPVSoftShadowView_h
#define vtkPVSoftShadowView_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"

#include <string>

class vtkLight;
class vtkSoftShadowPass;

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkPVSoftShadowView : public vtkPVRenderView
{
public:
  static vtkPVSoftShadowView* New();
  vtkTypeMacro(vtkPVSoftShadowView, vtkPVRenderView);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** Visibility solver: 0 auto, 1 hard, 2 pcf, 3 pcss, 4 none, 5 reference, 6 gears, 7 pvsm, 8 hardavg. */
  void SetMethod(int method);
  int GetMethod();

  /** Side of the square area lights (world units); 0 makes point lights. */
  void SetLightSize(double size);
  double GetLightSize() { return this->LightSize; }

  /** Shadow map resolution (rounded up to a power of two). */
  void SetShadowMapSize(int size);

  /** Where GEARS runs: 0 CPU, 1 GL compute (vtkSoftShadowPass::SetGearsBackend). */
  void SetGearsBackend(int backend);
  /** The backend GEARS ran on in the last frame: "cpu" or "gl". */
  const char* GetGearsBackendInUse();

  /** PVSM's quality: scale on the perceptual metric rho (vtkSoftShadowPass::SetPVSMQuality). */
  void SetPVSMQuality(double quality);
  /** The last frame's stats as JSON (vtkSoftShadowPass::GetStatsJSON). */
  const char* GetStatsJSON();

  /** Whether the view adds its own shadow (area) light above the data. */
  void SetShadowLight(bool on);
  bool GetShadowLight() { return this->ShadowLight; }

  /** Intensity of the shadow light (default 0.8). */
  void SetShadowLightIntensity(double intensity);

  vtkSoftShadowPass* GetShadowPass();

protected:
  vtkPVSoftShadowView();
  ~vtkPVSoftShadowView() override;

  void AboutToRenderOnLocalProcess(bool interactive) override;

  double LightSize = 1.0;
  double SavedKeyLightIntensity = 0.75;
  bool ShadowLight = true;
  vtkNew<vtkLight> ShadowLightObject;
  vtkSoftShadowPass* ShadowPass;
  std::string Stats; // backs GetStatsJSON's pointer

private:
  vtkPVSoftShadowView(const vtkPVSoftShadowView&) = delete;
  void operator=(const vtkPVSoftShadowView&) = delete;
};

#endif
