#include "ssASMTextures.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkTextureUnitManager.h"
#include "vtk_glew.h"

#include <algorithm>

namespace ss
{
namespace
{
void Delete(unsigned int& t)
{
  if (t)
  {
    glDeleteTextures(1, &t);
    t = 0;
  }
}

void NearestClamp(GLenum target)
{
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// A 2-D texture of one level; 0 when GL refuses it.
unsigned int Make2D(GLint internal, int w, int h, GLenum format, GLenum type)
{
  while (glGetError() != GL_NO_ERROR)
  {
  }
  unsigned int t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, internal, w, h, 0, format, type, nullptr);
  NearestClamp(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
  if (glGetError() != GL_NO_ERROR)
  {
    Delete(t);
  }
  return t;
}
}

bool ASMTextures::EnsureAtlas(const ASMAtlasLayout& layout, int pageSize, int summarySize, std::string& error)
{
  if (this->Atlas && this->Summary && this->PageSize == pageSize && this->SummarySize == summarySize &&
    this->Layout.cols == layout.cols && this->Layout.rows == layout.rows && this->Layout.layers == layout.layers)
  {
    this->Layout = layout;
    return true;
  }
  Delete(this->Atlas);
  Delete(this->Summary);
  this->Layout = layout;
  this->PageSize = pageSize;
  this->SummarySize = summarySize;
  while (glGetError() != GL_NO_ERROR)
  {
  }
  auto make = [&](GLint internal, int side, GLenum format, GLenum type) {
    unsigned int t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D_ARRAY, t);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, internal, layout.cols * side, layout.rows * side, layout.layers, 0, format,
      type, nullptr);
    NearestClamp(GL_TEXTURE_2D_ARRAY);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    return t;
  };
  this->Atlas = make(GL_RG32UI, pageSize, GL_RG_INTEGER, GL_UNSIGNED_INT);
  this->Summary = make(GL_R32F, summarySize, GL_RED, GL_FLOAT);
  if (glGetError() != GL_NO_ERROR)
  {
    Delete(this->Atlas);
    Delete(this->Summary);
    error = "Could not allocate the ASM atlas of " + std::to_string(layout.pages) + " pages (" +
      std::to_string(layout.Width(pageSize)) + "x" + std::to_string(layout.Height(pageSize)) + "x" +
      std::to_string(layout.layers) + " RG32UI and its R32F summary).";
    return false;
  }
  return true;
}

bool ASMTextures::EnsureScratch(int pageSize, int summarySize)
{
  if (this->Scratch && this->ScratchSize == pageSize && this->SummaryScratchSize == summarySize)
  {
    return true;
  }
  Delete(this->Scratch);
  Delete(this->ScratchDepth);
  Delete(this->SummaryScratch);
  this->Scratch = Make2D(GL_RG32UI, pageSize, pageSize, GL_RG_INTEGER, GL_UNSIGNED_INT);
  this->ScratchDepth = Make2D(GL_DEPTH_COMPONENT32F, pageSize, pageSize, GL_DEPTH_COMPONENT, GL_FLOAT);
  this->SummaryScratch = Make2D(GL_R32F, summarySize, summarySize, GL_RED, GL_FLOAT);
  const bool ok = this->Scratch && this->ScratchDepth && this->SummaryScratch;
  this->ScratchSize = ok ? pageSize : 0;
  this->SummaryScratchSize = ok ? summarySize : 0;
  return ok;
}

bool ASMTextures::EnsureScreen(int width, int height)
{
  if (this->Ids && this->Width == width && this->Height == height)
  {
    return true;
  }
  Delete(this->Ids);
  Delete(this->IdDepth);
  Delete(this->Edges);
  this->Ids = Make2D(GL_RG32UI, width, height, GL_RG_INTEGER, GL_UNSIGNED_INT);
  this->IdDepth = Make2D(GL_DEPTH_COMPONENT32F, width, height, GL_DEPTH_COMPONENT, GL_FLOAT);
  this->Edges = Make2D(GL_R8, width, height, GL_RED, GL_UNSIGNED_BYTE);
  const bool ok = this->Ids && this->IdDepth && this->Edges;
  this->Width = ok ? width : 0;
  this->Height = ok ? height : 0;
  return ok;
}

void ASMTextures::UploadNodeTable(const ASMTree& tree, int maxTextureSize)
{
  if (this->Nodes && this->UploadedVersion == tree.Version())
  {
    return;
  }
  const int C = tree.Settings().cells;
  this->NodeWidth = 1 + (C * C + 3) / 4;
  this->NodesPerRow = std::max(1, std::min(maxTextureSize, 4096) / this->NodeWidth);
  const int slots = std::max(1, tree.NodeSlots());
  const int rows = (slots + this->NodesPerRow - 1) / this->NodesPerRow;
  const int width = this->NodesPerRow * this->NodeWidth;
  std::vector<int> table(static_cast<std::size_t>(width) * rows * 4, -1);
  for (int id = 0; id < tree.NodeSlots(); ++id)
  {
    if (!tree.Alive(id))
    {
      continue;
    }
    const ASMNode& n = tree.Node(id);
    int* t = &table[(static_cast<std::size_t>(id / this->NodesPerRow) * width + (id % this->NodesPerRow) * this->NodeWidth) * 4];
    const glm::ivec3 o = this->Layout.PageOrigin(n.page, this->PageSize);
    t[0] = o.x;
    t[1] = o.y;
    t[2] = o.z;
    t[3] = n.resolution;
    for (int c = 0; c < C * C; ++c)
    {
      const int k = n.children[static_cast<std::size_t>(c)];
      t[4 + c] = (k >= 0 && tree.Node(k).resolution > 0) ? k : -1;
    }
  }
  if (!this->Nodes || rows > this->NodeRows || width != this->NodeTableWidth)
  {
    Delete(this->Nodes);
    this->NodeRows = rows;
    this->NodeTableWidth = width;
    this->Nodes = Make2D(GL_RGBA32I, width, rows, GL_RGBA_INTEGER, GL_INT);
  }
  if (this->Nodes)
  {
    glBindTexture(GL_TEXTURE_2D, this->Nodes);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, rows, GL_RGBA_INTEGER, GL_INT, table.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    this->UploadedVersion = tree.Version();
  }
}

void ASMTextures::Begin(vtkOpenGLRenderWindow* win, unsigned int color, int layer, unsigned int depth)
{
  if (!this->FBO)
  {
    this->FBO = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
    this->FBO->SetContext(win);
  }
  win->GetState()->PushFramebufferBindings();
  this->FBO->Bind();
  if (layer >= 0)
  {
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, color, 0, layer);
  }
  else
  {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
  }
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
  this->FBO->ActivateDrawBuffers(1);
}

void ASMTextures::BeginCleared(vtkOpenGLRenderWindow* win, unsigned int color, unsigned int depth, int w, int h,
  const unsigned int clear[4])
{
  this->Begin(win, color, -1, depth);
  win->GetState()->vtkglViewport(0, 0, w, h);
  win->GetState()->vtkglScissor(0, 0, w, h);
  const GLuint c[4] = { clear[0], clear[1], clear[2], clear[3] };
  glClearBufferuiv(GL_COLOR, 0, c);
  const GLfloat one = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &one);
}

void ASMTextures::End(vtkOpenGLRenderWindow* win)
{
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
  win->GetState()->PopFramebufferBindings();
}

void ASMTextures::CopyScratchToPage(int page, int res, bool summary)
{
  const glm::ivec3 o = this->Layout.PageOrigin(page, summary ? this->SummarySize : this->PageSize);
  this->FBO->ActivateReadBuffer(0);
  glBindTexture(GL_TEXTURE_2D_ARRAY, summary ? this->Summary : this->Atlas);
  glCopyTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, o.x, o.y, o.z, 0, 0, res, res);
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
}

void ASMTextures::ReadEdges(std::vector<std::uint8_t>& out)
{
  out.resize(static_cast<std::size_t>(this->Width) * this->Height);
  this->FBO->ActivateReadBuffer(1);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, this->Width, this->Height, GL_RED, GL_UNSIGNED_BYTE, out.data());
}

int ASMTextures::Bind(vtkOpenGLRenderWindow* win, unsigned int target, unsigned int handle)
{
  const int unit = win->GetTextureUnitManager()->Allocate();
  if (unit >= 0)
  {
    win->GetState()->vtkglActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(target, handle);
  }
  return unit;
}

void ASMTextures::Unbind(vtkOpenGLRenderWindow* win, unsigned int target, int unit)
{
  if (unit >= 0)
  {
    win->GetState()->vtkglActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(target, 0);
    win->GetTextureUnitManager()->Free(unit);
  }
}

long long ASMTextures::AtlasBytes() const
{
  return this->Atlas ? static_cast<long long>(this->Layout.pages) *
      (static_cast<long long>(this->PageSize) * this->PageSize * 8 +
        static_cast<long long>(this->SummarySize) * this->SummarySize * 4)
                     : 0;
}

long long ASMTextures::Bytes() const
{
  long long b = this->AtlasBytes();
  b += this->Scratch ? static_cast<long long>(this->ScratchSize) * this->ScratchSize * (8 + 4) +
      static_cast<long long>(this->SummaryScratchSize) * this->SummaryScratchSize * 4
                     : 0;
  b += this->Ids ? static_cast<long long>(this->Width) * this->Height * (8 + 4 + 1) : 0;
  b += this->Nodes ? static_cast<long long>(this->NodeTableWidth) * this->NodeRows * 16 : 0;
  return b;
}

int ASMTextures::CountGraphicsResources() const
{
  int n = 0;
  for (unsigned int t : { this->Atlas, this->Summary, this->Scratch, this->ScratchDepth, this->SummaryScratch, this->Ids,
         this->IdDepth, this->Edges, this->Nodes })
  {
    n += t ? 1 : 0;
  }
  return n + ((this->FBO && this->FBO->GetFBOIndex() != 0) ? 1 : 0);
}

void ASMTextures::ReleaseGraphicsResources(vtkWindow* w)
{
  for (unsigned int* t : { &this->Atlas, &this->Summary, &this->Scratch, &this->ScratchDepth, &this->SummaryScratch,
         &this->Ids, &this->IdDepth, &this->Edges, &this->Nodes })
  {
    Delete(*t);
  }
  if (this->FBO)
  {
    this->FBO->ReleaseGraphicsResources(w);
    this->FBO = nullptr;
  }
  this->Layout = ASMAtlasLayout{};
  this->PageSize = this->SummarySize = this->ScratchSize = this->SummaryScratchSize = 0;
  this->Width = this->Height = this->NodeRows = this->NodeTableWidth = 0;
  this->UploadedVersion = 0;
}
}
