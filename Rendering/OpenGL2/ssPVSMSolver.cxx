#include "ssPVSMSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssBlockerSearchWindow.h"
#include "ssCasterSet.h"
#include "ssConservativeMap.h"
#include "ssFrameState.h"
#include "ssFullScreenQuad.h"
#include "ssGBuffer.h"
#include "ssGLLimits.h"
#include "ssPVSMTileReads.h"
#include "ssPassStats.h"
#include "ssShadowMaps.h"
#include "ssShadowViews.h"
#include "ssVisibilityLayers.h"

#include "ssCasterVS.h"
#include "ssConservativeFS.h"
#include "ssConservativeGS.h"
#include "ssPVSMFilterFS.h"
#include "ssPVSMGridFS.h"
#include "ssPVSMGridVS.h"
#include "ssPVSMKernelFS.h"
#include "ssPVSMResolveFS.h"

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

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ss
{
namespace
{
// The filter's quad levels of a tile (its uniform tileLevels): its pyramid's
// levels down to one texel along its longer side.
int TileLevels(const ShadowTile& tile, int arrayLevels)
{
  int levels = 1;
  while ((std::max(tile.resX, tile.resY) >> levels) > 0 && levels < arrayLevels)
  {
    ++levels;
  }
  return levels;
}
}

PVSMSolver::PVSMSolver(Method method)
  : VisibilitySolver(method)
{
}

PVSMSolver::~PVSMSolver() = default;

const OptionList& PVSMSolver::DeclaredOptions()
{
  // key, property (Python, ParaView), label, range or names, default, help
  static const OptionList options = {
    DoubleOption("pvsm_quality", "PVSMQuality", "PVSM Quality", 0.05, 64.0, 1.0,
      "pvsm: scale on the perceptual metric rho (section 5.1): 2 asks about twice the texels per "
      "kernel (slower, finer penumbrae), 0.5 half"),
    EnumOption("pvsm_metric", "PVSMMetric", "PVSM Metric", { "auto", "dynamic", "static" }, 0,
      "pvsm: which metric of section 5.1 (auto: static when only the camera moved)"),
    IntOption("pvsm_grid", "PVSMGridSize", "PVSM Grid Size", 4, 256, 64, "pvsm: shadow-map tile grid"),
    IntOption("pvsm_max_tile", "PVSMMaxTileResolution", "PVSM Max Tile Resolution", 64, 16384, 4096,
      "pvsm: largest tile, texels a side"),
    IntOption("pvsm_low_resolution", "PVSMLowResolution", "PVSM Low Resolution", 64, 8192, 1024,
      "pvsm: conservative low-resolution map"),
    BoolOption("pvsm_tile_culling", "PVSMTileCulling", "PVSM Tile Culling", true,
      "pvsm: draw only the caster clusters reaching a tile"),
    BoolOption("pvsm_map_culling", "PVSMMapCulling", "PVSM Map Culling", true,
      "pvsm: draw into the conservative low-resolution map only the caster clusters reaching the texels "
      "the visible receivers' blocker searches read"),
    BoolOption("pvsm_tile_regions", "PVSMTileRegions", "PVSM Tile Regions", true,
      "pvsm: clear, draw and reduce each tile only where the pixels whose kernel reaches it read it, filter "
      "only over those pixels, and skip a tile no pixel reaches"),
    EnumOption("pvsm_map_raster", "PVSMMapRaster", "PVSM Map Raster", { "auto", "gpu", "cpu" }, 0,
      "pvsm: who rasterises the conservative low-resolution map: the GPU (a geometry shader) or the CPU "
      "(the same texels, multithreaded, uploaded); auto: the CPU on software GL such as llvmpipe when the map "
      "has at least a triangle for 8 of its texels"),
  };
  return options;
}

void PVSMSolver::Configure(vtkSoftShadowPass* pass)
{
  const auto opt = [pass](const char* key) { return static_cast<int>(pass->GetSolverOption(key)); };
  this->Opt.LowResolution = opt("pvsm_low_resolution");
  this->Opt.GridSize = opt("pvsm_grid");
  this->Opt.MaxTileResolution = opt("pvsm_max_tile");
  this->Opt.Quality = pass->GetSolverOption("pvsm_quality");
  this->Opt.Metric = opt("pvsm_metric");
  this->Opt.TileCulling = opt("pvsm_tile_culling") != 0;
  this->Opt.MapCulling = opt("pvsm_map_culling") != 0;
  this->Opt.TileRegions = opt("pvsm_tile_regions") != 0;
  this->Opt.MapRaster = opt("pvsm_map_raster");
  this->Opt.BlockerSearchSamples = opt("blocker_samples");
  this->Opt.FilterMaxQuads = opt("filter_max_quads");
  this->Opt.ConstantBias = pass->GetConstantBias();
  this->Opt.NormalOffset = pass->GetNormalOffset();
}

void PVSMSolver::BeginFrame(SolverFrame& frame, const std::vector<const ShadowLight*>& lights)
{
  this->Lights = 0;
  this->Active = !lights.empty();
  if (!this->Active)
  {
    this->LastStats = PVSMStats{};
    this->LastClustersJSON.clear();
    this->LastMapClustersJSON.clear();
    return;
  }
  this->Stats = PVSMStats{};
  this->Stats.quality = this->Opt.Quality;
  this->TileClusters = ClusterCounts{};
  this->MapClusters = ClusterCounts{};
  // §5.1: the static metric when only the camera moved since the last frame:
  // the same caster set and the same lights (a light that follows the camera
  // moves with it, so its transformed position is part of the key)
  std::ostringstream key;
  key.precision(9);
  key << frame.Casters->Version;
  for (const auto& l : frame.State->Lights)
  {
    key << ';' << l.Light << ':' << l.Light->GetMTime() << ':' << l.Layer;
    if (!l.Light->LightTypeIsSceneLight())
    {
      double p[3], f[3];
      l.Light->GetTransformedPosition(p);
      l.Light->GetTransformedFocalPoint(f);
      key << ':' << p[0] << ',' << p[1] << ',' << p[2] << ',' << f[0] << ',' << f[1] << ',' << f[2];
    }
  }
  const bool changed = key.str() != this->SceneKey;
  this->SceneKey = key.str();
  const PerceptualMetric metric = ChooseMetric(this->Opt.Metric, changed);
  this->Stats.metric = PerceptualMetricName(metric);
  double rc[4];
  PerceptualRhoCubic(metric, rc, this->RhoEnd);
  for (int i = 0; i < 4; ++i)
  {
    this->RhoCoeffs[i] = static_cast<float>(rc[i]);
  }
}

void PVSMSolver::PrepareCasters(CasterSet& casters)
{
  if (this->Opt.TileCulling || this->Opt.MapCulling)
  {
    casters.EnsureClusters();
  }
}

vtkShaderProgram* PVSMSolver::ReadyConservativeProgram(SolverFrame& frame)
{
  this->ConservativeProgram =
    frame.Window->GetShaderCache()->ReadyShaderProgram(ssCasterVS, ssConservativeFS, ssConservativeGS);
  if (!this->ConservativeProgram)
  {
    return nullptr;
  }
  if (!this->ConservativeVAO)
  {
    this->ConservativeVAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
    this->ConservativeVAOUploads = 0;
  }
  const CasterSet& casters = *frame.Casters;
  if (this->ConservativeVAOUploads != casters.GetUploads())
  {
    this->ConservativeVAO->Bind();
    this->ConservativeVAO->RemoveAttributeArray("vertexRel");
    const bool ok = this->ConservativeVAO->AddAttributeArray(this->ConservativeProgram, casters.GetVertexBuffer(),
      "vertexRel", 0, 3 * sizeof(float), VTK_FLOAT, 3, false);
    this->ConservativeVAO->Release();
    if (!ok)
    {
      return nullptr;
    }
    this->ConservativeVAOUploads = casters.GetUploads();
  }
  return this->ConservativeProgram;
}

// The triangle ranges of each view's map (empty: every triangle in every view).
std::vector<TriangleRanges> PVSMSolver::MapRanges(SolverFrame& frame, const ShadowLight& light)
{
  // Only what a visible receiver's blocker search reads matters (step 3):
  // the clusters that may reach those texels of each view
  // (ss::BlockerSearchWindows), so the map has the same texels there, and
  // z_avg, the fully-lit test and V are the same, whatever else is left out.
  // The receivers are the frame's visible ones (the points the views were
  // fitted to: the G-buffer's pixels inside the receivers' bounds; pixels of
  // props that receive no shadow are not shaded with V); without them (a
  // tiled frame, fit_views_to_visible off), every G-buffer pixel.
  const CasterSet& casters = *frame.Casters;
  std::vector<TriangleRanges> ranges;
  const float* points = nullptr;
  std::size_t numPoints = 0;
  bool haveReceivers = false;
  if (this->Opt.MapCulling && casters.HasClusters() && !casters.Triangles.empty())
  {
    const std::vector<float>*positions = nullptr, *normals = nullptr;
    if (frame.Visible && frame.Visible->known)
    {
      points = frame.Visible->xyz.data();
      numPoints = frame.Visible->Count();
      haveReceivers = true;
    }
    else if (frame.GBuffer->ReadForCPU(
               frame.Window, frame.FBO, frame.State->Width, frame.State->Height, positions, normals))
    {
      points = positions->data();
      numPoints = positions->size() / 3;
      haveReceivers = true;
    }
  }
  if (haveReceivers)
  {
    BlockerSearchParams bp;
    bp.mapSize = frame.Maps->GetArray().Size;
    bp.levels = frame.Maps->GetArray().Levels;
    bp.searchSamples = this->Opt.BlockerSearchSamples;
    bp.normalOffset = this->Opt.NormalOffset;
    bp.searchDepth = light.SearchDepth;
    if (light.Frame.type == LightType::Rect)
    {
      bp.lightHalfSize = glm::dvec2(0.5 * light.Frame.width, 0.5 * light.Frame.height);
    }
    else if (light.Frame.type == LightType::Directional)
    {
      bp.lightHalfSize = glm::dvec2(std::tan(0.5 * light.Frame.angularDiameter));
    }
    const std::vector<Rect> windows = BlockerSearchWindows(light.Views, bp, points, numPoints);
    const glm::dvec3 offset = casters.Origin - frame.State->Origin;
    for (std::size_t vi = 0; vi < light.Views.size(); ++vi)
    {
      const Rect& w = windows[vi];
      if (w.x0 > w.x1 || w.y0 > w.y1)
      {
        ranges.emplace_back(); // no receiver reads this view
        this->MapClusters.culled += static_cast<double>(casters.Clusters.Clusters());
        continue;
      }
      // the pad (1e-3 of the window) covers the GPU's float projection, as for tiles
      ranges.push_back(VisibleTriangleRanges(casters.Clusters, light.Views[vi], offset, w, 1e-3, &this->MapClusters));
    }
  }
  return ranges;
}

// §5.2 step 2: the low-resolution map of each view is rasterised
// conservatively, so that the blocker search of step 3 misses no thin caster.
void PVSMSolver::DrawShadowMaps(SolverFrame& frame, const ShadowLight& light)
{
  if (light.Views.empty())
  {
    return;
  }
  const CasterSet& casters = *frame.Casters;
  std::vector<TriangleRanges> ranges = this->MapRanges(frame, light);
  // Software GL runs the geometry shader slowly: with many triangles for the
  // map's texels (small ones) the CPU rasterises the same texels faster
  // there; with few large triangles or a large map llvmpipe's rasteriser is
  // faster (ssConservativeMap.h; the sweep in pvsm.md). Decided on the whole
  // caster set, not on what the map culling keeps, so that the choice (and
  // V to the last bit) does not change as the camera moves.
  bool onCPU = this->Opt.MapRaster == 2;
  if (this->Opt.MapRaster == 0 && QueryGLLimits().softwareRenderer)
  {
    const double S = frame.Maps->GetArray().Size;
    onCPU = static_cast<double>(casters.NumberOfTriangles()) >= S * S / 8.0;
  }
  this->MapOnCPU = onCPU;
  if (onCPU)
  {
    const int S = frame.Maps->GetArray().Size;
    std::vector<float> depth(static_cast<std::size_t>(S) * S);
    const glm::dvec3 offset = casters.Origin - frame.State->Origin;
    for (std::size_t vi = 0; vi < light.Views.size(); ++vi)
    {
      ConservativeMinDepthMap(casters.Triangles.data(), casters.NumberOfTriangles(),
        ranges.empty() ? nullptr : &ranges[vi], offset, light.Views[vi], S, depth.data());
      frame.Maps->WriteLayer(frame.Window, light.FirstLayer + static_cast<int>(vi), depth);
    }
    return;
  }
  vtkShaderProgram* p = this->ReadyConservativeProgram(frame);
  vtkOpenGLVertexArrayObject* vao = this->ConservativeVAO;
  if (!p)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "Could not build the conservative rasterisation program.");
    p = frame.Casters->UseProgram(frame.Window);
    vao = frame.Casters->GetVertexArray();
  }
  else
  {
    const float S = static_cast<float>(frame.Maps->GetArray().Size);
    const float vp[2] = { S, S };
    p->SetUniform2f("viewportSize", vp);
  }
  frame.Maps->DrawViews(frame, light, p, vao, ranges.empty() ? nullptr : &ranges);
}

void PVSMSolver::Compute(SolverFrame& frame, const ShadowLight& l)
{
  if (l.Views.empty())
  {
    return;
  }
  vtkOpenGLRenderWindow* win = frame.Window;
  vtkRenderer* ren = frame.Renderer;
  vtkOpenGLFramebufferObject* fbo = frame.FBO;
  vtkOpenGLState* ostate = win->GetState();
  GBuffer& gbuf = *frame.GBuffer;
  const CasterSet& casters = *frame.Casters;
  const TextureArray& maps = frame.Maps->GetArray();
  PVSMStats& st = this->Stats;
  const int W = frame.State->Width, H = frame.State->Height;
  auto finish = [&]() { frame.Timings->Finish(); };

  // resources
  for (auto& k : this->Kernel)
  {
    EnsureTexture2D(win, k, W, H, 4);
  }
  EnsureTexture2D(win, this->Accum, W, H, 4);
  int G = 4;
  while (G < this->Opt.GridSize)
  {
    G *= 2;
  }
  this->GridSide = G;
  this->Grid.Ensure(G, 1);
  const GLint maxTexture = QueryGLLimits().maxTextureSize;
  int tileMax = std::min(this->Opt.MaxTileResolution, static_cast<int>(maxTexture));
  int T = 64;
  while (T < tileMax)
  {
    T *= 2;
  }
  T = std::min(T, static_cast<int>(maxTexture));
  // The size limit is not the memory limit: llvmpipe allows 16384^2 textures
  // but not a 16384^2 RG32F one with its mip levels (2.7 GB). A tile array
  // the context cannot allocate is tried at half the size, down to 64, and
  // the stats and a warning say so (before, the tiles were drawn into no
  // texture: GL errors and wrong shadows).
  T = this->Tile.EnsureFitting(T, 1);
  if (!T)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "PVSM could not allocate a 64 x 64 tile: no shadows from this light.");
    return;
  }
  if (T < tileMax && this->TileWarned != T)
  {
    vtkWarningWithObjectMacro(frame.Reporter, "PVSM tiles of " << tileMax << " x " << tileMax
                                                                << " do not fit this OpenGL context's memory; using "
                                                                << T << " x " << T << ".");
    this->TileWarned = T;
  }
  tileMax = std::min(tileMax, T);
  this->TileUsed = tileMax;
  if (!this->EmptyVAO)
  {
    this->EmptyVAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
  }
  GLfloat pointRange[2] = { 1.0f, 1.0f };
  glGetFloatv(GL_POINT_SIZE_RANGE, pointRange);

  // the camera: clip space -> world relative to the frame origin
  vtkCamera* cam = ren->GetActiveCamera();
  vtkNew<vtkMatrix4x4> relToClip, shift;
  shift->Identity();
  for (int r = 0; r < 3; ++r)
  {
    shift->SetElement(r, 3, frame.State->Origin[r]);
  }
  vtkMatrix4x4::Multiply4x4(
    cam->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1), shift, relToClip);
  vtkNew<vtkMatrix4x4> clipToRel;
  vtkMatrix4x4::Invert(relToClip, clipToRel);
  // SetUniformMatrix hands VTK's row-major storage to GL as column-major:
  // transpose so that GLSL's clipToRel * v is the product above
  clipToRel->Transpose();

  static const std::string kernelFS = WithCommon(ssPVSMKernelFS);
  static const std::string filterFS = WithCommon(ssPVSMFilterFS);
  const glm::dvec3 casterOffset = casters.Origin - frame.State->Origin;
  const float screen[2] = { static_cast<float>(W), static_cast<float>(H) };

  ostate->PushFramebufferBindings();
  fbo->Bind();
  fbo->RemoveDepthAttachment();
  ostate->vtkglDisable(GL_DEPTH_TEST);
  ostate->vtkglDisable(GL_CULL_FACE);
  ostate->vtkglDisable(GL_BLEND);
  auto target = [&](vtkTextureObject* t, int w, int h) {
    fbo->RemoveColorAttachments(3);
    fbo->AddColorAttachment(0, t);
    fbo->ActivateDrawBuffers(1);
    ostate->vtkglViewport(0, 0, w, h);
    ostate->vtkglScissor(0, 0, w, h);
  };
  auto commonUniforms = [&](vtkShaderProgram* p, int shadowUnit) {
    p->SetUniformi("gPosition", gbuf.Position->GetTextureUnit());
    p->SetUniformi("gNormal", gbuf.Normal->GetTextureUnit());
    p->SetUniformi("gGeomNormal", gbuf.GeometricNormal->GetTextureUnit());
    p->SetUniformf("normalOffset", static_cast<float>(this->Opt.NormalOffset));
    p->SetUniformi("shadowMaps", shadowUnit);
    p->SetUniformf("mapSize", static_cast<float>(maps.Size));
    p->SetUniformi("numLevels", maps.Levels);
    p->SetUniformi("searchSamples", this->Opt.BlockerSearchSamples);
    p->SetUniformf("constantBias", static_cast<float>(this->Opt.ConstantBias));
    SetLightUniforms(p, l);
  };
  auto done = [&]() {
    TextureArray::Detach();
    fbo->RemoveColorAttachments(3);
    ostate->PopFramebufferBindings();
    // the host copy of the kernel buffer is needed only while the tiles are
    // made (32 bytes a pixel: 265 MB at 3840 x 2160)
    for (auto& k : this->HostKernel)
    {
      std::vector<float>().swap(k);
    }
  };

  ++this->Lights;
  // --- step 3: kernel-shape buffer (blocker search, footprint, convolution, prediction)
  auto t0 = Clock::now();
  vtkShaderProgram* kp = ReadyQuad(this->KernelQuad, win, kernelFS.c_str());
  if (!kp)
  {
    vtkErrorWithObjectMacro(frame.Reporter, "Could not build the PVSM kernel-shape program.");
    done();
    return;
  }
  gbuf.Position->Activate();
  gbuf.Normal->Activate();
  gbuf.GeometricNormal->Activate();
  int shadowUnit = maps.Bind(win);
  commonUniforms(kp, shadowUnit);
  kp->SetUniformMatrix("clipToRel", clipToRel);
  kp->SetUniform2f("screenSize", screen);
  kp->SetUniform4f("rhoCoeffs", this->RhoCoeffs);
  kp->SetUniformf("rhoEnd", static_cast<float>(this->RhoEnd));
  kp->SetUniformf("quality", static_cast<float>(this->Opt.Quality));
  fbo->RemoveColorAttachments(3);
  for (int i = 0; i < 3; ++i)
  {
    fbo->AddColorAttachment(static_cast<unsigned int>(i), this->Kernel[i]);
  }
  fbo->ActivateDrawBuffers(3);
  ostate->vtkglViewport(0, 0, W, H);
  ostate->vtkglScissor(0, 0, W, H);
  this->KernelQuad->Render();
  TextureArray::Unbind(win, shadowUnit);
  finish();
  auto t1 = Clock::now();
  st.msKernel += Milliseconds(t0, t1);
  // the kernel buffer on the host: what each tile's pixels read (ss::PVSMTileReads)
  KernelBuffer kernels;
  if (this->Opt.TileRegions)
  {
    if (ReadTexture(win, fbo, this->Kernel[0], 0, W, H, 4, this->HostKernel[0]) &&
      ReadTexture(win, fbo, this->Kernel[1], 0, W, H, 4, this->HostKernel[1]))
    {
      kernels = KernelBuffer{ this->HostKernel[0].data(), this->HostKernel[1].data(), W, H };
    }
    else
    {
      vtkWarningWithObjectMacro(frame.Reporter, "PVSM could not read its kernel buffer back: tiles are drawn whole.");
    }
    st.msTiling += Milliseconds(t1, Clock::now());
  }
  // the scissor bounds each tile's clear, draw, pyramid and filter to its region
  vtkOpenGLState::ScopedglEnableDisable scissorSaver(ostate, GL_SCISSOR_TEST);
  ostate->vtkglEnable(GL_SCISSOR_TEST);

  target(this->Accum, W, H);
  ostate->vtkglClearColor(0.0, 0.0, 0.0, 0.0);
  ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
  for (int vi = 0; vi < static_cast<int>(l.Views.size()); ++vi)
  {
    const ShadowView& view = l.Views[vi];
    // --- step 4: the SMTG, one point per pixel, min-blended
    t0 = Clock::now();
    this->Grid.Attach(fbo, 0, 0);
    ostate->vtkglViewport(0, 0, G, G);
    ostate->vtkglScissor(0, 0, G, G);
    ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
    ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
    this->GridProgram = win->GetShaderCache()->ReadyShaderProgram(ssPVSMGridVS, ssPVSMGridFS, "");
    if (!this->GridProgram)
    {
      vtkErrorWithObjectMacro(frame.Reporter, "Could not build the PVSM tile-grid program.");
      break;
    }
    for (int i = 0; i < 3; ++i)
    {
      this->Kernel[i]->Activate();
    }
    vtkShaderProgram* gp = this->GridProgram;
    gp->SetUniformi("kernel0", this->Kernel[0]->GetTextureUnit());
    gp->SetUniformi("kernel1", this->Kernel[1]->GetTextureUnit());
    gp->SetUniformi("kernel2", this->Kernel[2]->GetTextureUnit());
    gp->SetUniformi("screenWidth", W);
    gp->SetUniformi("view", vi);
    const float ext[4] = { static_cast<float>(view.extent.x0), static_cast<float>(view.extent.y0),
      static_cast<float>(view.extent.x1), static_cast<float>(view.extent.y1) };
    gp->SetUniform4f("extent", ext);
    gp->SetUniformf("gridSize", static_cast<float>(G));
    gp->SetUniformf("maxPointSize", std::min(pointRange[1], static_cast<float>(2 * G + 1)));
    ostate->vtkglEnable(GL_BLEND);
    ostate->vtkglBlendEquation(GL_MIN);
    ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
    glEnable(GL_PROGRAM_POINT_SIZE);
    this->EmptyVAO->Bind();
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(W) * H);
    this->EmptyVAO->Release();
    glDisable(GL_PROGRAM_POINT_SIZE);
    ostate->vtkglBlendEquation(GL_FUNC_ADD);
    ostate->vtkglDisable(GL_BLEND);
    // --- step 5: the SMTG pyramid on the GPU (the paper's one change to
    // [GW07]), then all its levels (4/3 G^2 texels) to the host for the
    // kd-tree of step 6
    BuildDepthPyramid(win, fbo, this->ReduceQuad, this->Grid, G, G, 1);
    this->LastGridLevels.assign(static_cast<std::size_t>(this->Grid.Levels), {});
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int level = 0; level < this->Grid.Levels; ++level)
    {
      const int sz = std::max(1, G >> level);
      this->Grid.Attach(fbo, level, 0);
      fbo->ActivateReadBuffer(0);
      this->LastGridLevels[level].resize(static_cast<std::size_t>(sz) * sz * 2);
      glReadPixels(0, 0, sz, sz, GL_RG, GL_FLOAT, this->LastGridLevels[level].data());
    }
    TextureArray::Detach();
    const TileGridPyramid pyramid(this->LastGridLevels, G);
    const double extent[4] = { view.extent.x0, view.extent.y0, view.extent.x1, view.extent.y1 };
    const std::vector<ShadowTile> tiles = BuildShadowTiles(pyramid, extent, tileMax);
    std::vector<TileReadRegion> regions;
    if (kernels.kernel0)
    {
      std::vector<TileReadInput> in(tiles.size());
      for (std::size_t ti = 0; ti < tiles.size(); ++ti)
      {
        std::copy(tiles[ti].rect, tiles[ti].rect + 4, in[ti].rect);
        in[ti].resX = tiles[ti].resX;
        in[ti].resY = tiles[ti].resY;
        in[ti].levels = TileLevels(tiles[ti], this->Tile.Levels);
      }
      regions = PVSMTileReads(kernels, vi, in, this->Opt.FilterMaxQuads, this->Tile.Levels);
    }
    t1 = Clock::now();
    st.msTiling += Milliseconds(t0, t1);

    for (std::size_t ti = 0; ti < tiles.size(); ++ti)
    {
      const ShadowTile& tile = tiles[ti];
      // between tiles: progress, and a render abort stops here
      if (ti > 0 && frame.Progress && !frame.Progress((vi + static_cast<double>(ti) / tiles.size()) / l.Views.size()))
      {
        break;
      }
      const TileReadRegion* region = regions.empty() ? nullptr : &regions[ti];
      st.tileTexels += static_cast<double>(tile.resX) * tile.resY;
      st.tileResolutions.emplace_back(tile.resX, tile.resY);
      st.clampedTiles += tile.clamped ? 1 : 0;
      if (region && !(region->Texels() > 0.0))
      {
        // no pixel's kernel reaches a texel of it: nothing reads it, and
        // its filter pass would add 0 to every pixel
        ++st.tilesSkipped;
        continue;
      }
      // --- step 7: the tile's shadow map at its predicted resolution, where it is read
      t0 = Clock::now();
      this->Tile.Attach(fbo, 0, 0);
      ostate->vtkglViewport(0, 0, tile.resX, tile.resY);
      const Rect r{ tile.rect[0], tile.rect[1], tile.rect[2], tile.rect[3] };
      Rect read = r; // what of the tile is read, in shadow-map units
      if (region)
      {
        const LevelRegion& g = region->levels[0];
        ostate->vtkglScissor(g[0], g[1], g[2] - g[0], g[3] - g[1]);
        st.texelsRendered += region->Texels();
        // one texel wider: a triangle drawn into a read texel covers its centre
        const double tw = (r.x1 - r.x0) / tile.resX, th = (r.y1 - r.y0) / tile.resY;
        read = Rect{ r.x0 + (g[0] - 1) * tw, r.y0 + (g[1] - 1) * th, r.x0 + (g[2] + 1) * tw, r.y0 + (g[3] + 1) * th };
      }
      else
      {
        ostate->vtkglScissor(0, 0, tile.resX, tile.resY);
        st.texelsRendered += static_cast<double>(tile.resX) * tile.resY;
      }
      ostate->vtkglClearColor(3.0e38, 3.0e38, 3.0e38, 3.0e38);
      ostate->vtkglClear(GL_COLOR_BUFFER_BIT);
      if (!casters.Triangles.empty())
      {
        vtkShaderProgram* casterProgram = frame.Casters->UseProgram(win);
        ostate->vtkglEnable(GL_BLEND);
        ostate->vtkglBlendEquation(GL_MIN);
        ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
        if (this->Opt.TileCulling && casters.HasClusters())
        {
          // only the clusters whose light-space bounds reach the read part
          // of the tile; the pad (1e-3 of it) covers the GPU's float projection
          const auto ranges = VisibleTriangleRanges(casters.Clusters, view, casterOffset, read, 1e-3, &this->TileClusters);
          for (const auto& range : ranges)
          {
            st.tileTrianglesDrawn += static_cast<double>(range.second);
          }
          casters.Draw(casterProgram, casters.GetVertexArray(), view, r, casterOffset, &ranges);
        }
        else
        {
          st.tileTrianglesDrawn += static_cast<double>(casters.NumberOfTriangles());
          casters.Draw(casterProgram, casters.GetVertexArray(), view, r, casterOffset);
        }
        ostate->vtkglBlendEquation(GL_FUNC_ADD);
        ostate->vtkglDisable(GL_BLEND);
      }
      BuildDepthPyramid(win, fbo, this->ReduceQuad, this->Tile, tile.resX, tile.resY, 0, region ? &region->levels : nullptr);
      TextureArray::Detach();
      finish();
      t1 = Clock::now();
      st.msTileSM += Milliseconds(t0, t1);

      // --- step 8: filtering of the pixels whose kernel reaches the tile
      vtkShaderProgram* fp = ReadyQuad(this->FilterQuad, win, filterFS.c_str());
      if (!fp)
      {
        vtkErrorWithObjectMacro(frame.Reporter, "Could not build the PVSM filter program.");
        break;
      }
      target(this->Accum, W, H);
      if (region)
      {
        const int* b = region->screen;
        ostate->vtkglScissor(b[0], b[1], b[2] - b[0] + 1, b[3] - b[1] + 1);
        st.filterPixels += static_cast<double>(b[2] - b[0] + 1) * (b[3] - b[1] + 1);
      }
      else
      {
        st.filterPixels += static_cast<double>(W) * H;
      }
      const int tileUnit = this->Tile.Bind(win);
      commonUniforms(fp, -1);
      fp->SetUniformi("kernel0", this->Kernel[0]->GetTextureUnit());
      fp->SetUniformi("kernel1", this->Kernel[1]->GetTextureUnit());
      fp->SetUniformi("kernel2", this->Kernel[2]->GetTextureUnit());
      fp->SetUniformi("tileMap", tileUnit);
      const float tr[4] = { static_cast<float>(tile.rect[0]), static_cast<float>(tile.rect[1]),
        static_cast<float>(tile.rect[2]), static_cast<float>(tile.rect[3]) };
      fp->SetUniform4f("tileRect", tr);
      const float res[2] = { static_cast<float>(tile.resX), static_cast<float>(tile.resY) };
      fp->SetUniform2f("tileRes", res);
      fp->SetUniformi("tileLevels", TileLevels(tile, this->Tile.Levels));
      fp->SetUniformi("view", vi);
      fp->SetUniformi("maxQuads", this->Opt.FilterMaxQuads);
      fp->SetUniformf("nearFraction", static_cast<float>(ReachParams{}.nearFraction));
      ostate->vtkglEnable(GL_BLEND);
      ostate->vtkglBlendEquation(GL_FUNC_ADD);
      ostate->vtkglBlendFunc(GL_ONE, GL_ONE);
      this->FilterQuad->Render();
      ostate->vtkglDisable(GL_BLEND);
      TextureArray::Unbind(win, tileUnit);
      finish();
      st.msFiltering += Milliseconds(t1, Clock::now());
    }
    st.tiles += tiles.size();
    for (int i = 0; i < 3; ++i)
    {
      this->Kernel[i]->Deactivate();
    }
  }
  // --- V = (V·A) / A into the light's visibility layer
  t0 = Clock::now();
  vtkShaderProgram* rp = ReadyQuad(this->ResolveQuad, win, ssPVSMResolveFS);
  if (rp)
  {
    this->Kernel[0]->Activate();
    this->Kernel[1]->Activate();
    this->Accum->Activate();
    rp->SetUniformi("kernel0", this->Kernel[0]->GetTextureUnit());
    rp->SetUniformi("kernel1", this->Kernel[1]->GetTextureUnit());
    rp->SetUniformi("accum", this->Accum->GetTextureUnit());
    frame.Visibility->Attach(fbo, l.Layer);
    ostate->vtkglViewport(0, 0, W, H);
    ostate->vtkglScissor(0, 0, W, H);
    this->ResolveQuad->Render();
    this->Accum->Deactivate();
    this->Kernel[1]->Deactivate();
    this->Kernel[0]->Deactivate();
  }
  else
  {
    vtkErrorWithObjectMacro(frame.Reporter, "Could not build the PVSM resolve program.");
  }
  gbuf.GeometricNormal->Deactivate();
  gbuf.Normal->Deactivate();
  gbuf.Position->Deactivate();
  finish();
  st.msFiltering += Milliseconds(t0, Clock::now());
  done();
}

void PVSMSolver::EndFrame(SolverFrame& frame)
{
  if (!this->Active)
  {
    return;
  }
  PVSMStats& st = this->Stats;
  const double W = frame.State->Width, H = frame.State->Height, G = this->GridSide;
  st.msGBuffer = frame.Timings->Get("gbuffer");
  st.msLowResSM = frame.Timings->Get("shadow_maps");
  st.shadowMemoryBytes = static_cast<double>(frame.Maps->Bytes() + this->Tile.Bytes()) + G * G * 8 + W * H * (3 * 16 + 8);
  st.msTotal = st.msGBuffer + st.msLowResSM + st.msKernel + st.msTiling + st.msTileSM + st.msFiltering;
  this->LastStats = st;
  this->LastClustersJSON = frame.Casters->ClusterStatsJSON(this->TileClusters);
  this->LastMapClustersJSON = frame.Casters->ClusterStatsJSON(this->MapClusters);
  frame.Timings->Set("pvsm", st.msKernel + st.msTiling + st.msTileSM + st.msFiltering);
}

std::string PVSMSolver::GetStatsJSON() const
{
  std::ostringstream o;
  o.precision(17);
  o << "{\"lights\": " << this->Lights << ", \"low_resolution\": " << this->Opt.LowResolution
    << ", \"grid\": " << this->Opt.GridSize << ", \"max_tile\": " << this->Opt.MaxTileResolution
    << ", \"max_tile_used\": " << this->TileUsed << ", \"map_raster\": \"" << (this->MapOnCPU ? "cpu" : "gpu") << "\""
    << ", \"tile_clusters\": " << (this->LastClustersJSON.empty() ? "null" : this->LastClustersJSON)
    << ", \"map_clusters\": " << (this->LastMapClustersJSON.empty() ? "null" : this->LastMapClustersJSON)
    << ", \"stats\": " << PVSMStatsToJSON(this->LastStats) << "}";
  return o.str();
}

long long PVSMSolver::GetMemoryBytes() const
{
  long long b = this->Tile.Bytes() + this->Grid.Bytes();
  for (int i = 0; i < 3; ++i)
  {
    b += TextureBytes(this->Kernel[i], 16);
  }
  return b + TextureBytes(this->Accum, 16);
}

int PVSMSolver::GetNumberOfGraphicsResources() const
{
  int n = (this->Tile.Handle != 0 ? 1 : 0) + (this->Grid.Handle != 0 ? 1 : 0);
  for (vtkTextureObject* t : { this->Kernel[0].Get(), this->Kernel[1].Get(), this->Kernel[2].Get(), this->Accum.Get() })
  {
    n += (t && t->GetHandle() != 0) ? 1 : 0;
  }
  n += (this->KernelQuad ? 1 : 0) + (this->FilterQuad ? 1 : 0) + (this->ResolveQuad ? 1 : 0) +
    (this->ReduceQuad ? 1 : 0);
  return n;
}

void PVSMSolver::ReleaseGraphicsResources(vtkWindow* w)
{
  this->Tile.Release();
  this->Tile.ForgetFailedSize(); // (another context may hold more)
  this->Grid.Release();
  this->LastGridLevels.clear();
  for (auto* t : { this->Kernel[0].Get(), this->Kernel[1].Get(), this->Kernel[2].Get(), this->Accum.Get() })
  {
    if (t)
    {
      t->ReleaseGraphicsResources(w);
    }
  }
  for (auto& t : this->Kernel)
  {
    t = nullptr;
  }
  this->Accum = nullptr;
  for (auto* q : { &this->KernelQuad, &this->FilterQuad, &this->ResolveQuad, &this->ReduceQuad })
  {
    ReleaseQuad(*q, w);
  }
  for (auto* vao : { &this->ConservativeVAO, &this->EmptyVAO })
  {
    if (*vao)
    {
      (*vao)->ReleaseGraphicsResources();
      *vao = nullptr;
    }
  }
  this->ConservativeProgram = nullptr;
  this->GridProgram = nullptr;
  this->SceneKey.clear();
}
}
