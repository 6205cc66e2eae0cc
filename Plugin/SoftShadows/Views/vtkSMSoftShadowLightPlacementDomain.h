/**
 * @class   vtkSMSoftShadowLightPlacementDomain
 * @brief   Defaults of the Light Visibility filter's rect light from its input's bounds.
 *
 * The filter's XML defaults (a 1 x 1 light at (0, 0, 5)) fit no data in
 * particular: inside the Wavelet source's contours the light sat within the
 * surfaces (stop 44's ParaView sweep). This domain places the light as the Soft
 * Shadow View places its own shadow light when Fixed in Scene with its default
 * direction: 1.5 bounding-box diagonals above the centre of the input's bounds
 * (along +z), facing down (LightNormal's default, 0 0 -1), with sides of 0.1
 * diagonal (the view's default Light Size). The values are set when the
 * filter is created (ParaView's domain defaults, as Clip's origin); they are
 * plain properties afterwards. An empty input keeps the XML defaults.
 * XML: `<SoftShadowLightPlacementDomain name="placement" role="center">` (or
 * `role="size"`) with a required property of function `Input`.
 */
#ifndef vtkSMSoftShadowLightPlacementDomain_h
#define vtkSMSoftShadowLightPlacementDomain_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkSMDomain.h"

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkSMSoftShadowLightPlacementDomain : public vtkSMDomain
{
public:
  static vtkSMSoftShadowLightPlacementDomain* New();
  vtkTypeMacro(vtkSMSoftShadowLightPlacementDomain, vtkSMDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  int SetDefaultValues(vtkSMProperty* prop, bool useUncheckedValues) override;

  /**
   * The light's centre (3 values) or its width and height (2 values) for
   * data of these bounds; false when the bounds are empty or not finite.
   */
  static bool Place(const double bounds[6], bool center, double out[3]);

protected:
  vtkSMSoftShadowLightPlacementDomain();
  ~vtkSMSoftShadowLightPlacementDomain() override;
  int ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element) override;

private:
  vtkSMSoftShadowLightPlacementDomain(const vtkSMSoftShadowLightPlacementDomain&) = delete;
  void operator=(const vtkSMSoftShadowLightPlacementDomain&) = delete;
  bool Center = true;
};

#endif
