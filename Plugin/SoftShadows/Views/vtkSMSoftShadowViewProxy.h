/**
 * @class   vtkSMSoftShadowViewProxy
 * @brief   Client side of the Soft Shadow View: its information after each render.
 *
 * ParaView updates a view's information properties only when asked; the
 * panel would show the plan and stats of some old frame. After every still
 * and interactive render this proxy pulls the view's Plan, Stats,
 * GearsBackendInUse and ShadowLightPosition, so the panel (and pvpython's GetPropertyValue) show the
 * frame just rendered. XML: `<SoftShadowViewProxy ...>` (the element name
 * picks the class).
 */
#ifndef vtkSMSoftShadowViewProxy_h
#define vtkSMSoftShadowViewProxy_h

#include "SoftShadowsParaViewViewsModule.h"
#include "vtkSMRenderViewProxy.h"

class SOFTSHADOWSPARAVIEWVIEWS_EXPORT vtkSMSoftShadowViewProxy : public vtkSMRenderViewProxy
{
public:
  static vtkSMSoftShadowViewProxy* New();
  vtkTypeMacro(vtkSMSoftShadowViewProxy, vtkSMRenderViewProxy);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSMSoftShadowViewProxy();
  ~vtkSMSoftShadowViewProxy() override;
  void PostRender(bool interactive) override;

private:
  vtkSMSoftShadowViewProxy(const vtkSMSoftShadowViewProxy&) = delete;
  void operator=(const vtkSMSoftShadowViewProxy&) = delete;
};

#endif
