/**
 * @class   vtkSMSoftShadowDoubleRangeDomain
 * @brief   A double range domain that refuses values outside it.
 *
 * vtkSMDoubleRangeDomain only describes the range (the GUI's slider); a
 * value outside it is still pushed. This one also puts the property's last
 * valid value back, with one error naming the property, when a value
 * outside the range or not finite is set (pvpython, the GUI, state files).
 * XML: `<SoftShadowDoubleRangeDomain name="range" min="0" />`; with
 * `nonzero="1"` a vector of zeros is refused too (a direction).
 */
#ifndef vtkSMSoftShadowDoubleRangeDomain_h
#define vtkSMSoftShadowDoubleRangeDomain_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkSMDoubleRangeDomain.h"

#include <memory>

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkSMSoftShadowDoubleRangeDomain : public vtkSMDoubleRangeDomain
{
public:
  static vtkSMSoftShadowDoubleRangeDomain* New();
  vtkTypeMacro(vtkSMSoftShadowDoubleRangeDomain, vtkSMDoubleRangeDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSMSoftShadowDoubleRangeDomain();
  ~vtkSMSoftShadowDoubleRangeDomain() override;
  int ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element) override;

private:
  vtkSMSoftShadowDoubleRangeDomain(const vtkSMSoftShadowDoubleRangeDomain&) = delete;
  void operator=(const vtkSMSoftShadowDoubleRangeDomain&) = delete;
  struct Guard;
  std::unique_ptr<Guard> Watch;
};

#endif
