#include "pqSoftShadowsAbort.h"

#include "pqApplicationCore.h"
#include "pqProgressManager.h"
#include "pqServerManagerModel.h"
#include "pqView.h"
#include "vtkPVSoftShadowView.h"
#include "vtkSMProxy.h"

pqSoftShadowsAbort::pqSoftShadowsAbort(QObject* parent)
  : QObject(parent)
{
}

pqSoftShadowsAbort::~pqSoftShadowsAbort() = default;

void pqSoftShadowsAbort::onStartup()
{
  pqApplicationCore* core = pqApplicationCore::instance();
  pqProgressManager* progress = core ? core->getProgressManager() : nullptr;
  if (!progress)
  {
    return;
  }
  QObject::connect(progress, &pqProgressManager::abort, this, &pqSoftShadowsAbort::abortRenders);
  QObject::connect(progress, &pqProgressManager::progressStartEvent, this, &pqSoftShadowsAbort::progressStarted);
  QObject::connect(progress, &pqProgressManager::progressEndEvent, this, &pqSoftShadowsAbort::progressEnded);
}

void pqSoftShadowsAbort::onShutdown()
{
  if (pqApplicationCore* core = pqApplicationCore::instance())
  {
    if (pqProgressManager* progress = core->getProgressManager())
    {
      QObject::disconnect(progress, nullptr, this, nullptr);
    }
  }
}

void pqSoftShadowsAbort::progressStarted()
{
  pqApplicationCore::instance()->getProgressManager()->setEnableAbort(true);
}

void pqSoftShadowsAbort::progressEnded()
{
  pqApplicationCore::instance()->getProgressManager()->setEnableAbort(false);
}

void pqSoftShadowsAbort::abortRenders()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqView* view : model->findItems<pqView*>())
  {
    // the client-side object is the view itself in the built-in session
    if (auto* shadows = vtkPVSoftShadowView::SafeDownCast(view->getProxy()->GetClientSideObject()))
    {
      shadows->AbortRender();
    }
  }
}
