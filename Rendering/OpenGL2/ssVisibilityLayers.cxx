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

bool VisibilityLayers::AllocateColor(int layers, const GLLimits& limits, std::string& error)
{
  if (layers <= 0)
  {
    this->Color.Release();
    return true;
  }
  if (layers > limits.maxArrayTextureLayers)
  {
    error = "Could not allocate the RGB visibility of " + std::to_string(layers) + " light(s).";
    return false;
  }
  this->Color.Allocate(this->Array.Width, this->Array.Height, layers, 1, 4);
  if (!this->Color.Handle)
  {
    error = "Could not allocate the RGB visibility of " + std::to_string(layers) + " light(s) at " +
      std::to_string(this->Array.Width) + "x" + std::to_string(this->Array.Height) + ".";
    return false;
  }
  return true;
}

void VisibilityLayers::AttachWithColor(vtkOpenGLFramebufferObject* fbo, int layer, int colorLayer) const
{
  this->Array.Attach(fbo, 0, layer);
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, this->Color.Handle, 0, colorLayer);
  fbo->ActivateDrawBuffers(2);
}

bool VisibilityLayers::ReadColor(
  vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int colorLayer, std::vector<float>& out) const
{
  std::vector<float> rgba(static_cast<std::size_t>(this->Color.Width) * this->Color.Height * 4);
  if (!fbo || !this->Color.Handle || !this->Color.Read(win, fbo, colorLayer, rgba.data()))
  {
    return false;
  }
  out.resize(rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < rgba.size() / 4; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      out[3 * i + c] = rgba[4 * i + 3] < 0.0f ? std::nanf("") : rgba[4 * i + c]; // alpha -1: background
    }
  }
  return true;
}

void VisibilityLayers::BindForShading(vtkOpenGLRenderWindow* win)
{
  this->Unit = this->Array.Bind(win);
  this->ColorUnit = this->Color.Handle ? this->Color.Bind(win) : -1;
}

void VisibilityLayers::UnbindAfterShading(vtkOpenGLRenderWindow* win)
{
  TextureArray::Unbind(win, this->ColorUnit);
  TextureArray::Unbind(win, this->Unit);
  this->Unit = -1;
  this->ColorUnit = -1;
}
}
