#include "vtkSMSoftShadowDoubleRangeDomain.h"

#include "vtkSMSoftShadowRangeGuard.h"

#include "vtkObjectFactory.h"
#include "vtkSMDoubleVectorProperty.h"

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
  this->Watch.reset(new Guard);
  this->Watch->Watch(prop, this);
  return 1;
}

void vtkSMSoftShadowDoubleRangeDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
