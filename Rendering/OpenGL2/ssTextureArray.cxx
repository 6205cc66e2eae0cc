#include "ssTextureArray.h"

#include "ssFullScreenQuad.h"
#include "ssMinReduceFS.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtkTextureUnitManager.h"
#include "vtk_glew.h"

#include <algorithm>

namespace ss
{
void TextureArray::Release()
{
  if (this->Handle)
  {
    glDeleteTextures(1, &this->Handle);
    this->Handle = 0;
  }
  this->Size = this->Width = this->Height = this->Layers = this->Levels = this->Components = 0;
}

long long TextureArray::Bytes() const
{
  const long long level0 = static_cast<long long>(this->Width) * this->Height * this->Layers * this->Components * 4;
  // all mip levels: about 4/3 of level 0
  return this->Handle ? (this->Levels > 1 ? level0 * 4 / 3 : level0) : 0;
}

void TextureArray::Ensure(int size, int layers)
{
  int levels = 1;
  while ((size >> (levels - 1)) > 1)
  {
    ++levels;
  }
  this->Allocate(size, size, layers, levels, 2);
  this->Size = this->Handle ? size : 0;
}

int TextureArray::EnsureFitting(int size, int layers)
{
  while (this->FailedSize > 0 && size >= this->FailedSize && size > 64)
  {
    size /= 2;
  }
  this->Ensure(size, layers);
  while (!this->Handle && size > 64)
  {
    this->FailedSize = size;
    size /= 2;
    this->Ensure(size, layers);
  }
  return this->Handle ? size : 0;
}

bool TextureArray::EnsureScreen(int width, int height, int layers)
{
  this->Allocate(width, height, layers, 1, 1);
  return this->Handle != 0;
}

void TextureArray::Allocate(int width, int height, int layers, int levels, int comps)
{
  if (this->Handle && this->Width == width && this->Height == height && this->Layers == layers &&
    this->Levels == levels && this->Components == comps)
  {
    return;
  }
  this->Release();
  for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i)
  {
  }
  glGenTextures(1, &this->Handle);
  glBindTexture(GL_TEXTURE_2D_ARRAY, this->Handle);
  for (int l = 0; l < levels; ++l)
  {
    const GLenum internal = comps == 4 ? GL_RGBA32F : (comps == 2 ? GL_RG32F : GL_R32F);
    const GLenum format = comps == 4 ? GL_RGBA : (comps == 2 ? GL_RG : GL_RED);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, l, internal, std::max(1, width >> l), std::max(1, height >> l), layers, 0,
      format, GL_FLOAT, nullptr);
  }
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, levels - 1);
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
  if (glGetError() != GL_NO_ERROR)
  {
    glDeleteTextures(1, &this->Handle);
    this->Handle = 0;
    return;
  }
  this->Width = width;
  this->Height = height;
  this->Layers = layers;
  this->Levels = levels;
  this->Components = comps;
}

bool TextureArray::Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, float* out) const
{
  if (!this->Handle || layer < 0 || layer >= this->Layers)
  {
    return false;
  }
  win->MakeCurrent();
  vtkOpenGLState* ostate = win->GetState();
  ostate->PushFramebufferBindings();
  fbo->Bind();
  this->Attach(fbo, 0, layer);
  fbo->ActivateReadBuffer(0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, this->Width, this->Height,
    this->Components == 4 ? GL_RGBA : (this->Components == 2 ? GL_RG : GL_RED), GL_FLOAT, out);
  TextureArray::Detach();
  ostate->PopFramebufferBindings();
  return glGetError() == GL_NO_ERROR;
}

int TextureArray::Bind(vtkOpenGLRenderWindow* win) const
{
  const int unit = win->GetTextureUnitManager()->Allocate();
  if (unit >= 0)
  {
    win->GetState()->vtkglActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D_ARRAY, this->Handle);
  }
  return unit;
}

void TextureArray::Unbind(vtkOpenGLRenderWindow* win, int unit)
{
  if (unit >= 0)
  {
    win->GetState()->vtkglActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    win->GetTextureUnitManager()->Free(unit);
  }
}

void TextureArray::Attach(vtkOpenGLFramebufferObject* fbo, int level, int layer) const
{
  fbo->RemoveColorAttachments(1);
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, this->Handle, level, layer);
  fbo->ActivateDrawBuffers(1);
}

void TextureArray::Detach()
{
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
}

bool BuildDepthPyramid(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo,
  std::unique_ptr<vtkOpenGLQuadHelper>& quad, const TextureArray& array, int w, int h, int mode,
  const std::vector<std::array<int, 4>>* regions)
{
  vtkOpenGLState* ostate = win->GetState();
  vtkShaderProgram* prog = ReadyQuad(quad, win, ssMinReduceFS);
  if (!prog)
  {
    return false;
  }
  const int unit = array.Bind(win);
  prog->SetUniformi("src", unit);
  prog->SetUniformi("mode", mode);
  for (int level = 1; level < array.Levels; ++level)
  {
    const std::array<int, 4>* region =
      (regions && static_cast<std::size_t>(level) < regions->size()) ? &(*regions)[level] : nullptr;
    if (regions && (!region || (*region)[2] <= (*region)[0] || (*region)[3] <= (*region)[1]))
    {
      continue;
    }
    // sample only the level below the one written
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BASE_LEVEL, level - 1);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, level - 1);
    auto up = [](int v, int l) { return std::max(1, (v + (1 << l) - 1) >> l); };
    const int src[2] = { up(w, level - 1), up(h, level - 1) };
    const int dst[2] = { up(w, level), up(h, level) };
    prog->SetUniform2i("srcSize", src);
    prog->SetUniform2i("dstSize", dst);
    ostate->vtkglViewport(0, 0, dst[0], dst[1]);
    if (region)
    {
      const std::array<int, 4>& r = *region;
      ostate->vtkglScissor(r[0], r[1], r[2] - r[0], r[3] - r[1]);
    }
    else
    {
      ostate->vtkglScissor(0, 0, dst[0], dst[1]);
    }
    for (int layer = 0; layer < array.Layers; ++layer)
    {
      array.Attach(fbo, level, layer);
      prog->SetUniformi("layer", layer);
      quad->Render();
    }
  }
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, array.Levels - 1);
  TextureArray::Unbind(win, unit);
  return true;
}

void EnsureTexture2D(vtkOpenGLRenderWindow* win, vtkSmartPointer<vtkTextureObject>& t, int w, int h, int comps)
{
  if (!t)
  {
    t = vtkSmartPointer<vtkTextureObject>::New();
    t->SetContext(win);
    t->SetFormat(comps == 4 ? GL_RGBA : (comps == 2 ? GL_RG : GL_RED));
    t->SetInternalFormat(comps == 4 ? GL_RGBA32F : (comps == 2 ? GL_RG32F : GL_R32F));
    t->SetDataType(GL_FLOAT);
    t->SetMinificationFilter(vtkTextureObject::Nearest);
    t->SetMagnificationFilter(vtkTextureObject::Nearest);
    t->SetWrapS(vtkTextureObject::ClampToEdge);
    t->SetWrapT(vtkTextureObject::ClampToEdge);
    t->Allocate2D(w, h, comps, VTK_FLOAT);
  }
  else if (static_cast<int>(t->GetWidth()) != w || static_cast<int>(t->GetHeight()) != h)
  {
    t->Resize(w, h);
  }
}

bool ReadTexture(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, vtkTextureObject* tex,
  int layer, int w, int h, int comps, std::vector<float>& out)
{
  win->MakeCurrent();
  vtkOpenGLState* ostate = win->GetState();
  ostate->PushFramebufferBindings();
  fbo->Bind();
  // vtkOpenGLFramebufferObject does not re-attach the same texture: the old
  // attachment goes first
  fbo->RemoveColorAttachments(1);
  fbo->AddColorAttachment(0, tex, static_cast<unsigned int>(layer));
  fbo->ActivateReadBuffer(0);
  out.resize(static_cast<std::size_t>(w) * h * comps);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, comps == 4 ? GL_RGBA : GL_RED, GL_FLOAT, out.data());
  fbo->RemoveColorAttachments(1);
  ostate->PopFramebufferBindings();
  return glGetError() == GL_NO_ERROR;
}

long long TextureBytes(vtkTextureObject* t, int bytesPerTexel)
{
  if (t && t->GetHandle() != 0)
  {
    return static_cast<long long>(t->GetWidth()) * t->GetHeight() * std::max(1u, t->GetDepth()) * bytesPerTexel;
  }
  return 0;
}
}
