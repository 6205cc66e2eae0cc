#include "vtkSMSoftShadowDoubleRangeDomain.h"

#include "vtkSMSoftShadowRangeGuard.h"

#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkSMDoubleVectorProperty.h"

#include <string>

vtkStandardNewMacro(vtkSMSoftShadowDoubleRangeDomain);

struct vtkSMSoftShadowDoubleRangeDomain::Guard : ssparaview::RangeGuard<double, vtkSMDoubleVectorProperty, vtkSMSoftShadowDoubleRangeDomain>
{
};

vtkSMSoftShadowDoubleRangeDomain::vtkSMSoftShadowDoubleRangeDomain() = default;
vtkSMSoftShadowDoubleRangeDomain::~vtkSMSoftShadowDoubleRangeDomain() = default;

int vtkSMSoftShadowDoubleRangeDomain::ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(prop, element))
  {
    return 0;
  }
  const char* nonZero = element->GetAttribute("nonzero");
  this->Watch.reset(new Guard);
  this->Watch->Watch(prop, this, nonZero && std::string(nonZero) == "1");
  return 1;
}

void vtkSMSoftShadowDoubleRangeDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
