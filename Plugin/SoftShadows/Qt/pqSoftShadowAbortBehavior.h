/**
 * @class   pqSoftShadowAbortBehavior
 * @brief   The progress bar's abort button stops a long Soft Shadow View render (ParaView GUI, builtin session).
 *
 * ParaView 5.11's GUI processes no events while a view renders
 * (pqProgressManager::setProgress has its processEvents call commented out,
 * "disabled for the 3.12 release"), nothing enables the status bar's abort
 * button (pqProgressManager::setEnableAbort has no caller) and nothing acts
 * on pqProgressManager::abort(). This auto-start component of the plugin
 * fills those three gaps for the Soft Shadow Views of the builtin session
 * (the GUI without a separate server):
 *
 * - it observes each view's render window AbortCheckEvent. The pass polls
 *   vtkRenderWindow::CheckAbortStatus between lights and chunks of its solvers
 *   (ss::FrameProgress::Report); VTK fires AbortCheckEvent from there at most
 *   5 times a second, and with InAbortCheck set, so the window refuses a
 *   nested Render() meanwhile;
 * - on the first check of a render it enables the abort button
 *   (pqProgressManager::setEnableAbort(true)), and disables it again when the
 *   window's render ends;
 * - at every check it processes Qt's pending events (Pump), with an
 *   application event filter that lets through the user's input only to the
 *   abort button (mouse, keys, wheel, shortcuts, drag and drop, closing
 *   windows are all held back, so nothing can start another render or change
 *   the pipeline mid-frame; the mouse, key and wheel events are posted again
 *   when the render ends, as they would have been delivered without the
 *   pump). GL views' paints are held back too. Timers and posted events do run: ParaView's own
 *   view renders are deferred while a progress is pending (pqView::tryRender),
 *   and this window refuses nested renders during its abort check.
 *   After the pump the view's GL context is made current again.
 *   With SOFTSHADOWS_ABORT_PLAYBACK set (the GUI test), the pump is a short
 *   real event loop instead, so that ParaView's test player, which plays its
 *   events when the event loop goes idle, can play a click during a render.
 * - pqProgressManager::abort() (the button's signal) calls
 *   vtkPVSoftShadowView::AbortRender(), i.e. vtkRenderWindow::SetAbortRender(1);
 *   the pass stops at its next check, the frame is shown without shadows and
 *   the Plan says "aborted". The view's renders requested meanwhile are
 *   cancelled (pqView::cancelPendingRenders): they would start the same
 *   long solve again; the next change renders the view as usual.
 *
 * Remote sessions (pvserver) are left alone: the render runs in the server
 * process, which reads no message from the client until the render is over,
 * and pumping the client's events while its socket is mid-exchange is what
 * made ParaView turn processEvents off (tag mismatches). See paraview.md.
 */
#ifndef pqSoftShadowAbortBehavior_h
#define pqSoftShadowAbortBehavior_h

#include <QObject>
#include <QPointer>
#include <QTimer>

#include "vtkPVSoftShadowView.h" // for vtkWeakPointer<vtkPVSoftShadowView>
#include "vtkRenderWindow.h"     // for vtkWeakPointer<vtkRenderWindow>
#include "vtkWeakPointer.h"

#include <map>
#include <utility>
#include <vector>

class pqView;
class QAbstractButton;
class QEvent;
class vtkObject;

class pqSoftShadowAbortBehavior : public QObject
{
  Q_OBJECT
public:
  pqSoftShadowAbortBehavior(QObject* parent = nullptr);
  ~pqSoftShadowAbortBehavior() override;

  /** pqAutoStartInterface: called when the plugin is loaded / unloaded. */
  void startup();
  void shutdown();

protected:
  bool eventFilter(QObject* object, QEvent* event) override;

private Q_SLOTS:
  void onViewAdded(pqView* view);
  void onViewRemoved(pqView* view);
  void onAbort();

private:
  struct Watched
  {
    vtkWeakPointer<vtkRenderWindow> Window; ///< weak: ParaView may delete the view first at exit
    vtkWeakPointer<vtkPVSoftShadowView> View;
    unsigned long CheckTag = 0;
    unsigned long EndTag = 0;
  };
  void Watch(pqView* view);
  void Unwatch(pqView* view);
  void OnAbortCheck(vtkObject* caller, unsigned long, void*);
  void OnRenderEnd(vtkObject* caller, unsigned long, void*);
  void Pump();
  void SetAbortEnabled(bool on);
  void ReleaseHeld();
  QAbstractButton* AbortButton();
  bool AllowedInput(QObject* object, QEvent* event);

  std::map<pqView*, Watched> Views;
  vtkWeakPointer<vtkPVSoftShadowView> Rendering; ///< the view whose render the abort button stops
  bool Pumping = false;
  bool AbortEnabled = false;
  bool AbortRequested = false; ///< the abort button was pressed during this render
  QPointer<QAbstractButton> Button;
  QTimer Idle;               ///< ends the pump's short event loop (PlaybackIdle)
  bool PlaybackIdle = false; ///< SOFTSHADOWS_ABORT_PLAYBACK: let ParaView's test player play during renders
  std::vector<std::pair<QPointer<QObject>, QEvent*>> Held; ///< input held back during the render
};

#endif
