#include "vtkSMSoftShadowViewProxy.h"

#include "vtkObjectFactory.h"
#include "vtkSMProperty.h"

vtkStandardNewMacro(vtkSMSoftShadowViewProxy);

vtkSMSoftShadowViewProxy::vtkSMSoftShadowViewProxy() = default;
vtkSMSoftShadowViewProxy::~vtkSMSoftShadowViewProxy() = default;

void vtkSMSoftShadowViewProxy::PostRender(bool interactive)
{
  this->Superclass::PostRender(interactive);
  for (const char* name : { "Plan", "Stats", "GearsBackendInUse", "ShadowLightPosition" })
  {
    if (vtkSMProperty* prop = this->GetProperty(name))
    {
      this->UpdatePropertyInformation(prop);
    }
  }
}

void vtkSMSoftShadowViewProxy::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
