#include "ssVisibilityLayers.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>

namespace ss
{
bool VisibilityLayers::Allocate(int width, int height, int layers, const GLLimits& limits, std::string& error)
{
  if (std::max(width, height) > limits.maxTextureSize || layers > limits.maxArrayTextureLayers ||
    !this->Array.EnsureScreen(width, height, layers))
  {
    error = "Could not allocate the visibility of " + std::to_string(layers) + " light(s) at " +
      std::to_string(width) + "x" + std::to_string(height) + " (this GL allows " +
      std::to_string(limits.maxTextureSize) + " pixels a side and " + std::to_string(limits.maxArrayTextureLayers) +
      " layers); no shadows this frame.";
    return false;
  }
  return true;
}

void VisibilityLayers::Attach(vtkOpenGLFramebufferObject* fbo, int layer) const
{
  this->Array.Attach(fbo, 0, layer);
  fbo->ActivateDrawBuffers(1);
}

void VisibilityLayers::Upload(int layer, std::vector<float>& V) const
{
  for (auto& v : V)
  {
    v = std::isnan(v) ? -1.0f : v; // background marker, as the GPU solvers write
  }
  glBindTexture(GL_TEXTURE_2D_ARRAY, this->Array.Handle);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage3D(
    GL_TEXTURE_2D_ARRAY, 0, 0, 0, layer, this->Array.Width, this->Array.Height, 1, GL_RED, GL_FLOAT, V.data());
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
}

bool VisibilityLayers::Read(
  vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, std::vector<float>& out) const
{
  out.resize(static_cast<std::size_t>(this->Array.Width) * this->Array.Height);
  return fbo && this->Array.Read(win, fbo, layer, out.data());
}

void VisibilityLayers::BindForShading(vtkOpenGLRenderWindow* win)
{
  this->Unit = this->Array.Bind(win);
}

void VisibilityLayers::UnbindAfterShading(vtkOpenGLRenderWindow* win)
{
  TextureArray::Unbind(win, this->Unit);
  this->Unit = -1;
}
}
