#include "ssReceiverCapture.h"

#include "vtkOpenGLRenderWindow.h"
#include "vtkShaderProgram.h"
#include "vtk_glew.h"

#include <limits>

namespace ss
{
namespace
{
// An image unit nothing else binds while shading (VTK's mappers use none;
// GL 4.2 guarantees 8).
constexpr int kCaptureImageUnit = 7;
}

std::string ReceiverCapture::Code(bool enabled)
{
  if (!enabled)
  {
    return "void ssCaptureFragment(int layer, float V, vec3 p, vec3 n) {}\n";
  }
  return "layout(rgba32f) uniform image2DArray ssCaptureImage;\n"
         "uniform int ssCaptureLayer; // the visibility layer captured\n"
         "void ssCaptureFragment(int layer, float V, vec3 p, vec3 n)\n"
         "{\n"
         "  if (layer == ssCaptureLayer && layer >= 0)\n"
         "  {\n"
         "    ivec2 pix = ivec2(gl_FragCoord.xy - ssViewportOrigin);\n"
         "    imageStore(ssCaptureImage, ivec3(pix, 0), vec4(p, V));\n"
         "    imageStore(ssCaptureImage, ivec3(pix, 1), vec4(n, 1.0));\n"
         "  }\n"
         "}\n";
}

bool ReceiverCapture::Begin(vtkOpenGLRenderWindow* win, int width, int height, int layer, std::string& error)
{
  this->Layer = -1;
  this->Captured = false;
  win->MakeCurrent();
  GLint units = 0;
  glGetIntegerv(GL_MAX_IMAGE_UNITS, &units);
  if (!glBindImageTexture || !glClearTexImage || units <= kCaptureImageUnit)
  {
    error = "CaptureTranslucentReceivers needs image load/store (GL 4.2) and glClearTexImage (GL 4.4).";
    return false;
  }
  this->Image.Allocate(width, height, 2, 1, 4);
  if (!this->Image.Handle)
  {
    error = "CaptureTranslucentReceivers: GL refused its " + std::to_string(width) + " x " +
      std::to_string(height) + " image.";
    return false;
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float clear[4] = { nan, nan, nan, nan };
  glClearTexImage(this->Image.Handle, 0, GL_RGBA, GL_FLOAT, clear);
  glBindImageTexture(kCaptureImageUnit, this->Image.Handle, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  this->Layer = layer;
  return true;
}

void ReceiverCapture::SetUniforms(vtkShaderProgram* program) const
{
  if (program->IsUniformUsed("ssCaptureLayer"))
  {
    program->SetUniformi("ssCaptureImage", kCaptureImageUnit);
    program->SetUniformi("ssCaptureLayer", this->Layer);
  }
}

void ReceiverCapture::End()
{
  if (this->Layer < 0)
  {
    return;
  }
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  glBindImageTexture(kCaptureImageUnit, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  this->Captured = true;
}

bool ReceiverCapture::Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, std::vector<float>& V,
  std::vector<float>& positions, std::vector<float>& normals) const
{
  if (!this->Captured || !this->Image.Handle)
  {
    return false;
  }
  const std::size_t n = static_cast<std::size_t>(this->Image.Width) * this->Image.Height;
  std::vector<float> pv(4 * n), nw(4 * n);
  if (!this->Image.Read(win, fbo, 0, pv.data()) || !this->Image.Read(win, fbo, 1, nw.data()))
  {
    return false;
  }
  V.resize(n);
  positions.resize(3 * n);
  normals.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    V[i] = pv[4 * i + 3];
    for (int c = 0; c < 3; ++c)
    {
      positions[3 * i + c] = pv[4 * i + c];
      normals[3 * i + c] = nw[4 * i + c];
    }
  }
  return true;
}
}
