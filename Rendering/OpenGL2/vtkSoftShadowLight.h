/**
 * @class   vtkSoftShadowLight
 * @brief   Area-light parameters of a vtkLight, as used by vtkSoftShadowPass.
 *
 * VTK's vtkLight has no notion of area. SoftShadows stores the area of a light
 * in the light's vtkInformation (vtkLight::GetInformation), so that any
 * vtkLight (also ParaView's) can become an area light without subclassing:
 *
 * - A *positional* light (`SetPositional(true)`) with both area sides non-zero is a
 *   one-sided rectangle: its centre is the light position, it faces its focal
 *   point (`normal = normalize(focal_point - position)`), its height edge is
 *   the "up" vector made orthogonal to the normal (Gram-Schmidt) and its width
 *   edge is `normalize(cross(up, normal))`.
 *   With a zero size (either side; the default) the light is a point light: hard shadows.
 * - A *directional* light (`SetPositional(false)`) may have an angular
 *   diameter (degrees): the light is then a disc-like distant source seen
 *   under that angle (the sun is ~0.53 degrees); zero gives hard shadows.
 * - Headlights never cast shadows. Any light can be excluded with
 *   SetCastsShadows(light, false).
 *
 * @code{.cpp}
 *   vtkNew<vtkLight> light;
 *   light->SetPositional(true);
 *   light->SetPosition(0, 0, 5);
 *   light->SetFocalPoint(0, 0, 0);
 *   light->SetConeAngle(90); // no spot cone: the rectangle lights a hemisphere
 *   vtkSoftShadowLight::SetAreaSize(light, 1.0, 0.5);
 *   vtkSoftShadowLight::SetAreaUp(light, 0, 1, 0);
 * @endcode
 */
#ifndef vtkSoftShadowLight_h
#define vtkSoftShadowLight_h

#include "SoftShadowsRenderingOpenGL2Module.h"
#include "vtkObject.h"

class vtkLight;
class vtkInformationDoubleKey;
class vtkInformationDoubleVectorKey;
class vtkInformationIntegerKey;
#ifndef __VTK_WRAP__
namespace ss
{
struct LightFrame;
}
#endif

class SOFTSHADOWSRENDERINGOPENGL2_EXPORT vtkSoftShadowLight : public vtkObject
{
public:
  static vtkSoftShadowLight* New();
  vtkTypeMacro(vtkSoftShadowLight, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Width and height (world units) of a positional light's rectangle.
   * Negative or non-finite values are rejected (error, light unchanged).
   */
  static void SetAreaSize(vtkLight* light, double width, double height);
  static void GetAreaSize(vtkLight* light, double size[2]);
  ///@}

  ///@{
  /**
   * The direction of the rectangle's height edge. When unset, or parallel to
   * the light's normal, the world axis least aligned with the normal is used.
   */
  static void SetAreaUp(vtkLight* light, double x, double y, double z);
  static bool GetAreaUp(vtkLight* light, double up[3]);
  ///@}

  ///@{
  /**
   * Angular diameter (degrees, in [0, 30]) of a directional light.
   */
  static void SetAngularDiameter(vtkLight* light, double degrees);
  static double GetAngularDiameter(vtkLight* light);
  ///@}

  ///@{
  /**
   * Whether the light casts shadows (default: every light but headlights).
   */
  static void SetCastsShadows(vtkLight* light, bool casts);
  static bool GetCastsShadows(vtkLight* light);
  ///@}

#ifndef __VTK_WRAP__
  /**
   * The light's frame (rect, point or directional; see ssLightFrame.h) as the
   * pass and vtkLightVisibilityFilter both build it, with positions relative
   * to `origin` (null: world coordinates). Throws std::invalid_argument for a
   * degenerate light (the message names what is wrong). C++ only.
   */
  static ss::LightFrame MakeLightFrame(vtkLight* light, const double origin[3] = nullptr);
#endif

  static vtkInformationDoubleVectorKey* AREA_SIZE();
  static vtkInformationDoubleVectorKey* AREA_UP();
  static vtkInformationDoubleKey* ANGULAR_DIAMETER();
  static vtkInformationIntegerKey* CASTS_SHADOWS();

protected:
  vtkSoftShadowLight() = default;
  ~vtkSoftShadowLight() override = default;

private:
  vtkSoftShadowLight(const vtkSoftShadowLight&) = delete;
  void operator=(const vtkSoftShadowLight&) = delete;
};

#endif
