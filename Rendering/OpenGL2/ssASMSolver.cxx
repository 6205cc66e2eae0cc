#include "ssASMSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssFullScreenQuad.h"
#include "ssGBuffer.h"
#include "ssGLLimits.h"
#include "ssPassStats.h"
#include "ssVisibilityLayers.h"

#include "ssASMIdFS.h"
#include "ssASMIdVS.h"
#include "ssASMNodeFS.h"
#include "ssASMQueryFS.h"
#include "ssCasterVS.h"
#include "ssConservativeFS.h"
#include "ssConservativeGS.h"

#include "vtkCamera.h"
#include "vtkLight.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkOpenGLBufferObject.h"
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVertexArrayObject.h"
#include "vtkRenderer.h"
#include "vtkSetGet.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ss
{
struct ASMSolver::FrameStats
{
  int lights = 0;
  ASMAnalysisStats analysis;
  int candidates = 0, created = 0, upgraded = 0, evictedLRU = 0, replaced = 0, skipped = 0;
  std::size_t remaining = 0;
  double predictedMs = 0.0, creationMs = 0.0;
  double msIds = 0.0, msAnalysis = 0.0, msCreation = 0.0, msQueries = 0.0;
  int queryPasses = 0;
  double trianglesDrawn = 0.0;
  int roots = 0;
  std::string clusters; ///< CasterSet::ClusterStatsJSON summed over the lights' top-level cells
};

namespace
{
ShadowView Relative(const ShadowView& v, const glm::dvec3& origin)
{
  ShadowView r = v;
  r.origin -= origin;
  return r;
}

// The caster program with each triangle's id passed on (§4.2): ssCasterVS
// with two lines added, so both draw the same positions.
std::string NodeVertexShader()
{
  std::string vs(ssCasterVS);
  vtkShaderProgram::Substitute(vs, "out float depthLS;", "out float depthLS;\nflat out uint triangleId;");
  vtkShaderProgram::Substitute(vs, "depthLS = z;", "depthLS = z;\n  triangleId = uint(gl_VertexID / 3) + 1u;");
  return vs;
}

void AddAnalysis(ASMAnalysisStats& sum, const ASMAnalysisStats& a)
{
  sum.pixels += a.pixels;
  sum.sampled += a.sampled;
  sum.edges += a.edges;
  sum.mismatched += a.mismatched;
  sum.unresolvable += a.unresolvable;
  sum.cacheHits += a.cacheHits;
  sum.cacheMisses += a.cacheMisses;
  sum.leavesUsed += a.leavesUsed;
  sum.maxEffectiveResolution = std::max(sum.maxEffectiveResolution, a.maxEffectiveResolution);
}
}

ASMSolver::ASMSolver(Method method)
  : VisibilitySolver(method)
  , Stats(new FrameStats)
  , LastStats(new FrameStats)
{
}

ASMSolver::~ASMSolver() = default;

const OptionList& ASMSolver::DeclaredOptions()
{
  // key, property (Python, ParaView), label, range, default, help
  static const OptionList options = {
    DoubleOption("asm_memory_mb", "ASMMemoryBudget", "ASM Memory Budget", 0.0625, 4096.0, 16.0,
      "asm: memory budget of the page pool, megabytes (never exceeded)"),
    IntOption("asm_page_size", "ASMPageSize", "ASM Page Size", 16, 4096, 128,
      "asm: page texels a side (rounded up to a power of two)"),
    IntOption("asm_cells", "ASMCells", "ASM Cells", 2, 8, 4,
      "asm: cells a side a node splits into (rounded up to 2, 4 or 8)"),
    IntOption("asm_max_depth", "ASMMaxDepth", "ASM Max Depth", 0, 20, 10,
      "asm: deepest level of the hierarchy"),
    DoubleOption("asm_time_budget_ms", "ASMTimeBudget", "ASM Time Budget", 0.0, 1.0e5, 20.0,
      "asm: refinement time a frame, ms"),
    IntOption("asm_stride", "ASMAnalysisStride", "ASM Analysis Stride", 1, 64, 8,
      "asm: one pixel in N analysed a frame"),
    DoubleOption("asm_quality", "ASMQuality", "ASM Quality", 0.125, 16.0, 1.0,
      "asm: texels per pixel side"),
    BoolOption("asm_id_test", "ASMIDTest", "ASM ID Test", true, "asm: the ID+depth test (section 4.2)"),
    // shared with the AVSM build (ssTranslucentSolver reads it too); PVSM's
    // tiles have pvsm_tile_culling
    BoolOption("caster_culling", "CasterCulling", "Caster Culling", true,
      "asm, avsm, vpcss: draw only the caster clusters whose bounds reach a cell or view (off: every triangle "
      "everywhere, for measuring)"),
  };
  return options;
}

void ASMSolver::Configure(vtkSoftShadowPass* pass)
{
  const auto opt = [pass](const char* key) { return static_cast<int>(pass->GetSolverOption(key)); };
  this->Opt.Culling = opt("caster_culling") != 0;
  this->Opt.MemoryMB = pass->GetSolverOption("asm_memory_mb");
  this->Opt.PageSize = opt("asm_page_size");
  this->Opt.Cells = opt("asm_cells");
  this->Opt.MaxDepth = opt("asm_max_depth");
  this->Opt.TimeBudgetMs = pass->GetSolverOption("asm_time_budget_ms");
  this->Opt.AnalysisStride = opt("asm_stride");
  this->Opt.Quality = pass->GetSolverOption("asm_quality");
  this->Opt.IDTest = opt("asm_id_test") != 0;
  this->Opt.ConstantBias = pass->GetConstantBias();
  this->Opt.SlopeBias = pass->GetSlopeBias();
  // the tree's shape: powers of two (the properties clamp the ranges)
  ASMSettings s;
  s.pageSize = CeilPowerOfTwo(this->Opt.PageSize);
  s.cells = CeilPowerOfTwo(this->Opt.Cells);
  s.minResolution = std::min(16, s.pageSize);
  s.maxDepth = this->Opt.MaxDepth;
  this->BudgetBytes = static_cast<long long>(this->Opt.MemoryMB * 1024.0 * 1024.0);
  // A budget that holds too few pages of the asked size (fewer than the six
  // roots of a point light) gets smaller pages, down to 16^2, with a note
  // (EnsureResources warns): before, ASMMemoryBudget 0.0625 or ASMPageSize
  // 4096 left the light unshadowed while the plan said asm ran.
  this->PageNote.clear();
  const int asked = s.pageSize;
  while (s.pageSize > 16 && this->BudgetBytes / s.PageBytes() < 6)
  {
    s.pageSize /= 2;
    s.minResolution = std::min(16, s.pageSize);
  }
  if (s.pageSize < asked)
  {
    this->PageNote = "ASM: a memory budget of " + std::to_string(this->Opt.MemoryMB) +
      " MB holds fewer than 6 pages of " + std::to_string(asked) + "^2 texels; using pages of " +
      std::to_string(s.pageSize) + "^2";
  }
  this->Settings = s;
}

void ASMSolver::Reset()
{
  for (auto& ls : this->Lights)
  {
    for (int v : ls->TreeViews)
    {
      this->Tree.RemoveRoot(v);
    }
  }
  this->Lights.clear();
  this->Tree = ASMTree();
  this->ShapeKey.clear();
  this->FramesWithoutWork = 0;
}

bool ASMSolver::EnsureResources(SolverFrame& frame)
{
  if (!this->PageNote.empty() && this->PageNote != this->PageWarned)
  {
    vtkWarningWithObjectMacro(frame.Reporter, << this->PageNote << ".");
    this->PageWarned = this->PageNote;
  }
  const GLLimits limits = QueryGLLimits();
  std::ostringstream key;
  key << this->Settings.pageSize << ',' << this->Settings.cells << ',' << this->Settings.maxDepth << ','
      << this->BudgetBytes << ',' << limits.maxTextureSize << ',' << limits.maxArrayTextureLayers;
  if (key.str() != this->ShapeKey || !this->Tex.Atlas)
  {
    this->Reset();
    // §3.2: the atlas holds the pages the budget allows and no more
    const long long pages = this->BudgetBytes / this->Settings.PageBytes();
    ASMAtlasLayout layout =
      PlanAtlas(pages, this->Settings.pageSize, limits.maxTextureSize, limits.maxArrayTextureLayers);
    std::string error;
    bool allocated = layout.pages > 0 &&
      this->Tex.EnsureAtlas(layout, this->Settings.pageSize, this->Settings.SummarySize(), error);
    // An atlas the context cannot allocate (a budget within the option's
    // range, 2048 MB on llvmpipe: stop 45's Python sweep found the light then
    // unshadowed) is halved until it can, down to a point light's 6 roots,
    // with a warning: the budget is a ceiling, never exceeded.
    long long tried = layout.pages;
    while (!allocated && tried / 2 >= 6)
    {
      tried /= 2;
      layout = PlanAtlas(tried, this->Settings.pageSize, limits.maxTextureSize, limits.maxArrayTextureLayers);
      std::string again;
      allocated = layout.pages > 0 &&
        this->Tex.EnsureAtlas(layout, this->Settings.pageSize, this->Settings.SummarySize(), again);
    }
    if (allocated && layout.pages < pages)
    {
      std::ostringstream note;
      note << "ASM: this context could not allocate the atlas of " << pages << " pages that "
           << this->Opt.MemoryMB << " MB holds; it uses " << layout.pages << " pages ("
           << layout.pages * this->Settings.PageBytes() / 1048576.0 << " MB)";
      vtkWarningWithObjectMacro(frame.Reporter, << note.str() << ".");
      this->AtlasNote = note.str();
    }
    else if (allocated)
    {
      this->AtlasNote.clear();
    }
    if (!allocated)
    {
      vtkErrorWithObjectMacro(frame.Reporter,
        << (error.empty() ? "ASM: a memory budget of " + std::to_string(this->Opt.MemoryMB) +
              " MB holds no page of " + std::to_string(this->Settings.pageSize) + "^2 texels (" +
              std::to_string(this->Settings.PageBytes()) + " bytes)"
                          : error));
      return false;
    }
    this->Tree = ASMTree(this->Settings, layout.pages);
    this->ShapeKey = key.str();
  }
  if (!this->Tex.EnsureScratch(this->Settings.pageSize, this->Settings.SummarySize()) ||
    !this->Tex.EnsureScreen(frame.State->Width, frame.State->Height))
  {
    vtkErrorWithObjectMacro(frame.Reporter, "ASM: could not allocate its render targets.");
    return false;
  }
  return true;
}

void ASMSolver::BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights)
{
  this->Active = !lights.empty();
  this->Pending.clear();
  this->IdsDone = false;
  this->PositionsRead = false;
  this->Positions = nullptr;
  if (!this->Active)
  {
    this->Refining = false;
    *this->LastStats = FrameStats{};
    return;
  }
  ++this->Frame;
  *this->Stats = FrameStats{};
  // lights gone since the last frame give their pages back
  for (std::size_t i = 0; i < this->Lights.size();)
  {
    bool present = false;
    for (const ShadowLight* l : lights)
    {
      present = present || l->Light == this->Lights[i]->Light;
    }
    if (present)
    {
      ++i;
      continue;
    }
    for (int v : this->Lights[i]->TreeViews)
    {
      this->Tree.RemoveRoot(v);
    }
    this->Lights.erase(this->Lights.begin() + static_cast<std::ptrdiff_t>(i));
  }
  // §4.3 culling needs the caster set in clusters; ids (§4.2) are positions
  // in the uploaded order, so the order is settled before anything is drawn
  frame.Casters->EnsureClusters();
  std::string error;
  if (!frame.Casters->ReadyProgram(frame.Window, error))
  {
    vtkErrorWithObjectMacro(frame.Reporter, << error);
  }
}

vtkOpenGLVertexArrayObject* ASMSolver::ReadyVAO(
  SolverFrame& frame, vtkShaderProgram* p, vtkSmartPointer<vtkOpenGLVertexArrayObject>& vao, unsigned long& uploads)
{
  if (!vao)
  {
    vao = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
    uploads = 0;
  }
  const CasterSet& casters = *frame.Casters;
  if (uploads != casters.GetUploads())
  {
    vao->Bind();
    vao->RemoveAttributeArray("vertexRel");
    const bool ok =
      vao->AddAttributeArray(p, casters.GetVertexBuffer(), "vertexRel", 0, 3 * sizeof(float), VTK_FLOAT, 3, false);
    vao->Release();
    if (!ok)
    {
      return nullptr;
    }
    uploads = casters.GetUploads();
  }
  return vao;
}

//------------------------------------------------------------------------------
// The light's views and roots
ASMSolver::LightState* ASMSolver::Prepare(SolverFrame& frame, const ShadowLight& light)
{
  LightState* ls = nullptr;
  for (auto& l : this->Lights)
  {
    ls = l->Light == light.Light ? l.get() : ls;
  }
  if (!ls)
  {
    this->Lights.emplace_back(new LightState);
    ls = this->Lights.back().get();
    ls->Light = light.Light;
  }
  ls->Current = &light;
  // absolute coordinates: the tree outlives the frame origin (the camera's
  // focal point by default)
  LightFrame absolute = light.Frame;
  absolute.center += frame.State->Origin;
  const CasterSet& casters = *frame.Casters;
  std::ostringstream key;
  key.precision(17);
  key << static_cast<int>(absolute.type) << ':' << absolute.center.x << ',' << absolute.center.y << ','
      << absolute.center.z << ':' << absolute.n.x << ',' << absolute.n.y << ',' << absolute.n.z << ':' << absolute.u.x
      << ',' << absolute.u.y << ',' << absolute.u.z << ':' << casters.Version << ':' << casters.GetUploads() << ':'
      << casters.Receivers.min.x << ',' << casters.Receivers.min.y << ',' << casters.Receivers.min.z << ','
      << casters.Receivers.max.x << ',' << casters.Receivers.max.y << ',' << casters.Receivers.max.z;
  if (key.str() == ls->Key && !ls->Failed)
  {
    return ls;
  }
  for (int v : ls->TreeViews)
  {
    this->Tree.RemoveRoot(v);
  }
  ls->TreeViews.clear();
  ls->Edges.clear();
  ls->EdgesKey.clear();
  ls->Key = key.str();
  std::string error;
  ls->Failed = !this->BuildLight(frame, *ls, absolute, error);
  if (ls->Failed)
  {
    for (int v : ls->TreeViews)
    {
      this->Tree.RemoveRoot(v);
    }
    ls->TreeViews.clear();
    vtkErrorWithObjectMacro(frame.Reporter, << error);
  }
  return ls;
}

bool ASMSolver::BuildLight(SolverFrame& frame, LightState& ls, const LightFrame& absolute, std::string& error)
{
  const CasterSet& casters = *frame.Casters;
  // fitted to the casters' bulk, without a needle to a lost vertex (stop 50)
  ls.Views = MakeASMViews(absolute, casters.Receivers, casters.BulkBounds);
  ls.Clusters = ClusterCounts{};
  const int n = static_cast<int>(ls.Views.views.size());
  const int C = this->Settings.cells;
  ls.CellRanges.assign(static_cast<std::size_t>(n), {});
  ls.DepthScale.assign(static_cast<std::size_t>(n), 1.0);
  Box all = casters.Receivers;
  all.Add(casters.BulkBounds);
  for (int v = 0; v < n; ++v)
  {
    const ShadowView& view = ls.Views.views[static_cast<std::size_t>(v)];
    // a root per view (§3); tree views are reused once free
    int id = 0;
    while (this->Tree.Root(id) >= 0 || std::any_of(this->Lights.begin(), this->Lights.end(), [&](const auto& o) {
             return std::find(o->TreeViews.begin(), o->TreeViews.end(), id) != o->TreeViews.end();
           }))
    {
      ++id;
    }
    if (this->Tree.AddRoot(id, view.extent) < 0)
    {
      std::ostringstream o;
      o << "ASM: the memory budget (ASMMemoryBudget " << this->Opt.MemoryMB << " MB) holds "
        << this->Tree.PageCapacity() << " pages of " << this->Settings.pageSize << "^2 texels; the light needs "
        << n << " root pages and other lights hold " << (this->Tree.UsedPages())
        << " (raise the budget or lower ASMPageSize). This light is unshadowed.";
      error = o.str();
      return false;
    }
    ls.TreeViews.push_back(id);
    // the light-space depth range of everything (fixed-point depths, §4.2),
    // at most 4 times the casters' bulk's: a receiver beyond clamps to the
    // largest depth, still behind every caster. From everything, a receiver
    // sliver to a vertex at 1e10 left 2.3 units a step, and the scene's
    // shadows were gone (stop 50).
    double zMax = 0.0, zCasters = 0.0;
    for (int c = 0; c < 8; ++c)
    {
      zMax = std::max(zMax, view.ToLightSpace(all.Corner(c)).z);
      if (!casters.BulkBounds.Empty())
      {
        zCasters = std::max(zCasters, view.ToLightSpace(casters.BulkBounds.Corner(c)).z);
      }
    }
    if (zCasters > 0.0)
    {
      zMax = std::min(zMax, 4.0 * zCasters);
    }
    ls.DepthScale[static_cast<std::size_t>(v)] = 1.0 / std::max(zMax * 1.01, 1e-30);
    // §4.3: "we use frustum culling for each cell in the topmost level of the
    // hierarchy": the caster clusters that reach each top-level cell
    auto& ranges = ls.CellRanges[static_cast<std::size_t>(v)];
    const int root = this->Tree.Root(id);
    for (int cell = 0; cell < C * C; ++cell)
    {
      ranges.push_back(casters.HasClusters() && this->Opt.Culling
          ? VisibleTriangleRanges(
              casters.Clusters, view, casters.Origin, this->Tree.CellWindow(root, cell), 1e-3, &ls.Clusters)
          : TriangleRanges{ { 0, casters.NumberOfTriangles() } });
    }
    ranges.push_back(casters.HasClusters() && this->Opt.Culling
        ? VisibleTriangleRanges(casters.Clusters, view, casters.Origin, view.extent, 1e-3, &ls.Clusters)
        : TriangleRanges{ { 0, casters.NumberOfTriangles() } });
  }
  if (!this->Cost.calibrated && n > 0)
  {
    this->Calibrate(frame, ls);
  }
  const int P = this->Settings.pageSize;
  for (int v = 0; v < n; ++v)
  {
    const int root = this->Tree.Root(ls.TreeViews[static_cast<std::size_t>(v)]);
    this->RenderNode(frame, ls, v, this->Tree.Node(root).window, -1, P, this->Tree.Node(root).page);
    this->Tree.SetResolution(root, P);
    ++this->Stats->roots;
  }
  return true;
}

// §3.1: "We perform a calibration test as a preprocess to evaluate a (the
// per-pixel rendering cost) and b (the constant overhead)": the first light's
// first view rendered at three resolutions, three times each (the fastest of
// each counts), into the scratch target and the root's page, timed with
// glFinish, then a least-squares line through them.
void ASMSolver::Calibrate(SolverFrame& frame, LightState& ls)
{
  const auto t0 = Clock::now();
  const int P = this->Settings.pageSize;
  const int root = this->Tree.Root(ls.TreeViews.front());
  std::vector<std::pair<double, double>> samples;
  glFinish();
  for (int res : { std::max(8, P / 4), std::max(8, P / 2), P })
  {
    double best = 1e300;
    for (int rep = 0; rep < 3; ++rep)
    {
      const auto a = Clock::now();
      this->RenderNode(frame, ls, 0, this->Tree.Node(root).window, -1, res, this->Tree.Node(root).page);
      glFinish();
      best = std::min(best, Milliseconds(a, Clock::now()));
    }
    samples.emplace_back(double(res) * res, best);
  }
  this->Cost = FitCostModel(samples);
  this->CalibrationMs = Milliseconds(t0, Clock::now());
}

// A node's piece of shadow map: the caster clusters of its top-level cell
// drawn into the scratch target at `res`^2 over `window`, then copied into
// its page of the atlas; then its summary: the same casters rasterised
// conservatively (PVSM's program, min-blended) at one texel per block, so a
// caster thinner than a texel still marks its blocks (asm.md, "thin casters").
void ASMSolver::RenderNode(
  SolverFrame& frame, const LightState& ls, int view, const Rect& window, int topCell, int res, int page)
{
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkOpenGLState* ostate = win->GetState();
  const CasterSet& casters = *frame.Casters;
  static const std::string vs = NodeVertexShader();
  this->NodeProgram = win->GetShaderCache()->ReadyShaderProgram(vs.c_str(), ssASMNodeFS, "");
  vtkOpenGLVertexArrayObject* vao =
    this->NodeProgram ? this->ReadyVAO(frame, this->NodeProgram, this->NodeVAO, this->NodeVAOUploads) : nullptr;
  if (!vao)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "ASM: could not build the node program.");
    return;
  }
  const auto& cellRanges = ls.CellRanges[static_cast<std::size_t>(view)];
  const TriangleRanges& ranges = (topCell >= 0) ? cellRanges[static_cast<std::size_t>(topCell)] : cellRanges.back();
  for (const auto& r : ranges)
  {
    this->Stats->trianglesDrawn += static_cast<double>(r.second);
  }
  const ShadowView rel = Relative(ls.Views.views[static_cast<std::size_t>(view)], frame.State->Origin);
  const glm::dvec3 offset = casters.Origin - frame.State->Origin;
  vtkOpenGLState::ScopedglDepthFunc depthFunc(ostate);
  const unsigned int far[4] = { 0xFFFFFFFFu, 0u, 0u, 0u };
  this->Tex.BeginCleared(win, this->Tex.Scratch, this->Tex.ScratchDepth, res, res, far);
  ostate->vtkglDisable(GL_BLEND);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglEnable(GL_DEPTH_TEST);
  ostate->vtkglDepthMask(GL_TRUE);
  ostate->vtkglDepthFunc(GL_LESS);
  this->NodeProgram->SetUniformf("depthScale", static_cast<float>(ls.DepthScale[static_cast<std::size_t>(view)]));
  casters.Draw(this->NodeProgram, vao, rel, window, offset, &ranges);
  this->Tex.CopyScratchToPage(page, res);
  this->Tex.End(win);
  ostate->vtkglDisable(GL_DEPTH_TEST);

  // the summary
  const int block = this->Settings.summaryBlock;
  const int sres = std::max(1, res / block);
  this->SummaryProgram = win->GetShaderCache()->ReadyShaderProgram(ssCasterVS, ssConservativeFS, ssConservativeGS);
  vtkOpenGLVertexArrayObject* svao =
    this->SummaryProgram ? this->ReadyVAO(frame, this->SummaryProgram, this->SummaryVAO, this->SummaryVAOUploads)
                         : nullptr;
  if (!svao)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "ASM: could not build the conservative summary program.");
    return;
  }
  this->Tex.Begin(win, this->Tex.SummaryScratch, -1, 0);
  ostate->vtkglViewport(0, 0, sres, sres);
  ostate->vtkglScissor(0, 0, sres, sres);
  const GLfloat farDepth[4] = { 3.0e38f, 3.0e38f, 3.0e38f, 3.0e38f };
  glClearBufferfv(GL_COLOR, 0, farDepth);
  ostate->vtkglEnable(GL_BLEND);
  ostate->vtkglBlendEquation(GL_MIN);
  ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
  const float vp[2] = { static_cast<float>(sres), static_cast<float>(sres) };
  this->SummaryProgram->SetUniform2f("viewportSize", vp);
  casters.Draw(this->SummaryProgram, svao, rel, window, offset, &ranges);
  ostate->vtkglBlendEquation(GL_FUNC_ADD);
  ostate->vtkglDisable(GL_BLEND);
  this->Tex.CopyScratchToPage(page, sres, true);
  this->Tex.End(win);
}

//------------------------------------------------------------------------------
// §4.2 / §5: the camera's view of the caster set with triangle ids
void ASMSolver::IdPass(SolverFrame& frame)
{
  const auto t0 = Clock::now();
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkOpenGLState* ostate = win->GetState();
  const CasterSet& casters = *frame.Casters;
  const int W = frame.State->Width, H = frame.State->Height;
  this->IdProgram = win->GetShaderCache()->ReadyShaderProgram(ssASMIdVS, ssASMIdFS, "");
  vtkOpenGLVertexArrayObject* vao =
    this->IdProgram ? this->ReadyVAO(frame, this->IdProgram, this->IdVAO, this->IdVAOUploads) : nullptr;
  vtkOpenGLState::ScopedglDepthFunc depthFunc(ostate);
  const unsigned int zero[4] = { 0u, 0u, 0u, 0u };
  this->Tex.BeginCleared(win, this->Tex.Ids, this->Tex.IdDepth, W, H, zero);
  if (vao && casters.NumberOfTriangles() > 0)
  {
    vtkCamera* cam = frame.Renderer->GetActiveCamera();
    vtkNew<vtkMatrix4x4> relToClip, shift;
    shift->Identity();
    for (int r = 0; r < 3; ++r)
    {
      shift->SetElement(r, 3, frame.State->Origin[r]);
    }
    vtkMatrix4x4::Multiply4x4(
      cam->GetCompositeProjectionTransformMatrix(frame.Renderer->GetTiledAspectRatio(), -1, 1), shift, relToClip);
    // VTK's row-major storage goes to GL as column-major: transpose
    relToClip->Transpose();
    const glm::vec3 offset(casters.Origin - frame.State->Origin), eye(frame.State->Eye);
    double dop[3];
    cam->GetDirectionOfProjection(dop);
    const glm::vec3 dir(static_cast<float>(dop[0]), static_cast<float>(dop[1]), static_cast<float>(dop[2]));
    this->IdProgram->SetUniform3f("casterOffset", glm::value_ptr(offset));
    this->IdProgram->SetUniformMatrix("relToClip", relToClip);
    this->IdProgram->SetUniform3f("eyeRel", glm::value_ptr(eye));
    this->IdProgram->SetUniform3f("viewDir", glm::value_ptr(dir));
    this->IdProgram->SetUniformf("camDepthScale", static_cast<float>(1.0 / (cam->GetClippingRange()[1] * 2.0)));
    ostate->vtkglDisable(GL_BLEND);
    ostate->vtkglDisable(GL_CULL_FACE);
    ostate->vtkglEnable(GL_DEPTH_TEST);
    ostate->vtkglDepthMask(GL_TRUE);
    ostate->vtkglDepthFunc(GL_LESS);
    vao->Bind();
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(3 * casters.NumberOfTriangles()));
    vao->Release();
    ostate->vtkglDisable(GL_DEPTH_TEST);
  }
  else if (!vao)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "ASM: could not build the triangle-id program; depth tests only.");
  }
  this->Tex.End(win);
  frame.Timings->Finish();
  this->Stats->msIds += Milliseconds(t0, Clock::now());
}

std::string ASMSolver::ViewKey(SolverFrame& frame, const LightState& ls) const
{
  return FrameSignature(frame.Renderer, *frame.State, *frame.Casters, 0) + '|' + ls.Key + '|' +
    std::to_string(this->Tree.Version()) + '|' + (this->Opt.IDTest ? "id" : "depth");
}

// The queries (§3): V of every pixel into the light's layer, and the edge
// flags read back for the next analysis.
void ASMSolver::QueryPass(SolverFrame& frame, LightState& ls, const std::string& edgesKey)
{
  const auto t0 = Clock::now();
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkOpenGLState* ostate = win->GetState();
  const ShadowLight& light = *ls.Current;
  const int W = frame.State->Width, H = frame.State->Height;
  this->Tex.UploadNodeTable(this->Tree, QueryGLLimits().maxTextureSize);
  vtkShaderProgram* prog = ReadyQuad(this->QueryQuad, win, ssASMQueryFS);
  if (!prog)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "ASM: could not build the query program.");
    return;
  }
  // the visibility layer on attachment 0, the edge flags on 1
  this->Tex.Begin(win, 0, -1, 0);
  frame.Visibility->Attach(this->Tex.FBO, light.Layer);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, this->Tex.Edges, 0);
  this->Tex.FBO->ActivateDrawBuffers(2);
  ostate->vtkglViewport(0, 0, W, H);
  ostate->vtkglScissor(0, 0, W, H);
  ostate->vtkglDisable(GL_BLEND);
  ostate->vtkglDisable(GL_DEPTH_TEST);
  GBuffer& g = *frame.GBuffer;
  g.Position->Activate();
  g.Normal->Activate();
  g.GeometricNormal->Activate();
  const int idUnit = ASMTextures::Bind(win, GL_TEXTURE_2D, this->Tex.Ids);
  const int atlasUnit = ASMTextures::Bind(win, GL_TEXTURE_2D_ARRAY, this->Tex.Atlas);
  const int summaryUnit = ASMTextures::Bind(win, GL_TEXTURE_2D_ARRAY, this->Tex.Summary);
  const int nodeUnit = ASMTextures::Bind(win, GL_TEXTURE_2D, this->Tex.Nodes);
  prog->SetUniformi("gPosition", g.Position->GetTextureUnit());
  prog->SetUniformi("gNormal", g.Normal->GetTextureUnit());
  prog->SetUniformi("gGeomNormal", g.GeometricNormal->GetTextureUnit());
  prog->SetUniformi("idImage", idUnit);
  prog->SetUniformi("atlas", atlasUnit);
  prog->SetUniformi("summary", summaryUnit);
  prog->SetUniformi("summaryBlock", this->Settings.summaryBlock);
  prog->SetUniformi("nodeTable", nodeUnit);
  prog->SetUniformi("nodeWidth", this->Tex.NodeWidth);
  prog->SetUniformi("nodesPerRow", this->Tex.NodesPerRow);
  prog->SetUniformi("cells", this->Settings.cells);
  const ASMLightViews& lv = ls.Views;
  const int nv = std::min(6, static_cast<int>(lv.views.size()));
  float U[6][3] = {}, V[6][3] = {}, N[6][3] = {}, O[6][3] = {}, E[6][4] = {}, S[6] = {};
  int roots[6] = { 0, 0, 0, 0, 0, 0 };
  for (int i = 0; i < nv; ++i)
  {
    const ShadowView r = Relative(lv.views[static_cast<std::size_t>(i)], frame.State->Origin);
    for (int c = 0; c < 3; ++c)
    {
      U[i][c] = static_cast<float>(r.u[c]);
      V[i][c] = static_cast<float>(r.v[c]);
      N[i][c] = static_cast<float>(r.n[c]);
      O[i][c] = static_cast<float>(r.origin[c]);
    }
    E[i][0] = static_cast<float>(r.extent.x0);
    E[i][1] = static_cast<float>(r.extent.y0);
    E[i][2] = static_cast<float>(r.extent.x1);
    E[i][3] = static_cast<float>(r.extent.y1);
    S[i] = static_cast<float>(ls.DepthScale[static_cast<std::size_t>(i)]);
    roots[i] = this->Tree.Root(ls.TreeViews[static_cast<std::size_t>(i)]);
  }
  prog->SetUniformi("numViews", nv);
  prog->SetUniform3fv("viewU", nv, U);
  prog->SetUniform3fv("viewV", nv, V);
  prog->SetUniform3fv("viewN", nv, N);
  prog->SetUniform3fv("viewOrigin", nv, O);
  prog->SetUniform4fv("viewExtent", nv, E);
  prog->SetUniform1iv("viewRoot", nv, roots);
  prog->SetUniform1fv("viewDepthScale", nv, S);
  prog->SetUniformi("orthographic", lv.Orthographic() ? 1 : 0);
  prog->SetUniform1iv("faceView", 6, lv.faceView);
  float axes[3][3];
  for (int a = 0; a < 3; ++a)
  {
    for (int c = 0; c < 3; ++c)
    {
      axes[a][c] = static_cast<float>(lv.axes[a][c]);
    }
  }
  prog->SetUniform3fv("cubeAxes", 3, axes);
  const glm::vec3 center(lv.center - frame.State->Origin), facing(lv.facing), eye(frame.State->Eye);
  prog->SetUniform3f("lightCenter", glm::value_ptr(center));
  prog->SetUniform3f("facing", glm::value_ptr(facing));
  prog->SetUniformi("useIdTest", this->Opt.IDTest ? 1 : 0);
  prog->SetUniformf("constantBias", static_cast<float>(this->Opt.ConstantBias));
  prog->SetUniformf("slopeBias", static_cast<float>(this->Opt.SlopeBias));
  vtkCamera* cam = frame.Renderer->GetActiveCamera();
  double dop[3];
  cam->GetDirectionOfProjection(dop);
  const glm::vec3 dir(static_cast<float>(dop[0]), static_cast<float>(dop[1]), static_cast<float>(dop[2]));
  prog->SetUniform3f("eyeRel", glm::value_ptr(eye));
  prog->SetUniform3f("viewDir", glm::value_ptr(dir));
  prog->SetUniformf("camDepthScale", static_cast<float>(1.0 / (cam->GetClippingRange()[1] * 2.0)));
  this->QueryQuad->Render();
  this->Tex.ReadEdges(ls.Edges);
  ls.EdgesKey = edgesKey;
  ASMTextures::Unbind(win, GL_TEXTURE_2D, nodeUnit);
  ASMTextures::Unbind(win, GL_TEXTURE_2D_ARRAY, summaryUnit);
  ASMTextures::Unbind(win, GL_TEXTURE_2D_ARRAY, atlasUnit);
  ASMTextures::Unbind(win, GL_TEXTURE_2D, idUnit);
  g.GeometricNormal->Deactivate();
  g.Normal->Deactivate();
  g.Position->Deactivate();
  TextureArray::Detach();
  this->Tex.End(win);
  frame.Timings->Finish();
  this->Stats->msQueries += Milliseconds(t0, Clock::now());
  ++this->Stats->queryPasses;
}

void ASMSolver::WriteUnshadowed(SolverFrame& frame, const ShadowLight& light)
{
  const std::vector<float>*positions, *normals;
  frame.GBuffer->ReadForCPU(frame.Window, frame.FBO, frame.State->Width, frame.State->Height, positions, normals);
  std::vector<float> V(positions->size() / 3);
  for (std::size_t i = 0; i < V.size(); ++i)
  {
    V[i] = std::isnan((*positions)[3 * i]) ? NAN : 1.0f;
  }
  frame.Visibility->Upload(light.Layer, V);
}

//------------------------------------------------------------------------------
void ASMSolver::Compute(SolverFrame& frame, const ShadowLight& light)
{
  FrameStats& st = *this->Stats;
  ++st.lights;
  if (!this->EnsureResources(frame))
  {
    this->WriteUnshadowed(frame, light);
    return;
  }
  LightState* ls = this->Prepare(frame, light);
  if (ls->Failed)
  {
    this->WriteUnshadowed(frame, light);
    return;
  }
  if (!this->IdsDone)
  {
    this->IdPass(frame);
    this->IdsDone = true;
  }
  // §3.1: the eye pixels in light space, with their exact footprints (§4.1's
  // mip-map estimate replaced)
  auto t0 = Clock::now();
  if (!this->PositionsRead)
  {
    const std::vector<float>* normals;
    frame.GBuffer->ReadForCPU(frame.Window, frame.FBO, frame.State->Width, frame.State->Height, this->Positions, normals);
    this->PositionsRead = true;
  }
  ASMProjectPixels(ls->Views, this->Positions->data(), frame.State->Origin, frame.State->Width, frame.State->Height,
    ls->Pixels);
  st.msAnalysis += Milliseconds(t0, Clock::now());
  // the edge flags of the current tree at this view
  const std::string key = this->ViewKey(frame, *ls);
  if (ls->EdgesKey != key)
  {
    this->QueryPass(frame, *ls, key);
  }
  t0 = Clock::now();
  ASMAnalysisOptions opt;
  opt.stride = this->Opt.AnalysisStride;
  opt.width = frame.State->Width;
  opt.frame = this->Frame;
  opt.quality = this->Opt.Quality;
  opt.cost = this->Cost;
  ASMAnalysisStats a;
  std::vector<ASMCandidate> c = ASMAnalyze(this->Tree, ls->Pixels, ls->Edges, opt, a);
  AddAnalysis(st.analysis, a);
  this->Pending.insert(this->Pending.end(), c.begin(), c.end());
  st.msAnalysis += Milliseconds(t0, Clock::now());
}

void ASMSolver::EndFrame(SolverFrame& frame)
{
  if (!this->Active)
  {
    return;
  }
  FrameStats& st = *this->Stats;
  // §3.1: "the cells are sorted according to this ratio ... new shadow map
  // nodes are only generated for the most profitable cells from this list
  // until a given time limit has passed" (all lights' cells together: they
  // share the budget)
  std::stable_sort(this->Pending.begin(), this->Pending.end(),
    [](const ASMCandidate& a, const ASMCandidate& b) { return a.Priority() > b.Priority(); });
  st.candidates = static_cast<int>(this->Pending.size());
  if (!this->Pending.empty())
  {
    glFinish(); // the clock measures node creation only, not the queries queued before it
  }
  const auto t0 = Clock::now();
  ASMRefiner refiner(this->Tree, std::move(this->Pending), this->Frame);
  this->Pending.clear();
  ASMAction a;
  bool work = false;
  if (this->Tex.Atlas)
  {
    while (Milliseconds(t0, Clock::now()) < this->Opt.TimeBudgetMs && refiner.Next(a))
    {
      const ASMNode& n = this->Tree.Node(a.node);
      const LightState* owner = nullptr;
      int view = -1;
      for (const auto& ls : this->Lights)
      {
        for (std::size_t v = 0; v < ls->TreeViews.size(); ++v)
        {
          if (ls->TreeViews[v] == n.view)
          {
            owner = ls.get();
            view = static_cast<int>(v);
          }
        }
      }
      if (!owner)
      {
        continue;
      }
      // the node's top-level cell: its ancestor at level 1 (§4.3 culling)
      int top = a.node;
      while (top >= 0 && this->Tree.Node(top).level > 1)
      {
        top = this->Tree.Node(top).parent;
      }
      const int topCell = (top >= 0 && this->Tree.Node(top).level == 1) ? this->Tree.Node(top).cell : -1;
      this->RenderNode(frame, *owner, view, n.window, topCell, a.resolution, n.page);
      // the time spent is the GPU's too (§3.1's cost is a render and read-back)
      glFinish();
      this->Tree.SetResolution(a.node, a.resolution);
      work = true;
      st.created += a.upgrade ? 0 : 1;
      st.upgraded += a.upgrade ? 1 : 0;
      st.evictedLRU += a.evictedLRU;
      st.replaced += a.replaced;
      st.predictedMs += a.predictedMs;
    }
  }
  st.creationMs = Milliseconds(t0, Clock::now());
  st.msCreation += st.creationMs;
  st.remaining = refiner.Remaining();
  st.skipped = refiner.SkippedForMemory();
  // a still view keeps refining until a whole cycle of the analysed pixel
  // set (the stride) found nothing to do
  this->FramesWithoutWork = (work || st.remaining > 0) ? 0 : this->FramesWithoutWork + 1;
  this->Refining = this->FramesWithoutWork < std::max(1, this->Opt.AnalysisStride);

  // the queries of every light with the refined tree
  for (auto& ls : this->Lights)
  {
    if (ls->Current && !ls->Failed)
    {
      this->QueryPass(frame, *ls, this->ViewKey(frame, *ls));
    }
    ls->Current = nullptr;
  }
  frame.Timings->Set("asm_id_pass", st.msIds);
  frame.Timings->Set("asm_analysis", st.msAnalysis);
  frame.Timings->Set("asm_node_creation", st.msCreation);
  frame.Timings->Set("asm_queries", st.msQueries);
  ClusterCounts clusters;
  for (const auto& ls : this->Lights)
  {
    clusters.drawn += ls->Clusters.drawn;
    clusters.culled += ls->Clusters.culled;
  }
  st.clusters = frame.Casters->ClusterStatsJSON(clusters);
  *this->LastStats = st;
}

//------------------------------------------------------------------------------
std::string ASMSolver::GetStatsJSON() const
{
  const FrameStats& s = *this->LastStats;
  const ASMTree& t = this->Tree;
  std::vector<int> perLevel;
  int maxLevel = 0;
  for (int id = 0; id < t.NodeSlots(); ++id)
  {
    if (t.Alive(id))
    {
      const int l = t.Node(id).level;
      perLevel.resize(std::max<std::size_t>(perLevel.size(), static_cast<std::size_t>(l) + 1), 0);
      ++perLevel[static_cast<std::size_t>(l)];
      maxLevel = std::max(maxLevel, l);
    }
  }
  const ASMAnalysisStats& a = s.analysis;
  const double lookups = static_cast<double>(a.cacheHits + a.cacheMisses);
  std::ostringstream o;
  o.precision(10);
  o << "{\"lights\": " << s.lights << ", \"memory_budget_bytes\": " << this->BudgetBytes
    << ", \"memory_used_bytes\": " << t.UsedBytes() << ", \"page_size\": " << this->Settings.pageSize
    << ", \"cells\": " << this->Settings.cells << ", \"max_depth\": " << this->Settings.maxDepth
    << ", \"pages\": {\"capacity\": " << t.PageCapacity() << ", \"used\": " << t.UsedPages() << "}"
    << ", \"atlas\": {\"width\": " << this->Tex.Layout.Width(this->Tex.PageSize)
    << ", \"height\": " << this->Tex.Layout.Height(this->Tex.PageSize) << ", \"layers\": " << this->Tex.Layout.layers
    << ", \"capped_by_gl\": " << (this->Tex.Layout.capped ? "true" : "false") << ", \"bytes\": " << this->Tex.AtlasBytes()
    << ", \"note\": \"" << this->AtlasNote << "\"}, \"nodes\": " << t.LiveNodes() << ", \"nodes_per_level\": [";
  for (std::size_t l = 0; l < perLevel.size(); ++l)
  {
    o << (l ? ", " : "") << perLevel[l];
  }
  o << "], \"deepest_level\": " << maxLevel << ", \"effective_resolution\": " << a.maxEffectiveResolution
    << ", \"frame\": " << this->Frame << ", \"refining\": " << (this->Refining ? "true" : "false")
    << ", \"id_test\": " << (this->Opt.IDTest ? "true" : "false") << ", \"time_budget_ms\": " << this->Opt.TimeBudgetMs
    << ", \"cost_model\": {\"a_ms_per_texel\": " << this->Cost.a << ", \"b_ms\": " << this->Cost.b
    << ", \"calibrated\": " << (this->Cost.calibrated ? "true" : "false")
    << ", \"calibration_ms\": " << this->CalibrationMs << "}"
    << ", \"this_frame\": {\"roots_built\": " << s.roots << ", \"candidates\": " << s.candidates
    << ", \"created\": " << s.created << ", \"upgraded\": " << s.upgraded << ", \"evicted_lru\": " << s.evictedLRU
    << ", \"replaced\": " << s.replaced << ", \"skipped_for_memory\": " << s.skipped
    << ", \"left_for_next_frame\": " << s.remaining << ", \"predicted_ms\": " << s.predictedMs
    << ", \"creation_ms\": " << s.creationMs << ", \"triangles_drawn\": " << s.trianglesDrawn
    << ", \"query_passes\": " << s.queryPasses << "}"
    << ", \"cell_clusters\": " << (s.clusters.empty() ? "null" : s.clusters)
    << ", \"analysis\": {\"pixels\": " << a.pixels << ", \"sampled\": " << a.sampled << ", \"edges\": " << a.edges
    << ", \"mismatched\": " << a.mismatched << ", \"unresolvable\": " << a.unresolvable
    << ", \"leaves_used\": " << a.leavesUsed << ", \"leaf_cache_hit_rate\": " << (lookups > 0 ? a.cacheHits / lookups : 0.0)
    << "}, \"ms\": {\"id_pass\": " << s.msIds << ", \"cost_benefit\": " << s.msAnalysis
    << ", \"node_creation\": " << s.msCreation << ", \"queries\": " << s.msQueries << "}}";
  return o.str();
}

long long ASMSolver::GetMemoryBytes() const
{
  return this->Tex.Bytes();
}

int ASMSolver::GetNumberOfGraphicsResources() const
{
  int vaos = 0;
  for (const auto* vao : { &this->NodeVAO, &this->IdVAO, &this->SummaryVAO })
  {
    vaos += *vao ? 1 : 0;
  }
  return this->Tex.CountGraphicsResources() + (this->QueryQuad ? 1 : 0) + vaos;
}

void ASMSolver::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Reset();
  this->Tex.ReleaseGraphicsResources(w);
  ReleaseQuad(this->QueryQuad, w);
  // every vertex array (the summary's too: until stop 46 it outlived the
  // context, and a renderer moved to a new window drew through a stale name)
  for (auto* vao : { &this->NodeVAO, &this->IdVAO, &this->SummaryVAO })
  {
    if (*vao)
    {
      (*vao)->ReleaseGraphicsResources();
      *vao = nullptr;
    }
  }
  this->NodeVAOUploads = this->IdVAOUploads = this->SummaryVAOUploads = 0;
  this->NodeProgram = nullptr;
  this->IdProgram = nullptr;
  this->SummaryProgram = nullptr;
  this->Refining = false;
}
}
