#include "vtkSISoftShadowProperty.h"

#include "vtkPVSoftShadowView.h"

#include "vtkInformation.h"
#include "vtkInformationDoubleKey.h"
#include "vtkLight.h"
#include "vtkInformationIntegerKey.h"
#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkPVDataRepresentation.h"
#include "vtkSMMessage.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"

#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkSISoftShadowProperty);

vtkSISoftShadowProperty::vtkSISoftShadowProperty() = default;
vtkSISoftShadowProperty::~vtkSISoftShadowProperty() = default;

bool vtkSISoftShadowProperty::Apply(vtkObjectBase* object, const char* command, double value)
{
  const std::string cmd = command ? command : "";
  if (cmd == "CastsShadows" || cmd == "ReceivesShadows")
  {
    auto* rep = vtkPVDataRepresentation::SafeDownCast(object);
    if (!rep || !std::isfinite(value))
    {
      return false;
    }
    // kept on the representation: the Soft Shadow View applies it to the
    // props of whichever sub-representation is active, every frame
    rep->GetInformation()->Set(cmd == "CastsShadows" ? vtkSoftShadowPass::CASTS_SHADOWS()
                                                     : vtkSoftShadowPass::RECEIVES_SHADOWS(),
      value != 0.0 ? 1 : 0);
    vtkPVSoftShadowView::ApplyRepresentationFlags(rep);
    return true;
  }
  if (auto* view = vtkPVSoftShadowView::SafeDownCast(object))
  {
    // the view's solver options: the command is the option's key
    // (SoftShadowView.xml's generated section, from the solver registry)
    return view->SetSolverOption(cmd.c_str(), value);
  }
  auto* light = vtkLight::SafeDownCast(object);
  if (cmd == "LightSize" && light)
  {
    if (!(value >= 0.0) || !std::isfinite(value))
    {
      vtkGenericWarningMacro("Shadow Size: expected a finite number >= 0, got " << value << "; light unchanged.");
      return false;
    }
    if (!light->GetInformation())
    {
      vtkNew<vtkInformation> info;
      light->SetInformation(info);
    }
    light->GetInformation()->Set(vtkPVSoftShadowView::LIGHT_SIZE(), value);
    light->Modified();
    return true;
  }
  if (cmd == "AngularDiameter" && light)
  {
    if (!(value >= 0.0 && value <= 30.0))
    {
      vtkGenericWarningMacro("Shadow Angular Diameter: expected degrees in [0, 30], got " << value
                                                                                         << "; light unchanged.");
      return false;
    }
    vtkSoftShadowLight::SetAngularDiameter(light, value);
    return true;
  }
  vtkGenericWarningMacro("vtkSISoftShadowProperty: command '" << cmd << "' does not apply to "
                                                             << (object ? object->GetClassName() : "null"));
  return false;
}

bool vtkSISoftShadowProperty::Push(vtkSMMessage* message, int offset)
{
  const ProxyState_Property* prop = &message->GetExtension(ProxyState::property, offset);
  this->SaveValueToCache(message, offset);
  const Variant& v = prop->value();
  double value = 0.0;
  if (v.integer_size() > 0)
  {
    value = v.integer(0);
  }
  else if (v.float64_size() > 0)
  {
    value = v.float64(0);
  }
  else
  {
    return true; // nothing to apply
  }
  Apply(this->GetVTKObject(), this->GetCommand(), value);
  return true;
}

bool vtkSISoftShadowProperty::ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(proxyhelper, element))
  {
    return false;
  }
  double value = 0.0;
  if (element->GetScalarAttribute("default_values", &value))
  {
    Apply(this->GetVTKObject(), this->GetCommand(), value);
  }
  return true;
}

void vtkSISoftShadowProperty::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
