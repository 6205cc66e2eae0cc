#include "vtkSMSoftShadowLightPlacementDomain.h"

#include "vtkObjectFactory.h"
#include "vtkPVDataInformation.h"
#include "vtkPVXMLElement.h"
#include "vtkSMInputProperty.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"

#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkSMSoftShadowLightPlacementDomain);

vtkSMSoftShadowLightPlacementDomain::vtkSMSoftShadowLightPlacementDomain() = default;
vtkSMSoftShadowLightPlacementDomain::~vtkSMSoftShadowLightPlacementDomain() = default;

int vtkSMSoftShadowLightPlacementDomain::ReadXMLAttributes(vtkSMProperty* prop, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(prop, element))
  {
    return 0;
  }
  const char* role = element->GetAttribute("role");
  if (!role || (std::strcmp(role, "center") != 0 && std::strcmp(role, "size") != 0))
  {
    vtkErrorMacro("SoftShadowLightPlacementDomain needs role=\"center\" or role=\"size\"");
    return 0;
  }
  this->Center = std::strcmp(role, "center") == 0;
  return 1;
}

bool vtkSMSoftShadowLightPlacementDomain::Place(const double b[6], bool center, double out[3])
{
  double h = 0.0; // the squared half diagonal (halves: extents near the double range overflow)
  for (int a = 0; a < 3; ++a)
  {
    if (!(b[2 * a] <= b[2 * a + 1]) || !std::isfinite(b[2 * a]) || !std::isfinite(b[2 * a + 1]))
    {
      return false; // empty (VTK's uninitialised bounds are min > max) or not finite
    }
    const double e = 0.5 * b[2 * a + 1] - 0.5 * b[2 * a];
    h += e * e;
  }
  double diag = 2.0 * std::sqrt(h);
  if (!(diag > 0.0))
  {
    diag = 1.0; // a single point: a light of the XML default's scale around it
  }
  if (center)
  {
    for (int a = 0; a < 3; ++a)
    {
      out[a] = 0.5 * b[2 * a] + 0.5 * b[2 * a + 1];
    }
    out[2] += 1.5 * diag;
    return std::isfinite(out[2]);
  }
  out[0] = out[1] = 0.1 * diag;
  return std::isfinite(diag);
}

int vtkSMSoftShadowLightPlacementDomain::SetDefaultValues(vtkSMProperty* prop, bool useUncheckedValues)
{
  // The input is brought up to date first: in the GUI it has been applied
  // already, but in pvpython `LightVisibility(Input=Contour(...))` creates the
  // filter before the contour ran, and its bounds would still be empty.
  auto* input = vtkSMInputProperty::SafeDownCast(this->GetRequiredProperty("Input"));
  auto* source = input && input->GetNumberOfUncheckedProxies() > 0
    ? vtkSMSourceProxy::SafeDownCast(input->GetUncheckedProxy(0))
    : nullptr;
  if (source)
  {
    source->UpdatePipeline();
  }
  vtkPVDataInformation* info = this->GetInputDataInformation("Input");
  double v[3];
  if (!prop || !info || info->GetNumberOfPoints() == 0 || !Place(info->GetBounds(), this->Center, v))
  {
    return 0;
  }
  vtkSMPropertyHelper helper(prop);
  helper.SetUseUnchecked(useUncheckedValues);
  helper.Set(v, this->Center ? 3 : 2);
  return 1;
}

void vtkSMSoftShadowLightPlacementDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Role: " << (this->Center ? "center" : "size") << "\n";
}
