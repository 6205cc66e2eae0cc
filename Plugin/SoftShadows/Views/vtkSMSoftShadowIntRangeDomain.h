/**
 * @class   vtkSMSoftShadowIntRangeDomain
 * @brief   A integer range domain that refuses values outside it.
 *
 * vtkSMIntRangeDomain only describes the range (the GUI's slider); a
 * value outside it is still pushed. This one also puts the property's last
 * valid value back, with one error naming the property, when a value
 * outside the range or not finite is set (pvpython, the GUI, state files).
 * XML: `<SoftShadowIntRangeDomain name="range" min="0" />`.
 */
#ifndef vtkSMSoftShadowIntRangeDomain_h
#define vtkSMSoftShadowIntRangeDomain_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkSMIntRangeDomain.h"

#include <memory>

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkSMSoftShadowIntRangeDomain : public vtkSMIntRangeDomain
{
public:
  static vtkSMSoftShadowIntRangeDomain* New();
  vtkTypeMacro(vtkSMSoftShadowIntRangeDomain, vtkSMIntRangeDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSMSoftShadowIntRangeDomain();
  ~vtkSMSoftShadowIntRangeDomain() override;
  int ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element) override;

private:
  vtkSMSoftShadowIntRangeDomain(const vtkSMSoftShadowIntRangeDomain&) = delete;
  void operator=(const vtkSMSoftShadowIntRangeDomain&) = delete;
  struct Guard;
  std::unique_ptr<Guard> Watch;
};

#endif
