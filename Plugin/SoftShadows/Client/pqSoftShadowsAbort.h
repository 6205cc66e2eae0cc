/**
 * @class   pqSoftShadowsAbort
 * @brief   ParaView GUI: the progress bar's abort button stops a long soft-shadow render.
 *
 * ParaView 5.11's progress bar has an abort button whose signal
 * (pqProgressManager::abort) nothing in ParaView acts on. This auto-start
 * component enables the button while progress is shown and, when it is
 * pressed, calls vtkPVSoftShadowView::AbortRender on every Soft Shadow View of
 * the built-in session (the render window's AbortRender flag, which the pass
 * polls between lights, chunks and tiles). The render in progress then ends
 * without shadows and its plan says "aborted"; the next render solves again.
 * The progress bar's events reach the button during the render because
 * pqProgressManager lets it through while it processes progress.
 */
#ifndef pqSoftShadowsAbort_h
#define pqSoftShadowsAbort_h

#include <QObject>

class pqSoftShadowsAbort : public QObject
{
  Q_OBJECT
public:
  pqSoftShadowsAbort(QObject* parent = nullptr);
  ~pqSoftShadowsAbort() override;
  void onStartup();
  void onShutdown();

private Q_SLOTS:
  void abortRenders();
  void progressStarted();
  void progressEnded();
};

#endif
