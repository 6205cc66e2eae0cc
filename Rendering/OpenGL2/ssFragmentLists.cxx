#include "ssFragmentLists.h"

#include "ssFullScreenQuad.h"
#include "ssGLLimits.h"

#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace ss
{
namespace
{
// A binding point nothing else uses while recording or shading (the AVSM
// build binds its buffers only while it builds; GL 4.3 guarantees 8).
constexpr int kListBinding = 6;
constexpr long long kHeader = 4; // uints before the heads
// The lists' budget: past it the shading (every peel) runs the lookups itself.
constexpr long long kBudgetBytes = 512ll << 20;

std::string Declarations()
{
  return "layout(std430, binding = " + std::to_string(kListBinding) +
    ") buffer ssFragListBuffer { uint ssFL[]; };\n"
    "uniform int ssListWidth;\n"
    "uniform int ssListHeight;\n"
    "uniform int ssListSlots;    // slots stored per entry\n"
    "uniform int ssListChannels; // 1 or 3\n"
    "uniform uint ssListCapacity;\n"
    "uint ssListEntry(uint i)\n"
    "{\n"
    "  return 4u + uint(ssListWidth * ssListHeight) + i * uint(" + std::to_string(FragmentLists::kEntryHeader) +
    " + ssListSlots * ssListChannels);\n"
    "}\n"
    "int ssListHead(ivec2 pix)\n"
    "{\n"
    "  bool inside = all(greaterThanEqual(pix, ivec2(0))) && pix.x < ssListWidth && pix.y < ssListHeight;\n"
    "  return inside ? 4 + pix.y * ssListWidth + pix.x : -1;\n"
    "}\n"
    "// entry `at`'s position, shading normal and facet normal\n"
    "void ssListPoint(uint at, out vec3 p, out vec3 nrm, out vec3 ng)\n"
    "{\n"
    "  for (int c = 0; c < 3; ++c)\n"
    "  {\n"
    "    p[c] = uintBitsToFloat(ssFL[at + 2u + uint(c)]);\n"
    "    nrm[c] = uintBitsToFloat(ssFL[at + 5u + uint(c)]);\n"
    "    ng[c] = uintBitsToFloat(ssFL[at + 8u + uint(c)]);\n"
    "  }\n"
    "}\n";
}
}

FragmentLists::FragmentLists() = default;

FragmentLists::~FragmentLists()
{
  // the context may be gone: ReleaseGraphicsResources is the pass's to call
}

std::string FragmentLists::RecordCode()
{
  std::ostringstream o;
  o << Declarations()
    << "// one entry per fragment: its depth and what its filter needs\n"
       "void ssRecordFragment(vec3 p, vec3 nrm, vec3 ng)\n"
       "{\n"
       "  int head = ssListHead(ivec2(gl_FragCoord.xy));\n"
       "  if (head < 0) { return; }\n"
       "  uint i = atomicAdd(ssFL[0], 1u);\n"
       "  if (i >= ssListCapacity) { return; } // counted all the same: the pass grows the buffer\n"
       "  uint at = ssListEntry(i);\n"
       "  ssFL[at] = floatBitsToUint(gl_FragCoord.z);\n"
       "  for (int c = 0; c < 3; ++c)\n"
       "  {\n"
       "    ssFL[at + 2u + uint(c)] = floatBitsToUint(p[c]);\n"
       "    ssFL[at + 5u + uint(c)] = floatBitsToUint(nrm[c]);\n"
       "    ssFL[at + 8u + uint(c)] = floatBitsToUint(ng[c]);\n"
       "  }\n"
       "  ssFL[at + 1u] = atomicExchange(ssFL[head], i + 1u);\n"
       "}\n";
  return o.str();
}

std::string FragmentLists::FilterCode()
{
  std::ostringstream o;
  o << Declarations()
    << "uniform int ssListCount;   // entries appended\n"
       "uniform int ssEntriesWide; // entries per row of the pass\n"
       "// this fragment's entry (~0u: past the last)\n"
       "uint ssListEntryAt()\n"
       "{\n"
       "  int e = int(gl_FragCoord.y) * ssEntriesWide + int(gl_FragCoord.x);\n"
       "  return (e < ssListCount) ? ssListEntry(uint(e)) : 0xFFFFFFFFu;\n"
       "}\n"
       "void ssListStore(uint at, int slot, vec3 V)\n"
       "{\n"
       "  uint c = at + " << FragmentLists::kEntryHeader << "u + uint(slot * ssListChannels);\n"
       "  ssFL[c] = floatBitsToUint(V.x);\n"
       "  if (ssListChannels == 3) { ssFL[c + 1u] = floatBitsToUint(V.y); ssFL[c + 2u] = floatBitsToUint(V.z); }\n"
       "}\n";
  return o.str();
}

std::string FragmentLists::LookupCode(bool countMisses)
{
  std::ostringstream o;
  o.precision(9);
  o << Declarations()
    << "uniform int ssListCount; // entries appended (bounds every walk)\n"
       "uint ssListAt = 0u;       // this fragment's entry (0: not looked up yet)\n"
       "// The entry of this fragment's pixel nearest to it in depth, looked up once\n"
       "// for all its lights (~0u: the pixel has none).\n"
       "uint ssListFind()\n"
       "{\n"
       "  if (ssListAt != 0u) { return ssListAt; }\n"
       "  int head = ssListHead(ivec2(gl_FragCoord.xy - ssViewportOrigin));\n"
       "  uint j = (head >= 0) ? ssFL[head] : 0u;\n"
       "  float best = 3.0e38;\n"
       "  uint found = 0xFFFFFFFFu;\n"
       "  // links are entry + 1, 0 ends a list: llvmpipe runs a loop for the\n"
       "  // lanes a peel has already returned from too, and their loads read 0\n"
       "  for (int n = 0; j != 0u && n < ssListCount; ++n)\n"
       "  {\n"
       "    uint at = ssListEntry(j - 1u);\n"
       "    float dz = abs(uintBitsToFloat(ssFL[at]) - gl_FragCoord.z);\n"
       "    found = (dz < best) ? at : found;\n"
       "    best = min(best, dz);\n"
       "    j = ssFL[at + 1u];\n"
       "  }\n";
  if (countMisses)
  {
    o << "  if (!(best <= " << kListDepthTolerance << ")) { atomicAdd(ssFL[1], 1u); }\n";
  }
  o << "  ssListAt = found;\n"
       "  return found;\n"
       "}\n"
       "vec3 ssListedVisibility(int slot)\n"
       "{\n"
       "  uint at = ssListFind();\n"
       "  if (at == 0xFFFFFFFFu || slot >= ssListSlots) { return vec3(1.0); }\n"
       "  uint c = at + " << FragmentLists::kEntryHeader << "u + uint(slot * ssListChannels);\n"
       "  float r = uintBitsToFloat(ssFL[c]);\n"
       "  return (ssListChannels == 3) ? vec3(r, uintBitsToFloat(ssFL[c + 1u]), uintBitsToFloat(ssFL[c + 2u])) : vec3(r);\n"
       "}\n"
       "// the point and the plane's normal the filter took (the capture's)\n"
       "void ssListedPoint(out vec3 p, out vec3 nPlane)\n"
       "{\n"
       "  uint at = ssListFind();\n"
       "  p = vec3(0.0);\n"
       "  nPlane = vec3(0.0);\n"
       "  if (at == 0xFFFFFFFFu) { return; }\n"
       "  vec3 nrm, ng;\n"
       "  ssListPoint(at, p, nrm, ng);\n"
       "  nPlane = (dot(ng, ng) > 0.5) ? ng : nrm;\n"
       "}\n";
  return o.str();
}

bool FragmentLists::Begin(
  vtkOpenGLRenderWindow* win, int width, int height, int slots, int channels, std::string& error)
{
  win->MakeCurrent();
  GLint fragmentBlocks = 0, bindings = 0;
  glGetIntegerv(GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, &fragmentBlocks);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  const std::int64_t maxBlock = QueryGLLimits().maxSSBOBytes; // (lowerable: SOFTSHADOWS_GL_MAX_SSBO_BYTES)
  // the shaders' #extension lines (ssShadingSubstitution RequireExtensions)
  const bool extensions = GLEW_ARB_shader_storage_buffer_object && GLEW_ARB_shading_language_420pack &&
    GLEW_ARB_shader_bit_encoding && GLEW_ARB_shader_image_load_store;
  if (!glBindBufferBase || !glClearBufferSubData || !extensions || fragmentBlocks < 1 || bindings <= kListBinding)
  {
    error = "no shader storage buffers in fragment shaders (GL 4.3)";
    return false;
  }
  const bool resized = width != this->Width || height != this->Height || slots != this->Slots ||
    channels != this->Channels;
  this->Width = width;
  this->Height = height;
  this->Slots = slots;
  this->Channels = channels;
  const long long pixels = static_cast<long long>(width) * height;
  const long long stride = this->Stride();
  const long long limit = std::min<long long>(kBudgetBytes, maxBlock) / 4;
  // room for what the last frame appended and a quarter more, 2 per pixel at least
  const long long wanted = std::max(this->Wanted + this->Wanted / 4, 2 * pixels);
  const long long capacity = std::min(wanted, (limit - kHeader - pixels) / stride);
  if (capacity <= 0)
  {
    error = "a " + std::to_string(width) + " x " + std::to_string(height) + " frame's lists exceed " +
      std::to_string(limit * 4) + " bytes (the budget or the GL's largest storage block)";
    return false;
  }
  const long long bytes = 4 * (kHeader + pixels + capacity * stride);
  if (!this->Buffer)
  {
    glGenBuffers(1, &this->Buffer);
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buffer);
  if (resized || capacity > this->Capacity || bytes > this->Allocated)
  {
    while (glGetError() != GL_NO_ERROR)
    {
    }
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_COPY);
    if (glGetError() != GL_NO_ERROR)
    {
      glDeleteBuffers(1, &this->Buffer);
      this->Buffer = 0;
      this->Allocated = 0;
      this->Capacity = 0;
      error = "GL refused a buffer of " + std::to_string(bytes >> 20) + " MB";
      return false;
    }
    this->Allocated = bytes;
    this->Capacity = capacity;
  }
  const GLuint zero = 0; // the counters, and every pixel's list empty
  glClearBufferSubData(
    GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0, 4 * (kHeader + pixels), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  this->Count = 0;
  this->Bind();
  return true;
}

void FragmentLists::BindRecordTarget(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo,
  vtkTextureObject* color, vtkTextureObject* depth) const
{
  vtkOpenGLState* ostate = win->GetState();
  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->AddColorAttachment(0, color);
  fbo->AddDepthAttachment(depth);
  fbo->ActivateDrawBuffers(1);
  ostate->vtkglViewport(0, 0, this->Width, this->Height);
  ostate->vtkglScissor(0, 0, this->Width, this->Height);
  ostate->vtkglDisable(GL_BLEND);
  ostate->vtkglEnable(GL_DEPTH_TEST);
  ostate->vtkglDepthFunc(GL_LEQUAL);
  ostate->vtkglDepthMask(GL_FALSE);
  ostate->vtkglColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
}

void FragmentLists::UnbindRecordTarget(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo) const
{
  fbo->RemoveColorAttachments(1);
  fbo->RemoveDepthAttachment();
  win->GetState()->PopFramebufferBindings();
}

bool FragmentLists::End(bool& retry, std::string& error)
{
  retry = false;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint appended = 0;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buffer);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, 4, &appended);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  this->Unbind();
  this->Count = appended;
  this->Wanted = appended;
  if (this->Count <= this->Capacity)
  {
    return true;
  }
  const long long needed = 4 * (kHeader + static_cast<long long>(this->Width) * this->Height + this->Count * this->Stride());
  const long long limit = std::min<long long>(kBudgetBytes, QueryGLLimits().maxSSBOBytes);
  retry = needed <= limit;
  if (!retry)
  {
    error = std::to_string(this->Count) + " translucent receiver fragments need " + std::to_string(needed) +
      " bytes of lists, over " + std::to_string(limit) + " (the budget or the GL's largest storage block)";
    this->Wanted = 0;
  }
  return false;
}

bool FragmentLists::Filter(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, const std::string& fs,
  const std::function<void(vtkShaderProgram*)>& setUniforms, std::string& error)
{
  if (this->Count == 0)
  {
    return true;
  }
  // one fragment per entry, in rows of `wide`
  GLint maxTexture = 0, dims[2] = { 0, 0 };
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  const long long side = std::min<long long>({ maxTexture, dims[0], dims[1] });
  const long long wide = std::min<long long>(side, 1024);
  const long long rows = (this->Count + wide - 1) / wide;
  if (rows > side)
  {
    error = std::to_string(this->Count) + " listed fragments exceed a " + std::to_string(side) + " x " +
      std::to_string(side) + " filter pass";
    return false;
  }
  if (fs != this->QuadSource)
  {
    ReleaseQuad(this->Quad, win);
    this->QuadSource = fs;
  }
  vtkShaderProgram* prog = ReadyQuad(this->Quad, win, fs.c_str());
  if (!prog)
  {
    error = "the fragment lists' filter pass did not compile";
    return false;
  }
  if (!this->Target)
  {
    this->Target = vtkSmartPointer<vtkTextureObject>::New();
    this->Target->SetContext(win);
  }
  if (static_cast<long long>(this->Target->GetWidth()) != wide ||
    static_cast<long long>(this->Target->GetHeight()) < rows)
  {
    this->Target->ReleaseGraphicsResources(win);
    this->Target->Allocate2D(static_cast<unsigned int>(wide), static_cast<unsigned int>(rows), 1, VTK_UNSIGNED_CHAR);
  }
  vtkOpenGLState* ostate = win->GetState();
  vtkOpenGLState::ScopedglColorMask colorSaver(ostate);
  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->AddColorAttachment(0, this->Target);
  fbo->ActivateDrawBuffers(1);
  ostate->vtkglViewport(0, 0, static_cast<GLsizei>(wide), static_cast<GLsizei>(rows));
  ostate->vtkglScissor(0, 0, static_cast<GLsizei>(wide), static_cast<GLsizei>(rows));
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_BLEND);
  ostate->vtkglColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  this->Bind();
  setUniforms(prog);
  this->SetUniforms(prog);
  prog->SetUniformi("ssEntriesWide", static_cast<int>(wide));
  this->Quad->Render();
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  this->Unbind();
  fbo->RemoveColorAttachments(1);
  ostate->PopFramebufferBindings();
  return true;
}

int FragmentLists::CountGraphicsResources() const
{
  return (this->Buffer != 0 ? 1 : 0) + (this->Quad ? 1 : 0) + (this->Target && this->Target->GetHandle() ? 1 : 0);
}

void FragmentLists::SetUniforms(vtkShaderProgram* program) const
{
  if (!program->IsUniformUsed("ssListWidth"))
  {
    return;
  }
  program->SetUniformi("ssListWidth", this->Width);
  program->SetUniformi("ssListHeight", this->Height);
  program->SetUniformi("ssListSlots", this->Slots);
  program->SetUniformi("ssListChannels", this->Channels);
  const long long cap = std::min<long long>(this->Capacity, 0x7FFFFFFF);
  if (program->IsUniformUsed("ssListCapacity"))
  {
    glUniform1ui(program->FindUniform("ssListCapacity"), static_cast<GLuint>(cap));
  }
  if (program->IsUniformUsed("ssListCount"))
  {
    program->SetUniformi("ssListCount", static_cast<int>(std::min(this->Count, cap)));
  }
}

void FragmentLists::Bind() const
{
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kListBinding, this->Buffer);
}

void FragmentLists::Unbind() const
{
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kListBinding, 0);
}

long long FragmentLists::ReadMisses() const
{
  if (!this->Buffer)
  {
    return 0;
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint misses = 0;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buffer);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 4, 4, &misses);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return misses;
}

void FragmentLists::ReleaseGraphicsResources(vtkWindow* w)
{
  ReleaseQuad(this->Quad, w);
  this->QuadSource.clear();
  if (this->Target)
  {
    this->Target->ReleaseGraphicsResources(w);
    this->Target = nullptr;
  }
  if (this->Buffer)
  {
    glDeleteBuffers(1, &this->Buffer);
  }
  this->Buffer = 0;
  this->Allocated = 0;
  this->Capacity = 0;
  this->Count = 0;
}
}
