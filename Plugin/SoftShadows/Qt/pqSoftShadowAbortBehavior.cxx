#include "pqSoftShadowAbortBehavior.h"

#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqProgressManager.h"
#include "pqServer.h"
#include "pqServerManagerModel.h"
#include "pqView.h"
#include "vtkCommand.h"
#include "vtkPVSoftShadowView.h"
#include "vtkRenderWindow.h"
#include "vtkSMProxy.h"

#include <QAbstractButton>
#include <QApplication>
#include <QEventLoop>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QWheelEvent>
#include <QWidget>

namespace
{
// The user's input: held back from everything but the abort button while a
// render pumps events (the pump runs inside vtkRenderWindow::Render).
bool IsUserInput(QEvent::Type type)
{
  switch (type)
  {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick:
    case QEvent::MouseMove:
    case QEvent::Wheel:
    case QEvent::KeyPress:
    case QEvent::KeyRelease:
    case QEvent::ShortcutOverride:
    case QEvent::Shortcut:
    case QEvent::ContextMenu:
    case QEvent::TouchBegin:
    case QEvent::TouchUpdate:
    case QEvent::TouchEnd:
    case QEvent::TouchCancel:
    case QEvent::TabletPress:
    case QEvent::TabletMove:
    case QEvent::TabletRelease:
    case QEvent::NativeGesture:
    case QEvent::Gesture:
    case QEvent::DragEnter:
    case QEvent::DragMove:
    case QEvent::DragLeave:
    case QEvent::Drop:
    case QEvent::InputMethod:
    case QEvent::Enter:
    case QEvent::Leave:
    case QEvent::Close:
      return true;
    default:
      return false;
  }
}

// A GL view's paint would make its context current and, through the
// interactor, ask its proxy for a render: held back too (the view repaints
// when its render window's frame ends).
bool IsGLPaint(QObject* object, QEvent::Type type)
{
  if (type != QEvent::Paint && type != QEvent::UpdateRequest && type != QEvent::Expose &&
    type != QEvent::UpdateLater)
  {
    return false;
  }
  return object->inherits("QOpenGLWindow") || object->inherits("QOpenGLWidget");
}
}

//------------------------------------------------------------------------------
pqSoftShadowAbortBehavior::pqSoftShadowAbortBehavior(QObject* parent)
  : QObject(parent)
{
  this->Idle.setSingleShot(true);
  this->PlaybackIdle = qEnvironmentVariableIsSet("SOFTSHADOWS_ABORT_PLAYBACK");
}

pqSoftShadowAbortBehavior::~pqSoftShadowAbortBehavior()
{
  this->shutdown();
  for (auto& held : this->Held)
  {
    delete held.second;
  }
}

void pqSoftShadowAbortBehavior::startup()
{
  pqApplicationCore* core = pqApplicationCore::instance();
  if (!core)
  {
    return;
  }
  pqServerManagerModel* model = core->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::viewAdded, this, &pqSoftShadowAbortBehavior::onViewAdded);
  QObject::connect(model, &pqServerManagerModel::preViewRemoved, this, &pqSoftShadowAbortBehavior::onViewRemoved);
  for (pqView* view : model->findItems<pqView*>())
  {
    this->Watch(view);
  }
  if (pqProgressManager* progress = core->getProgressManager())
  {
    QObject::connect(progress, &pqProgressManager::abort, this, &pqSoftShadowAbortBehavior::onAbort);
  }
}

void pqSoftShadowAbortBehavior::shutdown()
{
  while (!this->Views.empty())
  {
    this->Unwatch(this->Views.begin()->first);
  }
  if (pqApplicationCore* core = pqApplicationCore::instance())
  {
    QObject::disconnect(core->getServerManagerModel(), nullptr, this, nullptr);
    if (core->getProgressManager())
    {
      QObject::disconnect(core->getProgressManager(), nullptr, this, nullptr);
    }
  }
}

void pqSoftShadowAbortBehavior::onViewAdded(pqView* view)
{
  this->Watch(view);
}

void pqSoftShadowAbortBehavior::onViewRemoved(pqView* view)
{
  this->Unwatch(view);
}

void pqSoftShadowAbortBehavior::Watch(pqView* view)
{
  // builtin session only: the view object that renders lives in this process
  if (!view || this->Views.count(view) || !view->getServer() || view->getServer()->isRemote() ||
    !view->getProxy())
  {
    return;
  }
  auto* ssView = vtkPVSoftShadowView::SafeDownCast(view->getProxy()->GetClientSideObject());
  vtkRenderWindow* window = ssView ? ssView->GetRenderWindow() : nullptr;
  if (!window)
  {
    return;
  }
  Watched w;
  w.Window = window;
  w.View = ssView;
  w.CheckTag = window->AddObserver(vtkCommand::AbortCheckEvent, this, &pqSoftShadowAbortBehavior::OnAbortCheck);
  w.EndTag = window->AddObserver(vtkCommand::EndEvent, this, &pqSoftShadowAbortBehavior::OnRenderEnd);
  this->Views[view] = w;
}

void pqSoftShadowAbortBehavior::Unwatch(pqView* view)
{
  auto it = this->Views.find(view);
  if (it == this->Views.end())
  {
    return;
  }
  if (vtkRenderWindow* window = it->second.Window)
  {
    window->RemoveObserver(it->second.CheckTag);
    window->RemoveObserver(it->second.EndTag);
  }
  if (this->Rendering == it->second.View)
  {
    this->SetAbortEnabled(false);
    this->Rendering = nullptr;
    this->ReleaseHeld();
  }
  this->Views.erase(it);
}

//------------------------------------------------------------------------------
void pqSoftShadowAbortBehavior::OnAbortCheck(vtkObject* caller, unsigned long, void*)
{
  // another watched window's check while pumping (it cannot start a render:
  // input is held back and pqView defers renders while progress is pending)
  if (this->Pumping)
  {
    return;
  }
  vtkPVSoftShadowView* view = nullptr;
  for (const auto& entry : this->Views)
  {
    if (entry.second.Window.GetPointer() == caller)
    {
      view = entry.second.View;
    }
  }
  if (!view)
  {
    return;
  }
  if (this->Rendering != view)
  {
    this->Rendering = view;
    this->SetAbortEnabled(true);
  }
  // the pump paints: Qt may make another context current and bind a
  // QOpenGLWidget's framebuffer in the view's
  const bool saved = view->SaveGLContext();
  this->Pump();
  view->RestoreGLContext(saved);
}

void pqSoftShadowAbortBehavior::OnRenderEnd(vtkObject* caller, unsigned long, void*)
{
  for (const auto& entry : this->Views)
  {
    if (entry.second.Window.GetPointer() == caller && entry.second.View == this->Rendering)
    {
      if (this->AbortRequested)
      {
        // The renders asked for while this one ran (pqView::tryRender defers
        // them while a progress is pending) would solve the same scene again
        // at once: the user has just stopped that. The view keeps the
        // aborted frame (no shadows) until the next change renders it.
        entry.first->cancelPendingRenders();
        this->AbortRequested = false;
      }
      this->Rendering = nullptr;
      this->SetAbortEnabled(false);
      this->ReleaseHeld();
    }
  }
}

void pqSoftShadowAbortBehavior::ReleaseHeld()
{
  for (auto& held : this->Held)
  {
    if (held.first)
    {
      QCoreApplication::postEvent(held.first, held.second);
    }
    else
    {
      delete held.second;
    }
  }
  this->Held.clear();
}

void pqSoftShadowAbortBehavior::onAbort()
{
  if (this->Rendering)
  {
    this->AbortRequested = true;
    this->Rendering->AbortRender();
  }
}

void pqSoftShadowAbortBehavior::SetAbortEnabled(bool on)
{
  pqApplicationCore* core = pqApplicationCore::instance();
  pqProgressManager* progress = core ? core->getProgressManager() : nullptr;
  if (progress && this->AbortEnabled != on)
  {
    this->AbortEnabled = on;
    progress->setEnableAbort(on);
  }
}

QAbstractButton* pqSoftShadowAbortBehavior::AbortButton()
{
  // pqStatusBar's pqProgressWidget names its button "AbortButton"
  if (!this->Button)
  {
    if (QWidget* main = pqCoreUtilities::mainWidget())
    {
      this->Button = main->findChild<QAbstractButton*>("AbortButton");
    }
  }
  return this->Button;
}

//------------------------------------------------------------------------------
void pqSoftShadowAbortBehavior::Pump()
{
  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  // pqProgressManager's own filter blocks mouse presses to everything not on
  // its list, and with Qt 5 a press first goes to the QWindow (not listed):
  // the abort button could not be pressed. This filter takes its place.
  const bool unblocked = progress ? progress->unblockEvents(true) : false;
  this->Pumping = true;
  qApp->installEventFilter(this);
  if (this->PlaybackIdle)
  {
    // For ParaView's XML test player only (SOFTSHADOWS_ABORT_PLAYBACK set):
    // a short real event loop, so that the dispatcher goes idle once
    // (QAbstractEventDispatcher::aboutToBlock, for up to 1 ms). The player
    // plays its next event at that point, so a recorded click on the abort
    // button is played during the render. It is opt-in because the player
    // bypasses this filter: any event recorded after a long render would be
    // played during it too.
    QEventLoop loop;
    QObject::connect(&this->Idle, &QTimer::timeout, &loop, &QEventLoop::quit);
    this->Idle.start(1);
    loop.exec();
    QObject::disconnect(&this->Idle, &QTimer::timeout, &loop, &QEventLoop::quit);
  }
  else
  {
    // the window system's queued input (the user's click), timers, posted
    // events, paints; no waiting
    QCoreApplication::processEvents(QEventLoop::AllEvents);
  }
  qApp->removeEventFilter(this);
  this->Pumping = false;
  if (progress)
  {
    progress->unblockEvents(unblocked);
  }
}

bool pqSoftShadowAbortBehavior::AllowedInput(QObject* object, QEvent* event)
{
  QAbstractButton* button = this->AbortButton();
  if (!button)
  {
    return false;
  }
  if (object == button)
  {
    return true;
  }
  // the first stage of a mouse event: the top-level QWindow, which passes it
  // on to the widget under the pointer (or to the pressed button)
  if (object->isWindowType())
  {
    if (auto* mouse = dynamic_cast<QMouseEvent*>(event))
    {
      return QApplication::widgetAt(mouse->globalPos()) == button || button->isDown();
    }
  }
  return false;
}

bool pqSoftShadowAbortBehavior::eventFilter(QObject* object, QEvent* event)
{
  if (this->Pumping && object)
  {
    const QEvent::Type type = event->type();
    if (IsUserInput(type))
    {
      if (this->AllowedInput(object, event))
      {
        return this->QObject::eventFilter(object, event);
      }
      // Held back. The window-level mouse, key and wheel events are posted
      // again when the render ends, so the user's input is delivered after
      // the render as without the pump (a drag begun before a render ends).
      // Shortcuts, drag and drop, closing a window and the like are dropped.
      if (object->isWindowType())
      {
        QEvent* copy = nullptr;
        if (auto* mouse = dynamic_cast<QMouseEvent*>(event))
        {
          copy = new QMouseEvent(*mouse);
        }
        else if (auto* key = dynamic_cast<QKeyEvent*>(event))
        {
          copy = new QKeyEvent(*key);
        }
        else if (auto* wheel = dynamic_cast<QWheelEvent*>(event))
        {
          copy = new QWheelEvent(*wheel);
        }
        if (copy)
        {
          this->Held.emplace_back(QPointer<QObject>(object), copy);
        }
      }
      return true;
    }
    if (IsGLPaint(object, type))
    {
      return true;
    }
  }
  return this->QObject::eventFilter(object, event);
}
