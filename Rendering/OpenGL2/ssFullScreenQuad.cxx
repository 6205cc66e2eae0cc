#include "ssFullScreenQuad.h"

#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkShaderProgram.h"

#include "ssQuadLit.h"
#include "ssShadowCommon.h"

namespace ss
{
vtkShaderProgram* ReadyQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkOpenGLRenderWindow* win, const char* fs)
{
  if (!quad)
  {
    quad.reset(new vtkOpenGLQuadHelper(win, vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fs, ""));
  }
  else
  {
    win->GetShaderCache()->ReadyShaderProgram(quad->Program);
  }
  vtkShaderProgram* prog = quad->Program;
  return (prog && prog->GetCompiled()) ? prog : nullptr;
}

std::string WithCommon(const char* fs)
{
  std::string src(fs);
  vtkShaderProgram::Substitute(src, "//SS::Common", ssShadowCommon);
  vtkShaderProgram::Substitute(src, "//SS::QuadLit", ssQuadLit);
  return src;
}

void ReleaseQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkWindow* win)
{
  if (quad)
  {
    quad->ReleaseGraphicsResources(win);
    quad.reset();
  }
}
}
