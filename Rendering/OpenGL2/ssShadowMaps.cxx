#include "ssShadowMaps.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssFullScreenQuad.h"
#include "ssVisibilitySolver.h"

#include "vtkObject.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkSetGet.h"
#include "vtk_glew.h"

#include <algorithm>

namespace ss
{
ShadowMaps::ShadowMaps() = default;
ShadowMaps::~ShadowMaps() = default;

int ShadowMaps::ChooseSize(const std::vector<int>& asked, int fallback, int maxTextureSize, vtkObject* reporter)
{
  const bool agree =
    !asked.empty() && std::all_of(asked.begin(), asked.end(), [&](int s) { return s == asked.front(); });
  const int want = agree ? asked.front() : fallback;
  const int size = FitPowerOfTwo(want, maxTextureSize);
  this->SizeNote.clear();
  if (size < want)
  {
    this->SizeNote =
      "shadow map size " + std::to_string(want) + " capped at this GL's limit of " + std::to_string(size);
    if (this->WarnedSize != want)
    {
      vtkWarningWithObjectMacro(reporter, << this->SizeNote << ".");
      this->WarnedSize = want;
    }
  }
  return size;
}

bool ShadowMaps::Allocate(int size, int views, const GLLimits& limits, std::string& error)
{
  if (views > limits.maxArrayTextureLayers)
  {
    error = "The lights need " + std::to_string(views) + " shadow map views, more than this GL's " +
      std::to_string(limits.maxArrayTextureLayers) + " array texture layers; no shadows this frame.";
    return false;
  }
  // a size the context cannot allocate is halved until it can, with a note
  // and a warning (before, no shadows at all)
  const int asked = size;
  size = this->Array.EnsureFitting(size, std::max(views, 1));
  if (!size)
  {
    error = "Could not allocate " + std::to_string(std::max(views, 1)) +
      " shadow map(s) of 64x64 or more; no shadows this frame.";
    return false;
  }
  if (size < asked)
  {
    this->SizeNote = "shadow map size " + std::to_string(asked) + " does not fit this GL context's memory for " +
      std::to_string(std::max(views, 1)) + " view(s); using " + std::to_string(size);
    if (this->WarnedAlloc != asked)
    {
      vtkGenericWarningMacro(<< this->SizeNote << ".");
      this->WarnedAlloc = asked;
    }
  }
  return true;
}

void ShadowMaps::BeginDrawing(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo) const
{
  vtkOpenGLState* ostate = win->GetState();
  const int S = this->Array.Size;
  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->RemoveDepthAttachment();
  ostate->vtkglViewport(0, 0, S, S);
  ostate->vtkglScissor(0, 0, S, S);
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_BLEND);
  ostate->vtkglBlendEquation(GL_MIN);
  ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
  ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
}

void ShadowMaps::DrawViews(const SolverFrame& frame, const ShadowLight& light, vtkShaderProgram* program,
  vtkOpenGLVertexArrayObject* vao, const std::vector<TriangleRanges>* ranges) const
{
  const CasterSet& casters = *frame.Casters;
  const glm::dvec3 offset = casters.Origin - frame.State->Origin;
  int layer = light.FirstLayer;
  for (const auto& v : light.Views)
  {
    this->Array.Attach(frame.FBO, 0, layer);
    frame.Window->GetState()->vtkglClear(GL_COLOR_BUFFER_BIT);
    if (!casters.Triangles.empty())
    {
      const std::size_t vi = static_cast<std::size_t>(layer - light.FirstLayer);
      casters.Draw(program, vao, v, v.extent, offset, (ranges && vi < ranges->size()) ? &(*ranges)[vi] : nullptr);
    }
    ++layer;
  }
}

bool ShadowMaps::EndDrawing(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo)
{
  vtkOpenGLState* ostate = win->GetState();
  ostate->vtkglBlendEquation(GL_FUNC_ADD);
  ostate->vtkglDisable(GL_BLEND);
  const bool ok = BuildDepthPyramid(win, fbo, this->ReduceQuad, this->Array, this->Array.Size, this->Array.Size);
  TextureArray::Detach();
  ostate->PopFramebufferBindings();
  return ok;
}

void ShadowMaps::WriteLayer(vtkOpenGLRenderWindow* win, int layer, const std::vector<float>& depth) const
{
  const int S = this->Array.Size;
  if (S <= 0 || depth.size() != static_cast<std::size_t>(S) * S)
  {
    return;
  }
  // in bands of rows: the interleaved copy stays small (8 MB) at any size
  const int band = std::max(1, (1 << 20) / S);
  std::vector<float> rg(2 * static_cast<std::size_t>(S) * std::min(band, S));
  const int unit = this->Array.Bind(win);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  for (int y0 = 0; y0 < S; y0 += band)
  {
    const int rows = std::min(band, S - y0);
    const float* d = depth.data() + static_cast<std::size_t>(y0) * S;
    for (std::size_t k = 0; k < static_cast<std::size_t>(rows) * S; ++k)
    {
      rg[2 * k] = rg[2 * k + 1] = d[k];
    }
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, y0, layer, S, rows, 1, GL_RG, GL_FLOAT, rg.data());
  }
  TextureArray::Unbind(win, unit);
}

bool ShadowMaps::Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, float* out) const
{
  return fbo && this->Array.Read(win, fbo, layer, out);
}

int ShadowMaps::CountGraphicsResources() const
{
  return (this->Array.Handle != 0 ? 1 : 0) + (this->ReduceQuad ? 1 : 0);
}

void ShadowMaps::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Array.Release();
  this->Array.ForgetFailedSize(); // (another context may hold more)
  ReleaseQuad(this->ReduceQuad, w);
}
}
