#include "ssAVSMMaps.h"

#include "ssCasterSet.h"
#include "ssComputeProgram.h"
#include "ssFrameState.h"
#include "ssGLLimits.h"
#include "ssPassStats.h"
#include "ssVisibilitySolver.h"
#include "ssVolumeCasters.h"

#include "ssAVSMBuildCS.h"
#include "ssAVSMCasterFS.h"
#include "ssAVSMCasterVS.h"
#include "ssAVSMNodes.h"

#include "vtkImageData.h"
#include "vtkOpenGLBufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVertexArrayObject.h"
#include "vtkPointData.h"
#include "vtkShaderProgram.h"
#include "vtkTexture.h"
#include "vtkTextureObject.h"
#include "vtkUnsignedCharArray.h"
#include "vtk_glew.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace ss
{
namespace
{
// SSBO binding points (glsl/ssAVSMBuildCS.glsl, ssAVSMCasterFS.glsl)
enum Binding
{
  BCounts = 0,
  BLocal = 1,
  BRows = 2,
  BRowStart = 3,
  BCursor = 4,
  BState = 5,
  BFrags = 6,
  BFrags2 = 7,
  NumBuffers = 8
};
constexpr GLuint kWG = 64;

// Loop iterations one insertion costs in ssAVSMNodes.glsl (two evaluations,
// the copy, the cut after a zero, two removals), so that a resolve dispatch
// stays under llvmpipe's 65535 iterations per invocation.
int InsertionBudget(int nodes)
{
  return std::max(16, 30000 / (6 * nodes + 12));
}
}

std::string AVSMBuildStats::ToJSON() const
{
  std::ostringstream o;
  o.precision(9);
  o << "{\"map_size\": " << mapSize << ", \"nodes\": " << nodes << ", \"channels\": " << channels
    << ", \"views\": " << views << ", \"levels\": " << levels << ", \"fragments\": " << fragments
    << ", \"longest_list\": " << longestList << ", \"bands\": " << bands << ", \"resolve_dispatches\": " << dispatches
    << ", \"fragment_capacity\": " << fragmentCapacity << ", \"unsorted_lists\": " << (unsortedLists ? "true" : "false")
    << ", \"truncated_rows\": " << (truncated ? "true" : "false") << ", \"triangles_drawn\": " << trianglesDrawn
    << ", \"clusters_drawn\": " << clusters.drawn << ", \"clusters_culled\": " << clusters.culled
    << ", \"volumes\": " << volumes << ", \"map_bytes\": " << mapBytes << ", \"buffer_bytes\": " << bufferBytes
    << ", \"ms\": {\"opaque\": " << msOpaque << ", \"count\": " << msCount << ", \"store\": " << msStore
    << ", \"sort\": " << msSort << ", \"resolve\": " << msResolve << ", \"pyramid\": " << msPyramid << "}"
    << ", \"note\": \"" << note << "\"}";
  return o.str();
}

struct AVSMMaps::Impl
{
  AVSMSettings Settings;
  AVSMBuildStats Stats;
  int S = 0, N = 8, C = 1;
  TextureArray Array;
  TextureArray Opaque; // one R32F layer: the view being built
  GLuint Buf[NumBuffers] = {};
  std::size_t Cap[NumBuffers] = {};
  GLuint FBO = 0;
  std::map<std::string, GLuint> Programs;
  std::map<std::pair<GLuint, std::string>, GLint> Locations;
  // the caster program and its vertex arrays (positions: the caster set's VBO)
  vtkShaderProgram* CasterProgram = nullptr;
  vtkSmartPointer<vtkOpenGLBufferObject> AttrVBO;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> VAO;
  unsigned long AttrUploads = ~0ul;
  vtkShaderProgram* VAOProgram = nullptr;
  std::vector<vtkSmartPointer<vtkTextureObject>> AlphaTex;
  unsigned long AlphaVersion = ~0ul;
  vtkSmartPointer<vtkTextureObject> Dummy3D;
  vtkSmartPointer<vtkTextureObject> Dummy2D; // what alpha samplers without a texture read

  void Ensure(Binding b, std::size_t bytes)
  {
    bytes = std::max<std::size_t>(bytes, 16);
    if (!this->Buf[b])
    {
      glGenBuffers(1, &this->Buf[b]);
    }
    if (this->Cap[b] != bytes)
    {
      glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buf[b]);
      glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_COPY);
      this->Cap[b] = bytes;
    }
  }
  void Zero(Binding b)
  {
    const GLuint zero = 0;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buf[b]);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  void BindBuffers()
  {
    for (int i = 0; i < NumBuffers; ++i)
    {
      const GLuint id = this->Buf[i == BFrags2 ? BFrags : i];
      if (id)
      {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(i), id);
      }
    }
  }
  long long BufferBytes() const
  {
    long long b = 0;
    for (std::size_t c : this->Cap)
    {
      b += static_cast<long long>(c);
    }
    return b;
  }

  GLuint Program(const std::string& kernel, std::string& error)
  {
    std::ostringstream head;
    head << "#version 430\n#define " << kernel << "\n#define WG " << kWG << "\n#define AVSM_N " << this->N
         << "\n#define AVSM_C " << this->C << "\n";
    const std::string key = head.str();
    const auto it = this->Programs.find(key);
    if (it != this->Programs.end())
    {
      return it->second;
    }
    std::string src = key + ssAVSMBuildCS;
    vtkShaderProgram::Substitute(src, "//SS::AVSMNodes", ssAVSMNodes);
    std::string why;
    const GLuint prog = CompileComputeProgram(src, why);
    if (!prog)
    {
      error = "AVSM: " + kernel + " " + why;
      return 0;
    }
    this->Programs[key] = prog;
    return prog;
  }
  GLint Loc(GLuint prog, const char* name)
  {
    const auto key = std::make_pair(prog, std::string(name));
    const auto it = this->Locations.find(key);
    if (it != this->Locations.end())
    {
      return it->second;
    }
    const GLint l = glGetUniformLocation(prog, name);
    this->Locations[key] = l;
    return l;
  }
  void Dispatch(std::size_t items)
  {
    const std::size_t groups = std::max<std::size_t>(1, (items + kWG - 1) / kWG);
    const GLuint gx = static_cast<GLuint>(std::min<std::size_t>(groups, 65535));
    const GLuint gy = static_cast<GLuint>((groups + gx - 1) / gx);
    glDispatchCompute(gx, gy, 1);
  }

  // The caster program with its vertex array: positions from the caster
  // set, opacity/colour/texture coordinates per vertex from ours.
  bool ReadyCasterProgram(SolverFrame& frame, std::string& error)
  {
    CasterSet& casters = *frame.Casters;
    this->CasterProgram = frame.Window->GetShaderCache()->ReadyShaderProgram(ssAVSMCasterVS, ssAVSMCasterFS, "");
    if (!this->CasterProgram)
    {
      error = "AVSM: could not build the caster program.";
      return false;
    }
    if (!this->AttrVBO)
    {
      this->AttrVBO = vtkSmartPointer<vtkOpenGLBufferObject>::New();
      this->AttrVBO->SetType(vtkOpenGLBufferObject::ArrayBuffer);
      this->VAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
    }
    // no triangles (only volumes cast): nothing to bind, nothing is drawn
    if (casters.NumberOfTriangles() > 0 &&
      (this->AttrUploads != casters.GetUploads() || this->VAOProgram != this->CasterProgram))
    {
      const std::size_t nt = casters.NumberOfTriangles();
      std::vector<float> attr(nt * 3 * 7, 0.0f);
      for (std::size_t t = 0; t < nt; ++t)
      {
        const float op = t < casters.Opacity.size() ? casters.Opacity[t] : 1.0f;
        for (int v = 0; v < 3; ++v)
        {
          float* a = &attr[(3 * t + v) * 7];
          a[0] = op;
          for (int c = 0; c < 3; ++c)
          {
            a[1 + c] = 3 * t + 2 < casters.Color.size() ? casters.Color[3 * t + c] : 1.0f;
          }
          const bool textured = t < casters.TextureIndex.size() && casters.TextureIndex[t] >= 0 &&
            casters.TextureIndex[t] < 4;
          a[4] = textured ? casters.TCoords[6 * t + 2 * v] : 0.0f;
          a[5] = textured ? casters.TCoords[6 * t + 2 * v + 1] : 0.0f;
          a[6] = textured ? static_cast<float>(casters.TextureIndex[t]) : -1.0f;
        }
      }
      this->AttrVBO->Upload(attr, vtkOpenGLBufferObject::ArrayBuffer);
      this->VAO->Bind();
      this->VAO->RemoveAttributeArray("vertexRel");
      this->VAO->RemoveAttributeArray("avsmLook");
      this->VAO->RemoveAttributeArray("avsmUV");
      const bool ok = this->VAO->AddAttributeArray(this->CasterProgram, casters.GetVertexBuffer(), "vertexRel", 0,
                        3 * sizeof(float), VTK_FLOAT, 3, false) &&
        this->VAO->AddAttributeArray(
          this->CasterProgram, this->AttrVBO, "avsmLook", 0, 7 * sizeof(float), VTK_FLOAT, 4, false) &&
        this->VAO->AddAttributeArray(
          this->CasterProgram, this->AttrVBO, "avsmUV", 4 * sizeof(float), 7 * sizeof(float), VTK_FLOAT, 3, false);
      this->VAO->Release();
      if (!ok)
      {
        error = "AVSM: could not bind the caster attributes.";
        return false;
      }
      this->AttrUploads = casters.GetUploads();
      this->VAOProgram = this->CasterProgram;
    }
    // the casters' alpha textures (RGBA or luminance-alpha images)
    if (this->AlphaVersion != casters.Version)
    {
      for (auto& t : this->AlphaTex)
      {
        t->ReleaseGraphicsResources(frame.Window);
      }
      this->AlphaTex.clear();
      for (std::size_t i = 0; i < casters.AlphaTextures.size() && i < 4; ++i)
      {
        vtkTexture* tex = casters.AlphaTextures[i];
        auto* img = vtkImageData::SafeDownCast(tex->GetInput());
        auto* src = img ? vtkUnsignedCharArray::SafeDownCast(img->GetPointData()->GetScalars()) : nullptr;
        int dims[3] = { 0, 0, 0 };
        if (img)
        {
          img->GetDimensions(dims);
        }
        auto t = vtkSmartPointer<vtkTextureObject>::New();
        t->SetContext(frame.Window);
        std::vector<unsigned char> rgba(static_cast<std::size_t>(std::max(dims[0] * dims[1], 1)) * 4, 255);
        const int nc = src ? src->GetNumberOfComponents() : 0;
        for (vtkIdType p = 0; src && p < static_cast<vtkIdType>(dims[0]) * dims[1]; ++p)
        {
          for (int c = 0; c < 3; ++c)
          {
            rgba[4 * p + c] = src->GetValue(p * nc + (nc == 4 ? c : 0));
          }
          rgba[4 * p + 3] = src->GetValue(p * nc + nc - 1);
        }
        const GLint wrap = tex->GetRepeat() ? vtkTextureObject::Repeat : vtkTextureObject::ClampToEdge;
        t->SetWrapS(wrap);
        t->SetWrapT(wrap);
        t->SetMinificationFilter(tex->GetInterpolate() ? vtkTextureObject::Linear : vtkTextureObject::Nearest);
        t->SetMagnificationFilter(tex->GetInterpolate() ? vtkTextureObject::Linear : vtkTextureObject::Nearest);
        t->Create2DFromRaw(static_cast<unsigned>(std::max(dims[0], 1)), static_cast<unsigned>(std::max(dims[1], 1)), 4,
          VTK_UNSIGNED_CHAR, rgba.data());
        this->AlphaTex.push_back(t);
      }
      this->AlphaVersion = casters.Version;
    }
    return true;
  }

  bool BuildView(SolverFrame& frame, const ShadowView& view, int layer0, VolumeCasters& volumes, std::string& error);
};

AVSMMaps::AVSMMaps()
  : P(new Impl)
{
}

AVSMMaps::~AVSMMaps() = default;

const TextureArray& AVSMMaps::GetArray() const
{
  return P->Array;
}
int AVSMMaps::GetSize() const
{
  return P->S;
}
int AVSMMaps::GetNodes() const
{
  return P->N;
}
int AVSMMaps::GetChannels() const
{
  return P->C;
}
int AVSMMaps::GetLayersPerView() const
{
  return P->N / 4 * (1 + P->C);
}
const AVSMBuildStats& AVSMMaps::GetStats() const
{
  return P->Stats;
}

bool AVSMMaps::Begin(SolverFrame& frame, int views, const AVSMSettings& settings, std::string& error)
{
  Impl& p = *P;
  p.Settings = settings;
  p.Stats = AVSMBuildStats{};
  const GLLimits limits = QueryGLLimits();
  if (limits.maxSSBOBytes <= 0 || !(GLEW_VERSION_4_3 || GLEW_ARB_compute_shader))
  {
    error = "AVSM needs OpenGL 4.3 (compute shaders and shader storage buffers); this context has none.";
    return false;
  }
  const int N = std::clamp((settings.Nodes + 3) / 4 * 4, 4, 16);
  const int C = settings.Colored ? 3 : 1;
  if (N != p.N || C != p.C)
  {
    // the programs are compiled for N and C
    for (auto& e : p.Programs)
    {
      glDeleteProgram(e.second);
    }
    p.Programs.clear();
    p.Locations.clear();
  }
  p.N = N;
  p.C = C;
  const int layersPerView = N / 4 * (1 + C);
  if (views * layersPerView > limits.maxArrayTextureLayers)
  {
    error = "AVSM: " + std::to_string(views) + " views of " + std::to_string(layersPerView) +
      " layers need more than this GL's " + std::to_string(limits.maxArrayTextureLayers) + " array layers.";
    return false;
  }
  const long long budget = static_cast<long long>(std::max(settings.MemoryMB, 1)) << 20;
  const int asked = FitPowerOfTwo(settings.MapSize, limits.maxTextureSize);
  int S = asked;
  auto fixedBytes = [&](int s) {
    const long long texels = static_cast<long long>(s) * s;
    const long long map = texels * 16 * layersPerView * views * (settings.Pyramid ? 4 : 3) / 3;
    return map + texels * (4 + 4 + 4 + 8 + 4); // counts, offsets, cursors, state, opaque depth
  };
  while (S > 64 && fixedBytes(S) > budget * 3 / 4)
  {
    S /= 2;
  }
  p.Stats.note.clear();
  if (S < std::max(64, settings.MapSize) && S < asked)
  {
    p.Stats.note = "AVSM of " + std::to_string(asked) + "^2 lowered to " + std::to_string(S) + "^2 to fit " +
      std::to_string(settings.MemoryMB) + " MB";
  }
  else if (asked < settings.MapSize)
  {
    p.Stats.note = "AVSM size capped at this GL's limit of " + std::to_string(asked);
  }
  p.S = S;
  int levels = 1;
  while (settings.Pyramid && (S >> levels) > 0)
  {
    ++levels;
  }
  p.Array.Allocate(S, S, views * layersPerView, levels, 4);
  p.Array.Size = S;
  p.Opaque.Allocate(S, S, 1, 1, 1);
  if (!p.Array.Handle || !p.Opaque.Handle)
  {
    error = "AVSM: could not allocate " + std::to_string(views * layersPerView) + " layers of " + std::to_string(S) +
      "^2 RGBA32F.";
    return false;
  }
  const std::size_t texels = static_cast<std::size_t>(S) * S;
  p.Ensure(BCounts, texels * 4);
  p.Ensure(BLocal, texels * 4);
  p.Ensure(BCursor, texels * 4);
  p.Ensure(BState, texels * 8);
  p.Ensure(BRows, static_cast<std::size_t>(S) * 8);
  p.Ensure(BRowStart, static_cast<std::size_t>(S) * 4);
  const long long entry = C == 3 ? 16 : 8;
  const long long room = std::max(budget - fixedBytes(S), 4ll << 20);
  const long long capBytes = std::min<long long>(room, limits.maxSSBOBytes) / entry * entry;
  p.Stats.fragmentCapacity = capBytes / entry; // the buffer grows to what a view's bands need, up to this
  if (!p.FBO)
  {
    glGenFramebuffers(1, &p.FBO);
  }
  if (!p.Dummy3D)
  {
    p.Dummy3D = vtkSmartPointer<vtkTextureObject>::New();
    p.Dummy3D->SetContext(frame.Window);
    const float zero = 0.0f;
    p.Dummy3D->Create3DFromRaw(1, 1, 1, 1, VTK_FLOAT, const_cast<float*>(&zero));
  }
  if (!p.Dummy2D)
  {
    p.Dummy2D = vtkSmartPointer<vtkTextureObject>::New();
    p.Dummy2D->SetContext(frame.Window);
    const unsigned char white[4] = { 255, 255, 255, 255 };
    p.Dummy2D->Create2DFromRaw(1, 1, 4, VTK_UNSIGNED_CHAR, const_cast<unsigned char*>(white));
  }
  p.Stats.mapSize = S;
  p.Stats.nodes = N;
  p.Stats.channels = C;
  p.Stats.levels = levels;
  p.Stats.mapBytes = p.Array.Bytes();
  p.Stats.bufferBytes = p.BufferBytes();
  std::string ignored;
  return p.ReadyCasterProgram(frame, error);
}

bool AVSMMaps::Build(SolverFrame& frame, const ShadowLight& light, int firstView, VolumeCasters& volumes, std::string& error)
{
  bool ok = true;
  for (std::size_t v = 0; v < light.Views.size() && ok; ++v)
  {
    ok = P->BuildView(frame, light.Views[v], (firstView + static_cast<int>(v)) * this->GetLayersPerView(), volumes, error);
    ++P->Stats.views;
  }
  return ok;
}

bool AVSMMaps::Impl::BuildView(
  SolverFrame& frame, const ShadowView& view, int layer0, VolumeCasters& volumes, std::string& error)
{
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkOpenGLState* ostate = win->GetState();
  CasterSet& casters = *frame.Casters;
  const glm::dvec3 offset = casters.Origin - frame.State->Origin;
  auto finish = [&]() { frame.Timings->Finish(); };
  auto t0 = Clock::now();

  // the clusters whose bounds reach the view (all triangles without clusters)
  TriangleRanges ranges;
  if (casters.HasClusters() && this->Settings.Culling)
  {
    ranges = VisibleTriangleRanges(casters.Clusters, view, offset, view.extent, 1e-3, &this->Stats.clusters);
  }
  else if (casters.NumberOfTriangles() > 0)
  {
    ranges.emplace_back(0, casters.NumberOfTriangles());
  }
  for (const auto& r : ranges)
  {
    this->Stats.trianglesDrawn += static_cast<long long>(r.second);
  }

  // --- 1. the nearest opaque depth per texel
  ostate->PushFramebufferBindings();
  ostate->vtkglBindFramebuffer(GL_FRAMEBUFFER, this->FBO);
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, this->Opaque.Handle, 0, 0);
  GLenum drawBuffer = GL_COLOR_ATTACHMENT0; // through the state cache (its checks compare GL_DRAW_BUFFER)
  ostate->vtkglDrawBuffers(1, &drawBuffer);
  ostate->vtkglViewport(0, 0, this->S, this->S);
  ostate->vtkglScissor(0, 0, this->S, this->S);
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_SCISSOR_TEST);
  ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
  ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
  win->GetShaderCache()->ReadyShaderProgram(this->CasterProgram);
  vtkShaderProgram* cp = this->CasterProgram;
  cp->SetUniformi("mapSize", this->S);
  cp->SetUniformi("coloured", this->C == 3 ? 1 : 0);
  cp->SetUniformi("view", 0);
  auto draw = [&](int pass) {
    cp->SetUniformi("pass", pass);
    if (!ranges.empty())
    {
      casters.Draw(cp, this->VAO, view, view.extent, offset, &ranges);
    }
  };
  // Every sampler of the caster program names a unit holding a texture of
  // its type before the first draw. A freshly linked program's samplers all
  // name unit 0, and samplers of different types on one unit (opaqueMap, a
  // 2-D array; alphaTex*, 2-D) make GL refuse the draw with INVALID_OPERATION
  // (GL 4.5 §11.1.3.11): the first build of a window drew no opaque caster
  // (no shadow in ParaView's first avsm frame; issue 20).
  int alphaUnits[4] = { -1, -1, -1, -1 };
  for (int i = 0; i < 4; ++i)
  {
    vtkTextureObject* t = i < static_cast<int>(this->AlphaTex.size()) ? this->AlphaTex[i].Get() : nullptr;
    if (t)
    {
      t->Activate();
      alphaUnits[i] = t->GetTextureUnit();
    }
  }
  if (alphaUnits[0] < 0)
  {
    this->Dummy2D->Activate();
  }
  // samplers that see no texture point at a 2-D one all the same
  const int fallback2D = alphaUnits[0] >= 0 ? alphaUnits[0] : this->Dummy2D->GetTextureUnit();
  for (int i = 0; i < 4; ++i)
  {
    cp->SetUniformi(("alphaTex" + std::to_string(i)).c_str(), alphaUnits[i] >= 0 ? alphaUnits[i] : fallback2D);
  }
  // pass 0 renders into the opaque map: its sampler names the AVSM array
  // meanwhile (a 2-D array that is not a target of this pass, never read)
  const int pass0Unit = this->Array.Bind(win);
  cp->SetUniformi("opaqueMap", pass0Unit);
  ostate->vtkglEnable(GL_BLEND);
  ostate->vtkglBlendEquation(GL_MIN);
  ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
  draw(0);
  ostate->vtkglBlendEquation(GL_FUNC_ADD);
  ostate->vtkglDisable(GL_BLEND);
  TextureArray::Unbind(win, pass0Unit);
  finish();
  auto t1 = Clock::now();
  this->Stats.msOpaque += Milliseconds(t0, t1);

  // --- 2. count the translucent fragments in front of it (no colour target)
  glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_WIDTH, this->S);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_HEIGHT, this->S);
  GLenum none = GL_NONE;
  ostate->vtkglDrawBuffers(1, &none);
  this->Zero(BCounts);
  this->BindBuffers();
  const int opaqueUnit = this->Opaque.Bind(win);
  cp->SetUniformi("opaqueMap", opaqueUnit);
  draw(1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  finish();
  t0 = Clock::now();
  this->Stats.msCount += Milliseconds(t1, t0);

  // --- row offsets, then bands of rows whose fragments fit the buffer
  win->GetShaderCache()->ReleaseCurrentShader();
  const GLuint scan = this->Program("K_SCAN", error);
  if (!scan)
  {
    ostate->PopFramebufferBindings();
    return false;
  }
  glUseProgram(scan);
  glUniform1i(this->Loc(scan, "uS"), this->S);
  this->BindBuffers();
  this->Dispatch(static_cast<std::size_t>(this->S));
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  std::vector<GLuint> rows(2 * static_cast<std::size_t>(this->S));
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buf[BRows]);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(rows.size() * 4), rows.data());
  const long long cap = this->Stats.fragmentCapacity;
  struct Band
  {
    int y0, y1;
    long long longest;
  };
  std::vector<Band> bands;
  long long inBand = 0;
  for (int y = 0; y < this->S; ++y)
  {
    const long long total = rows[y], longest = rows[this->S + y];
    this->Stats.fragments += total;
    this->Stats.longestList = std::max(this->Stats.longestList, longest);
    this->Stats.truncated = this->Stats.truncated || total > cap;
    if (bands.empty() || inBand + total > cap)
    {
      bands.push_back({ y, y + 1, longest });
      inBand = total;
    }
    else
    {
      bands.back().y1 = y + 1;
      bands.back().longest = std::max(bands.back().longest, longest);
      inBand += total;
    }
  }
  this->Stats.unsortedLists = this->Stats.unsortedLists || this->Stats.longestList > this->Settings.SortMax;
  this->Stats.bands += static_cast<int>(bands.size());
  // the fragment buffer: what the largest band needs (kept when larger, unless four times larger)
  long long need = 1;
  for (const Band& band : bands)
  {
    long long sum = 0;
    for (int y = band.y0; y < band.y1; ++y)
    {
      sum += rows[y];
    }
    need = std::max(need, std::min(sum, cap));
  }
  const std::size_t needBytes = static_cast<std::size_t>(need) * (this->C == 3 ? 16 : 8);
  if (this->Cap[BFrags] < needBytes || this->Cap[BFrags] > 4 * needBytes + (1u << 20))
  {
    this->Ensure(BFrags, needBytes);
  }

  // the volumes the resolve marches (at most four; unused samplers see an empty texture)
  const GLLimits limits = QueryGLLimits();
  GLint max3D = 256;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
  const auto& volTex = volumes.Textures(win, std::max<int>(1, max3D));
  const auto& volGeo = volumes.GPUGrids();
  this->Stats.volumes = std::max(this->Stats.volumes, static_cast<int>(volTex.size()));
  (void)limits;

  const GLuint sortProg = this->Program("K_SORT", error);
  const GLuint resolve = this->Program("K_RESOLVE", error);
  if (!sortProg || !resolve)
  {
    ostate->PopFramebufferBindings();
    return false;
  }
  const int budget = InsertionBudget(this->N);
  for (const Band& band : bands)
  {
    // row starts within the band (rows outside start at 0: they store nothing)
    std::vector<GLuint> start(static_cast<std::size_t>(this->S), 0u);
    long long acc = 0;
    for (int y = band.y0; y < band.y1; ++y)
    {
      start[y] = static_cast<GLuint>(std::min<long long>(acc, 0xFFFFFFFFll));
      acc += rows[y];
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, this->Buf[BRowStart]);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(start.size() * 4), start.data());
    this->Zero(BCursor);

    // --- store the band's fragments
    t1 = Clock::now();
    win->GetShaderCache()->ReadyShaderProgram(cp);
    cp->SetUniformi("fragCapacity", static_cast<int>(std::min<long long>(cap, 0x7FFFFFFF)));
    ostate->vtkglScissor(0, band.y0, this->S, band.y1 - band.y0);
    this->BindBuffers();
    draw(2);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    finish();
    t0 = Clock::now();
    this->Stats.msStore += Milliseconds(t1, t0);
    win->GetShaderCache()->ReleaseCurrentShader();

    const std::size_t items = static_cast<std::size_t>(this->S) * (band.y1 - band.y0);
    // --- sort each list
    glUseProgram(sortProg);
    glUniform1i(this->Loc(sortProg, "uS"), this->S);
    glUniform1i(this->Loc(sortProg, "uY0"), band.y0);
    glUniform1i(this->Loc(sortProg, "uY1"), band.y1);
    glUniform1i(this->Loc(sortProg, "uSortMax"), this->Settings.SortMax);
    glUniform1ui(this->Loc(sortProg, "uCapacity"), static_cast<GLuint>(std::min<long long>(cap, 0xFFFFFFFFll)));
    this->BindBuffers();
    this->Dispatch(items);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    finish();
    t1 = Clock::now();
    this->Stats.msSort += Milliseconds(t0, t1);

    // --- resolve: fragments and march steps into the nodes, in dispatches of `budget` insertions
    glUseProgram(resolve);
    glUniform1i(this->Loc(resolve, "uS"), this->S);
    glUniform1i(this->Loc(resolve, "uY0"), band.y0);
    glUniform1i(this->Loc(resolve, "uY1"), band.y1);
    glUniform1i(this->Loc(resolve, "uLayer0"), layer0);
    glUniform1i(this->Loc(resolve, "uBudget"), budget);
    glUniform1ui(this->Loc(resolve, "uCapacity"), static_cast<GLuint>(std::min<long long>(cap, 0xFFFFFFFFll)));
    glUniform1i(this->Loc(resolve, "uView"), 0);
    glUniform1i(this->Loc(resolve, "uOpaqueMap"), opaqueUnit);
    const glm::vec3 vo(view.origin), vu(view.u), vv(view.v), vn(view.n);
    glUniform3fv(this->Loc(resolve, "uViewOrigin"), 1, glm::value_ptr(vo));
    glUniform3fv(this->Loc(resolve, "uAxisU"), 1, glm::value_ptr(vu));
    glUniform3fv(this->Loc(resolve, "uAxisV"), 1, glm::value_ptr(vv));
    glUniform3fv(this->Loc(resolve, "uAxisN"), 1, glm::value_ptr(vn));
    glUniform4f(this->Loc(resolve, "uExtent"), static_cast<float>(view.extent.x0), static_cast<float>(view.extent.y0),
      static_cast<float>(view.extent.x1), static_cast<float>(view.extent.y1));
    glUniform1i(this->Loc(resolve, "uOrtho"), view.orthographic ? 1 : 0);
    const int nv = static_cast<int>(std::min<std::size_t>(volTex.size(), VolumeCasters::kMaxGPUVolumes));
    glUniform1i(this->Loc(resolve, "uVolumes"), nv);
    double step = 1e30;
    this->Dummy3D->Activate();
    for (int v = 0; v < 4; ++v)
    {
      int unit = this->Dummy3D->GetTextureUnit();
      if (v < nv)
      {
        volTex[v]->Activate();
        unit = volTex[v]->GetTextureUnit();
        const VolumeGrid& g = volGeo[v];
        step = std::min(step, 0.5 * g.MinSpacing());
        // relative world -> index: inverse(axes) * (p + frameOrigin - gridOrigin)
        const glm::dmat3 inv = glm::inverse(g.axes);
        const glm::dvec3 t = inv * (frame.State->Origin - g.origin);
        glm::mat4 m(1.0f);
        for (int c = 0; c < 3; ++c)
        {
          for (int r = 0; r < 3; ++r)
          {
            m[c][r] = static_cast<float>(inv[c][r]);
          }
          m[3][c] = static_cast<float>(t[c]);
        }
        const std::string mname = "uRelToIndex[" + std::to_string(v) + "]";
        const std::string dname = "uDims[" + std::to_string(v) + "]";
        glUniformMatrix4fv(this->Loc(resolve, mname.c_str()), 1, GL_FALSE, glm::value_ptr(m));
        glUniform3f(this->Loc(resolve, dname.c_str()), static_cast<float>(g.dims[0]), static_cast<float>(g.dims[1]),
          static_cast<float>(g.dims[2]));
      }
      const std::string sname = "uVol" + std::to_string(v);
      glUniform1i(this->Loc(resolve, sname.c_str()), unit);
    }
    glUniform1f(this->Loc(resolve, "uStep"), static_cast<float>(nv > 0 ? step : 1.0));
    glUniform1i(this->Loc(resolve, "uMaxSteps"), std::max(1, this->Settings.VolumeSteps));
    glBindImageTexture(0, this->Array.Handle, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32F);
    const long long events = band.longest + (nv > 0 ? this->Settings.VolumeSteps : 0) + 1;
    const int dispatches = static_cast<int>((events + budget - 1) / budget);
    for (int d = 0; d < dispatches; ++d)
    {
      glUniform1i(this->Loc(resolve, "uFirst"), d == 0 ? 1 : 0);
      this->Dispatch(items);
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
    this->Stats.dispatches += dispatches;
    for (int v = 0; v < nv; ++v)
    {
      volTex[v]->Deactivate();
    }
    this->Dummy3D->Deactivate();
    finish();
    t0 = Clock::now();
    this->Stats.msResolve += Milliseconds(t1, t0);
  }
  TextureArray::Unbind(win, opaqueUnit);
  for (int i = 0; i < 4; ++i)
  {
    if (i < static_cast<int>(this->AlphaTex.size()))
    {
      this->AlphaTex[i]->Deactivate();
    }
  }
  if (alphaUnits[0] < 0)
  {
    this->Dummy2D->Deactivate();
  }

  // --- 4. the pyramid of mean functions
  if (this->Array.Levels > 1)
  {
    t1 = Clock::now();
    const GLuint pyr = this->Program("K_PYRAMID", error);
    if (!pyr)
    {
      ostate->PopFramebufferBindings();
      return false;
    }
    glUseProgram(pyr);
    glUniform1i(this->Loc(pyr, "uLayer0"), layer0);
    for (int level = 1; level < this->Array.Levels; ++level)
    {
      const int size = std::max(1, this->S >> level);
      glUniform1i(this->Loc(pyr, "uSize"), size);
      glBindImageTexture(0, this->Array.Handle, level, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(1, this->Array.Handle, level - 1, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
      this->Dispatch(static_cast<std::size_t>(size) * size);
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    finish();
    this->Stats.msPyramid += Milliseconds(t1, Clock::now());
  }
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glUseProgram(0);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  ostate->PopFramebufferBindings();
  return true;
}

bool AVSMMaps::ReadTexel(vtkOpenGLRenderWindow* win, int view, int level, int x, int y, std::vector<float>& depths,
  std::vector<float>& transmittance) const
{
  const Impl& p = *P;
  const int size = std::max(1, p.S >> level);
  if (!p.Array.Handle || level < 0 || level >= p.Array.Levels || x < 0 || y < 0 || x >= size || y >= size)
  {
    return false;
  }
  win->MakeCurrent();
  const int nb = p.N / 4, layer0 = view * this->GetLayersPerView();
  if (layer0 + this->GetLayersPerView() > p.Array.Layers)
  {
    return false;
  }
  std::vector<float> block(4 * static_cast<std::size_t>(this->GetLayersPerView()));
  glGetTextureSubImage(p.Array.Handle, level, x, y, layer0, 1, 1, this->GetLayersPerView(), GL_RGBA, GL_FLOAT,
    static_cast<GLsizei>(block.size() * 4), block.data());
  depths.assign(block.begin(), block.begin() + 4 * nb);
  transmittance.assign(block.begin() + 4 * nb, block.end());
  return glGetError() == GL_NO_ERROR;
}

long long AVSMMaps::Bytes() const
{
  return P->Array.Bytes() + P->Opaque.Bytes() + P->BufferBytes();
}

int AVSMMaps::CountGraphicsResources() const
{
  int n = (P->Array.Handle ? 1 : 0) + (P->Opaque.Handle ? 1 : 0) + (P->FBO ? 1 : 0) + (P->Dummy3D ? 1 : 0) +
    (P->Dummy2D ? 1 : 0);
  for (GLuint b : P->Buf)
  {
    n += b ? 1 : 0;
  }
  n += static_cast<int>(P->Programs.size() + P->AlphaTex.size());
  n += (P->AttrVBO && P->AttrVBO->GetHandle() != 0) ? 1 : 0;
  return n;
}

void AVSMMaps::ReleaseGraphicsResources(vtkWindow* w)
{
  Impl& p = *P;
  p.Array.Release();
  p.Opaque.Release();
  for (std::size_t i = 0; i < NumBuffers; ++i)
  {
    if (p.Buf[i])
    {
      glDeleteBuffers(1, &p.Buf[i]);
      p.Buf[i] = 0;
      p.Cap[i] = 0;
    }
  }
  if (p.FBO)
  {
    glDeleteFramebuffers(1, &p.FBO);
    p.FBO = 0;
  }
  for (auto& e : p.Programs)
  {
    glDeleteProgram(e.second);
  }
  p.Programs.clear();
  p.Locations.clear();
  for (auto& t : p.AlphaTex)
  {
    t->ReleaseGraphicsResources(w);
  }
  p.AlphaTex.clear();
  p.AlphaVersion = ~0ul;
  if (p.Dummy3D)
  {
    p.Dummy3D->ReleaseGraphicsResources(w);
    p.Dummy3D = nullptr;
  }
  if (p.Dummy2D)
  {
    p.Dummy2D->ReleaseGraphicsResources(w);
    p.Dummy2D = nullptr;
  }
  if (p.VAO)
  {
    p.VAO->ReleaseGraphicsResources();
    p.VAO = nullptr;
  }
  if (p.AttrVBO)
  {
    p.AttrVBO->ReleaseGraphicsResources();
    p.AttrVBO = nullptr;
  }
  p.AttrUploads = ~0ul;
  p.VAOProgram = nullptr;
  p.CasterProgram = nullptr;
  p.S = 0;
}
}
