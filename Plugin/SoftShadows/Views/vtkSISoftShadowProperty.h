/**
 * @class   vtkSISoftShadowProperty
 * @brief   Server side of the plugin's per-object and per-light properties.
 *
 * ParaView's representations and lights have no soft-shadow settings, and an
 * XML `<Extension>` can add properties to their proxies but not methods to
 * their VTK classes. This property (`si_class="vtkSISoftShadowProperty"`)
 * takes the one number the client pushes and applies it where
 * vtkSoftShadowPass and vtkPVSoftShadowView read it; its XML `command` says
 * what it sets:
 *
 * - `CastsShadows`, `ReceivesShadows` (representations): vtkSoftShadowPass's
 *   prop keys, kept on the representation; vtkPVSoftShadowView puts them on
 *   the props of its active sub-representation every frame (surface,
 *   wireframe, points, outline, feature edges, 3D glyphs, surface LIC,
 *   volume, slice, hyper tree grid).
 * - `LightSize` (lights): a scene light's own area size, in the Soft Shadow
 *   View's light-size units (vtkPVSoftShadowView::LIGHT_SIZE).
 * - `AngularDiameter` (lights): a directional light's angular diameter in
 *   degrees (vtkSoftShadowLight::SetAngularDiameter).
 * - any other command on the Soft Shadow View: a solver option's key
 *   (`pvsm_quality`, ...; vtkPVSoftShadowView::SetSolverOption). These
 *   properties are generated from the solver registry at build time
 *   (ssGenerateViewXML), so a method's options need no view method.
 *
 * A value the target refuses (negative size, angle outside [0, 30]) gives
 * one error and leaves the target unchanged. The XML default is applied when
 * the object is made.
 */
#ifndef vtkSISoftShadowProperty_h
#define vtkSISoftShadowProperty_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkSIProperty.h"

class vtkObjectBase;

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkSISoftShadowProperty : public vtkSIProperty
{
public:
  static vtkSISoftShadowProperty* New();
  vtkTypeMacro(vtkSISoftShadowProperty, vtkSIProperty);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Applies `command` with `value` to `object` (a representation or a
   * light); false, with an error, when the command does not apply to it or
   * the value is refused. Public for tests.
   */
  static bool Apply(vtkObjectBase* object, const char* command, double value);

protected:
  vtkSISoftShadowProperty();
  ~vtkSISoftShadowProperty() override;

  bool Push(vtkSMMessage* message, int offset) override;
  /**
   * Also applies the XML default to the VTK object: ParaView pushes a
   * property only once it is modified (a light made by AddLight or a state
   * file is never pushed its defaults), and the panel must show what the
   * object has.
   */
  bool ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element) override;

private:
  vtkSISoftShadowProperty(const vtkSISoftShadowProperty&) = delete;
  void operator=(const vtkSISoftShadowProperty&) = delete;
};

#endif
