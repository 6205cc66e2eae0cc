// What vtkSMSoftShadowDoubleRangeDomain and vtkSMSoftShadowIntRangeDomain
// share: they watch their property and put its last valid value back when a
// value outside the range (or not finite) is set, with one error naming the
// property, so that `view.LightSize = -1` is refused and the previous value
// kept (issue 24), in pvpython, the GUI and state files alike.
#ifndef vtkSMSoftShadowRangeGuard_h
#define vtkSMSoftShadowRangeGuard_h

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkSMProperty.h"
#include "vtkSMVectorProperty.h"
#include "vtkWeakPointer.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace ssparaview
{
/// T: double or int; Property: vtkSMDoubleVectorProperty or
/// vtkSMIntVectorProperty; Domain: the range domain that owns the guard.
template <typename T, typename Property, typename Domain>
class RangeGuard
{
public:
  /// nonZero: a vector of zeros is refused too (a direction).
  void Watch(vtkSMProperty* prop, Domain* domain, bool nonZero = false)
  {
    this->Prop = Property::SafeDownCast(prop);
    this->Owner = domain;
    this->NonZero = nonZero;
    if (!this->Prop)
    {
      return;
    }
    this->Callback->SetClientData(this);
    this->Callback->SetCallback(
      [](vtkObject*, unsigned long, void* self, void*) { static_cast<RangeGuard*>(self)->Check(); });
    this->Tag = this->Prop->AddObserver(vtkCommand::ModifiedEvent, this->Callback);
  }
  ~RangeGuard()
  {
    if (this->Prop)
    {
      this->Prop->RemoveObserver(this->Tag);
    }
  }

private:
  void Remember()
  {
    const unsigned int n = this->Prop->GetNumberOfElements();
    this->LastValid.assign(this->Prop->GetElements(), this->Prop->GetElements() + n);
  }

  void Check()
  {
    Domain* domain = this->Owner;
    if (this->Reverting)
    {
      return;
    }
    std::ostringstream bad;
    for (unsigned int i = 0; i < this->Prop->GetNumberOfElements(); ++i)
    {
      const T v = this->Prop->GetElement(i);
      int hasMin = 0, hasMax = 0;
      const T lo = domain->GetMinimum(0, hasMin), hi = domain->GetMaximum(0, hasMax);
      if (!std::isfinite(static_cast<double>(v)) || (hasMin && v < lo) || (hasMax && v > hi))
      {
        bad << v << " (expected " << (hasMin ? "at least " + ToString(lo) : std::string()) << (hasMin && hasMax ? " and " : "")
            << (hasMax ? "at most " + ToString(hi) : std::string()) << (hasMin || hasMax ? "" : "a finite number") << ")";
        break;
      }
    }
    if (bad.str().empty() && this->NonZero && this->Prop->GetNumberOfElements() > 0)
    {
      bool zero = true;
      for (unsigned int i = 0; i < this->Prop->GetNumberOfElements(); ++i)
      {
        zero = zero && this->Prop->GetElement(i) == T(0);
      }
      if (zero)
      {
        bad << "a vector of zeros (expected a direction)";
      }
    }
    if (bad.str().empty())
    {
      this->Remember();
      return;
    }
    if (this->LastValid.empty())
    {
      return; // the property is being set up (its elements before its defaults)
    }
    std::ostringstream kept;
    for (std::size_t i = 0; i < this->LastValid.size(); ++i)
    {
      kept << (i ? " " : "") << this->LastValid[i];
    }
    vtkErrorWithObjectMacro(this->Prop, << (this->Prop->GetXMLLabel() ? this->Prop->GetXMLLabel() : "property")
                                        << ": " << bad.str() << " refused; kept " << kept.str() << ".");
    this->Reverting = true;
    this->Prop->SetElements(this->LastValid.data(), static_cast<unsigned int>(this->LastValid.size()));
    this->Reverting = false;
  }

  static std::string ToString(T v)
  {
    std::ostringstream o;
    o << v;
    return o.str();
  }

  vtkWeakPointer<Property> Prop;
  Domain* Owner = nullptr;
  vtkNew<vtkCallbackCommand> Callback;
  unsigned long Tag = 0;
  std::vector<T> LastValid;
  bool Reverting = false;
  bool NonZero = false;
};
}

#endif
