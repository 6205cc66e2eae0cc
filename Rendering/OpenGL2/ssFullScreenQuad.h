// Full-screen passes: a fragment shader drawn over the bound target with
// VTK's quad helper, and the shared GLSL pasted into such shaders.
#ifndef ssFullScreenQuad_h
#define ssFullScreenQuad_h

#include <memory>
#include <string>

class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkShaderProgram;
class vtkWindow;

namespace ss
{
/// The program of a full-screen pass with fragment shader `fs`, built on
/// first use into `quad` and made current; null when it does not compile.
vtkShaderProgram* ReadyQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkOpenGLRenderWindow* win, const char* fs);

/// `fs` with the shared shadow code pasted where it says //SS::Common
/// (ssShadowCommon.glsl) and //SS::QuadLit (ssQuadLit.glsl).
std::string WithCommon(const char* fs);

/// Releases `quad`'s GL resources and forgets it.
void ReleaseQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkWindow* win);
}

#endif
