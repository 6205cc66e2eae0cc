#include "vtkSMSoftShadowIntRangeDomain.h"

#include "vtkSMSoftShadowRangeGuard.h"

#include "vtkObjectFactory.h"
#include "vtkSMIntVectorProperty.h"

vtkStandardNewMacro(vtkSMSoftShadowIntRangeDomain);

struct vtkSMSoftShadowIntRangeDomain::Guard : ssparaview::RangeGuard<int, vtkSMIntVectorProperty, vtkSMSoftShadowIntRangeDomain>
{
};

vtkSMSoftShadowIntRangeDomain::vtkSMSoftShadowIntRangeDomain() = default;
vtkSMSoftShadowIntRangeDomain::~vtkSMSoftShadowIntRangeDomain() = default;

int vtkSMSoftShadowIntRangeDomain::ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(prop, element))
  {
    return 0;
  }
  this->Watch.reset(new Guard);
  this->Watch->Watch(prop, this);
  return 1;
}

void vtkSMSoftShadowIntRangeDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
