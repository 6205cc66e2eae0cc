/**
 * @class   vtkSoftShadowPass
 * @brief   Soft shadows of area lights for every prop of a renderer.
 *
 * Install it on a renderer and render as usual:
 * @code{.cpp}
 *   vtkNew<vtkSoftShadowPass> shadows;
 *   shadows->SetMethod(vtkSoftShadowPass::PCSS);
 *   renderer->SetPass(shadows);
 * @endcode
 *
 * Each frame follows one data flow (see DESIGN.md):
 * 1. G-buffer: the opaque props are drawn through their own VTK mappers into
 *    float targets holding the world position (relative to PositionsOrigin),
 *    the world normal, the prop id and whether the prop receives shadows.
 * 2. Caster set: the world-space triangles of every shadow-casting prop,
 *    rebuilt only when a prop, its data or its transform changed.
 * 3. Effect plan: per light, what to simulate (which method, or none) and why.
 * 4. Per shadow-casting light, the method's solver writes a visibility
 *    texture V(x,y) in [0,1]: the fraction of the light visible from the
 *    surface. Solvers that use shadow maps share one array of whole-view maps.
 * 5. Shading: the delegate pass (by default the renderer's standard path, so
 *    translucency, depth peeling, volumes and overlays keep working) renders
 *    with VTK's own lighting; each light's diffuse and specular terms (Phong)
 *    or radiance (PBR) are multiplied by that light's V.
 *
 * Props opt out with SetCastsShadows / SetReceivesShadows. Lights are
 * configured with vtkSoftShadowLight. Translucent props cast shadows; with
 * the shadow-map methods as if opaque, with VPCSS and AVSM (and the
 * reference) by their transmittance; volumes (vtkVolume of image data, their
 * scalar opacity) cast shadows with VPCSS, AVSM and the reference. Translucent
 * props are not in the G-buffer: they receive the shadows of lights solved
 * by VPCSS or AVSM (their fragments compute V), with depth peeling on or
 * off, and none from the other methods.
 */
#ifndef vtkSoftShadowPass_h
#define vtkSoftShadowPass_h

#include "SoftShadowsRenderingOpenGL2Module.h"
#include "vtkOpenGLRenderPass.h"

#include <memory> // for unique_ptr
#include <string> // for string

class vtkFloatArray;
class vtkOpenGLRenderWindow;
class vtkInformationIntegerKey;
class vtkProp;
class vtkRenderPass;
class vtkRenderWindow;
class vtkShaderProgram;

class SOFTSHADOWSRENDERINGOPENGL2_EXPORT vtkSoftShadowPass : public vtkOpenGLRenderPass
{
public:
  static vtkSoftShadowPass* New();
  vtkTypeMacro(vtkSoftShadowPass, vtkOpenGLRenderPass);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum MethodType
  {
    AUTO = 0, ///< the effect planner decides per light (default)
    HARD = 1, ///< one shadow map, slope-scaled bias, one texel
    PCF = 2,  ///< fixed filter of PCFRadius texels
    PCSS = 3, ///< blocker search + penumbra estimate + texel-quad coverage filter
    NONE = 4, ///< no shadows (the pass only shades)
    REFERENCE = 5, ///< ray-traced ground truth: k x k light samples per pixel (Embree, CPU)
    GEARS = 6,     ///< exact soft shadows: triangles assigned to pixels by a grid, k x k bitmasks
    PVSM = 7,      ///< predicted virtual soft shadow maps: adaptive tiles, anisotropic coverage filter
    HARDAVG = 8,   ///< brute force: average of AverageSamples^2 hard shadow maps, one per light sample
    VPCSS = 9,     ///< volumetric PCSS: soft shadows of translucent casters and volumes over an AVSM
    ASM = 10,      ///< adaptive shadow maps: hard shadows refined where the view needs them, in a memory budget
    AVSM = 11      ///< adaptive volumetric shadow map: hard shadows of translucent casters and volumes
  };

  /** GEARS backends (SetGearsBackend). */
  enum GearsBackends
  {
    GEARS_BACKEND_CPU = 0,
    GEARS_BACKEND_GL = 1
  };

  ///@{
  /**
   * The visibility solver used for every shadow-casting light.
   */
  virtual void SetMethod(int method);
  vtkGetMacro(Method, int);
  /** SetMethod clamps to this range: every registered method (ssSolverRegistry). */
  virtual int GetMethodMinValue();
  virtual int GetMethodMaxValue();
  /** By name: auto, hard, pcf, pcss, none, reference, gears, pvsm, hardavg, vpcss, asm, avsm. Returns false for unknown names. */
  bool SetMethodByName(const char* name);
  static const char* GetMethodName(int method);
  /** Every method's name, comma-separated, in the registry's order. */
  static std::string GetMethodNames();
  ///@}

  ///@{
  /**
   * Render pass used for the shading step. When null (default), the pass
   * renders the renderer's standard path (lights, opaque, translucent with
   * depth peeling, volumes, overlays), like ParaView's vtkPVDefaultPass.
   */
  virtual void SetDelegatePass(vtkRenderPass* pass);
  vtkGetObjectMacro(DelegatePass, vtkRenderPass);
  ///@}

  ///@{
  /**
   * Reference solver: k x k light samples (1..64, default 32) and their
   * pattern (0: regular grid centres, as GEARS uses; 1: stratified jitter
   * with a fixed seed).
   */
  vtkSetClampMacro(ReferenceSamples, int, 1, 64);
  vtkGetMacro(ReferenceSamples, int);
  vtkSetClampMacro(ReferencePattern, int, 0, 1);
  vtkGetMacro(ReferencePattern, int);
  ///@}

  ///@{
  /**
   * GEARS solver (CPU, all cores through TBB): k x k regular light samples
   * (1..32, default 16; the same samples as the reference with
   * ReferencePattern 0), grid resolution (default 128) and rasterisation
   * (0: exact edge planes, 1: lookup table).
   */
  vtkSetClampMacro(GearsSamples, int, 1, 32);
  vtkGetMacro(GearsSamples, int);
  vtkSetClampMacro(GearsGrid, int, 8, 1024);
  vtkGetMacro(GearsGrid, int);
  vtkSetClampMacro(GearsRaster, int, 0, 1);
  vtkGetMacro(GearsRaster, int);
  /** Count the paper's "necessary" assignments (Table 9) in the stats; slower (no early exit). */
  vtkSetMacro(GearsCountNecessary, bool);
  vtkGetMacro(GearsCountNecessary, bool);
  /**
   * Where GEARS runs: GEARS_BACKEND_CPU (Rendering/Core, TBB; the default) or
   * GEARS_BACKEND_GL (GL 4.3 compute shaders in this window's context; the
   * same bitmasks). The GL backend runs edge-plane rasterisation only; with
   * GearsRaster 1 (LUT), on a context older than 4.3, or beyond the context's
   * buffer limits the frame uses the CPU and the stats say why
   * (gears.backend, gears.backend_note), with one warning.
   */
  vtkSetClampMacro(GearsBackend, int, 0, 1);
  vtkGetMacro(GearsBackend, int);
  /** The backend GEARS ran on in the last frame ("cpu" or "gl"; "cpu" before any GEARS frame). */
  const char* GetLastGearsBackend();
  ///@}

  ///@{
  /**
   * PVSM (Shen et al. 2011). PVSMLowResolution: the conservative low-resolution
   * map for the blocker search (default 1024; when other lights use shadow maps
   * in the same frame, ShadowMapSize is used for all). PVSMGridSize: the shadow
   * map tile grid (64, a power of two). PVSMMaxTileResolution: the largest tile
   * (4096, capped by the GL limit). PVSMQuality: scale on the perceptual metric
   * rho (2 asks twice the texels per kernel). PVSMMetric: 0 automatic (static
   * when only the camera moved since the last frame), 1 dynamic, 2 static.
   */
  vtkSetClampMacro(PVSMLowResolution, int, 64, 8192);
  vtkGetMacro(PVSMLowResolution, int);
  vtkSetClampMacro(PVSMGridSize, int, 4, 256);
  vtkGetMacro(PVSMGridSize, int);
  vtkSetClampMacro(PVSMMaxTileResolution, int, 64, 16384);
  vtkGetMacro(PVSMMaxTileResolution, int);
  vtkSetClampMacro(PVSMQuality, double, 0.05, 64.0);
  vtkGetMacro(PVSMQuality, double);
  vtkSetClampMacro(PVSMMetric, int, 0, 2);
  vtkGetMacro(PVSMMetric, int);
  /**
   * PVSMTileCulling (default on): each tile draws only the caster clusters
   * (at most 1024 triangles, ordered along a Morton curve) whose light-space
   * bounds reach it, instead of the whole caster set. The maps are the same
   * either way; off is for measuring what it saves (stats:
   * pvsm.tile_triangles_drawn).
   */
  vtkSetMacro(PVSMTileCulling, bool);
  vtkGetMacro(PVSMTileCulling, bool);
  vtkBooleanMacro(PVSMTileCulling, bool);
  ///@}

  ///@{
  /**
   * HARDAVG: light samples per side (default 8: the 64 hard shadow maps PVSM
   * §6 compares against). Each sample of the regular grid gets its own hard
   * map of ShadowMapSize^2 and V is the mean of the hard tests.
   */
  vtkSetClampMacro(AverageSamples, int, 1, 32);
  vtkGetMacro(AverageSamples, int);
  ///@}

  ///@{
  /**
   * VPCSS and AVSM (translucent casters and volumes). AVSMNodes: nodes of
   * each texel's transmittance function (4..16, rounded up to a multiple of
   * 4; default 8). AVSMSize: texels a side of the adaptive volumetric shadow
   * map (a power of two, default 512). AVSMMemory: megabytes for the maps,
   * their per-texel buffers and the fragment lists (default 256); the map is
   * made smaller to fit, and the fragment lists are resolved in bands of
   * rows that fit (stats: vpcss.avsm). ColoredShadows: RGB transmittance
   * from each caster's colour and opacity (default off: one channel).
   * VolumeSteps: the most march steps of a texel's ray through the volumes
   * (default 256). VPCSSFilterQuads: texel quads per axis of VPCSS's filter
   * at most (coarser pyramid levels for larger kernels; default 8).
   */
  vtkSetClampMacro(AVSMNodes, int, 4, 16);
  vtkGetMacro(AVSMNodes, int);
  vtkSetClampMacro(AVSMSize, int, 64, 8192);
  vtkGetMacro(AVSMSize, int);
  vtkSetClampMacro(AVSMMemory, int, 16, 65536);
  vtkGetMacro(AVSMMemory, int);
  vtkSetMacro(ColoredShadows, bool);
  vtkGetMacro(ColoredShadows, bool);
  vtkBooleanMacro(ColoredShadows, bool);
  vtkSetClampMacro(VolumeSteps, int, 8, 4096);
  vtkGetMacro(VolumeSteps, int);
  vtkSetClampMacro(VPCSSFilterQuads, int, 2, 64);
  vtkGetMacro(VPCSSFilterQuads, int);
  ///@}

  ///@{
  /**
   * ASM (Fernando et al. 2001, Documentation/asm.md): hard shadows of point,
   * spot and directional lights from a tree of shadow-map pieces refined
   * where the view needs them. Progressive: every frame refines within
   * ASMTimeBudget (ms, default 20) until nothing is left to refine, so a
   * still view re-rendered improves (the planner does not reuse it while the
   * stats say "refining"). ASMMemoryBudget: megabytes of node pages (default
   * 16; 8 bytes a texel: depth and triangle id), never exceeded; nodes unused
   * in the last frame go least recently used first, others only for a larger
   * benefit. ASMPageSize: texels a side of a node (rounded up to a power of
   * two, default 128). ASMCells: cells a side of a node (2, 4 or 8, default
   * 4). ASMMaxDepth: levels below the roots (default 10). ASMAnalysisStride:
   * the cost-benefit analysis looks at one pixel in this many (default 8, as
   * §4.3). ASMQuality: texels per pixel side asked for (default 1).
   * ASMIDTest: the ID + depth test of §4.2 (default on; off: depth only).
   */
  vtkSetClampMacro(ASMMemoryBudget, double, 0.0625, 4096.0);
  vtkGetMacro(ASMMemoryBudget, double);
  vtkSetClampMacro(ASMPageSize, int, 16, 4096);
  vtkGetMacro(ASMPageSize, int);
  vtkSetClampMacro(ASMCells, int, 2, 8);
  vtkGetMacro(ASMCells, int);
  vtkSetClampMacro(ASMMaxDepth, int, 0, 20);
  vtkGetMacro(ASMMaxDepth, int);
  vtkSetClampMacro(ASMTimeBudget, double, 0.0, 1.0e5);
  vtkGetMacro(ASMTimeBudget, double);
  vtkSetClampMacro(ASMAnalysisStride, int, 1, 64);
  vtkGetMacro(ASMAnalysisStride, int);
  vtkSetClampMacro(ASMQuality, double, 0.125, 16.0);
  vtkGetMacro(ASMQuality, double);
  vtkSetMacro(ASMIDTest, bool);
  vtkGetMacro(ASMIDTest, bool);
  vtkBooleanMacro(ASMIDTest, bool);
  /**
   * Whether the last frame's ASM lights are still being refined (the view
   * is not final yet; render again to refine further). False for other methods.
   */
  bool GetASMRefining();
  ///@}

  ///@{
  /** Shadow map resolution (texels per side, rounded up to a power of two), default 2048. */
  vtkSetClampMacro(ShadowMapSize, int, 64, 16384);
  vtkGetMacro(ShadowMapSize, int);
  ///@}

  ///@{
  /** Filter radius of the pcf method, in texels (default 1.5). */
  vtkSetClampMacro(PCFRadius, double, 0.5, 64.0);
  vtkGetMacro(PCFRadius, double);
  ///@}

  ///@{
  /** Blocker-search samples per axis of PCSS (default 8). */
  vtkSetClampMacro(BlockerSearchSamples, int, 2, 32);
  vtkGetMacro(BlockerSearchSamples, int);
  ///@}

  ///@{
  /**
   * Largest number of texel quads per axis the coverage filter visits
   * (default 24). Larger kernels use coarser quads (same integral, less
   * detail), so the cost per pixel is bounded.
   */
  vtkSetClampMacro(FilterMaxQuads, int, 2, 128);
  vtkGetMacro(FilterMaxQuads, int);
  ///@}

  ///@{
  /**
   * Depth bias in shadow-map texels (constant and slope-scaled), default 1 and 2.
   */
  vtkSetMacro(ConstantBias, double);
  vtkGetMacro(ConstantBias, double);
  vtkSetMacro(SlopeBias, double);
  vtkGetMacro(SlopeBias, double);
  ///@}

  ///@{
  /**
   * Normal-offset lookup of the shadow-map methods, in shadow-map texels
   * (0..16, default 0: off): each receiver is looked up moved along its
   * triangle's normal by this many of its view's texels at the receiver,
   * times the sine of the angle between that normal and the light
   * (Filament's normal bias). Measured on the real-mesh set it does not pay
   * once the receiver plane is the triangle's own (Documentation/
   * stability.md, "Acne on smooth-shaded meshes"); it remains for coarse
   * maps and for users who want it.
   */
  vtkSetClampMacro(NormalOffset, double, 0.0, 16.0);
  vtkGetMacro(NormalOffset, double);
  ///@}

  ///@{
  /**
   * Origin of the positions buffer and of all float computations. By default
   * (AutomaticPositionsOrigin on) the camera focal point of each frame.
   */
  vtkSetVector3Macro(PositionsOrigin, double);
  vtkGetVector3Macro(PositionsOrigin, double);
  vtkSetMacro(AutomaticPositionsOrigin, bool);
  vtkGetMacro(AutomaticPositionsOrigin, bool);
  vtkBooleanMacro(AutomaticPositionsOrigin, bool);
  ///@}

  ///@{
  /**
   * When on, the GPU is finished (glFinish) between stages so the per-stage
   * timings in GetStatsJSON are true (costs some speed; default off).
   */
  vtkSetMacro(MeasureTimings, bool);
  vtkGetMacro(MeasureTimings, bool);
  vtkBooleanMacro(MeasureTimings, bool);
  ///@}

  ///@{
  /**
   * Interactive frames. With AdaptToFrameBudget on (default), a frame
   * rendered while the render window's DesiredUpdateRate is at least
   * InteractiveUpdateRate (default 0.1 frames per second) is interactive:
   * VTK's interactor sets 15 while the user drags and 0.0001 after,
   * ParaView's interactive render 5 and its still render 0.002. Its shadow
   * work has 1000 / DesiredUpdateRate milliseconds: where the costs measured
   * on earlier frames do not fit, the effect planner stands faster methods in
   * (requested -> the method auto uses for area lights -> hard shadows) and
   * says so in the plan; the next still frame uses the requested method
   * again. Measuring costs one glFinish per solved frame.
   */
  vtkSetMacro(AdaptToFrameBudget, bool);
  vtkGetMacro(AdaptToFrameBudget, bool);
  vtkBooleanMacro(AdaptToFrameBudget, bool);
  vtkSetClampMacro(InteractiveUpdateRate, double, 1e-6, 1e6);
  vtkGetMacro(InteractiveUpdateRate, double);
  ///@}

  /**
   * Progress and abort. While it solves, the pass invokes
   * vtkCommand::ProgressEvent on itself (call data: a double* in [0, 1], over
   * all shadow lights of the frame), between lights and between chunks of
   * the long solvers' work (reference and gears on the CPU: chunks of pixels
   * or cells; pvsm: tiles). At the same points it asks the render window
   * vtkRenderWindow::CheckAbortStatus (which fires AbortCheckEvent); once the
   * window's AbortRender is set, it stops: that frame has no shadows, the
   * plan says "aborted", and the next render solves again.
   */
  bool GetLastFrameAborted();

  ///@{
  /** Per-prop flags (stored in vtkProp::GetPropertyKeys); both default to true. */
  static void SetCastsShadows(vtkProp* prop, bool casts);
  static bool GetCastsShadows(vtkProp* prop);
  static void SetReceivesShadows(vtkProp* prop, bool receives);
  static bool GetReceivesShadows(vtkProp* prop);
  static vtkInformationIntegerKey* CASTS_SHADOWS();
  static vtkInformationIntegerKey* RECEIVES_SHADOWS();
  ///@}

  ///@{
  /**
   * Results of the last frame.
   * GetVisibilityImage fills a 1-component array (width*height, row 0 at the
   * bottom, background NaN) with V of the given shadow light (0-based among
   * the lights that cast shadows, in renderer order); it returns false when
   * that light does not exist. GetPositionsImage fills 3 components: world
   * position minus GetLastPositionsOrigin (background NaN).
   */
  int GetNumberOfShadowLights();
  bool GetVisibilityImage(int shadowLight, vtkFloatArray* out);
  /**
   * RGB visibility of a shadow light whose solver wrote colour (VPCSS or
   * AVSM with ColoredShadows on): 3 components per pixel, background NaN;
   * false for lights without it. V (GetVisibilityImage) is then the mean of
   * the three.
   */
  bool GetColorVisibilityImage(int shadowLight, vtkFloatArray* out);
  bool GetPositionsImage(vtkFloatArray* out);
  /**
   * The factor VTK's diffuse lighting multiplies the given shadow light's V
   * with, per pixel (1 component, background NaN): max(0, n . l) with l
   * towards the light's centre and n turned towards the camera
   * (ss::DiffuseCosine). Where it is 0, V does not change the picture; the
   * benches weight V's error with it for the error in the picture.
   */
  bool GetDiffuseCosineImage(int shadowLight, vtkFloatArray* out);
  /**
   * PVSM's shadow map tile grid pyramid of the last view solved, as built on
   * the GPU and read back (§5.2 step 5): level l has (G/2^l)^2 cells of 2
   * components (the smallest predicted texel size per axis; values >= 1e38
   * mean no pixel needs the cell). GetLastPVSMTileGridLevels is 0 before a
   * PVSM frame; GetLastPVSMTileGridLevel returns false for a level that does
   * not exist.
   */
  int GetLastPVSMTileGridLevels();
  bool GetLastPVSMTileGridLevel(int level, vtkFloatArray* out);
  /**
   * Level 0 of shadow-map layer `layer` of the last frame (the whole-view
   * maps: PCSS/PCF/hard maps, PVSM's conservative low-resolution map), read
   * back from `win`'s context: size^2 tuples of 2 components (min, max
   * light-space depth; >= 1e38 where nothing was drawn), row 0 at the bottom.
   * False when there is no such layer.
   */
  bool GetShadowMapLayer(vtkRenderWindow* win, int layer, vtkFloatArray* out);
  int GetLastWidth();
  int GetLastHeight();
  void GetLastPositionsOrigin(double origin[3]);
  int GetLastNumberOfCasterTriangles();
  /** JSON object: plan (per light: method and reasons), timings_ms, memory_bytes. */
  std::string GetStatsJSON();
  /** The plan as readable lines (also in PrintSelf). */
  std::string GetPlanDescription();
  /**
   * One line for an annotation: the methods of the last frame and its time,
   * e.g. "pcss (interactive: stands in for gears), 38 ms".
   */
  std::string GetPlanSummary();
  ///@}

  /** Live GPU objects owned by the pass (textures, buffers, programs); 0 after release. */
  int GetNumberOfGraphicsResources();

  void Render(const vtkRenderState* s) override;
  void ReleaseGraphicsResources(vtkWindow* w) override;

  bool PreReplaceShaderValues(std::string& vertexShader, std::string& geometryShader,
    std::string& fragmentShader, vtkAbstractMapper* mapper, vtkProp* prop) override;
  bool PostReplaceShaderValues(std::string& vertexShader, std::string& geometryShader,
    std::string& fragmentShader, vtkAbstractMapper* mapper, vtkProp* prop) override;
  bool SetShaderParameters(vtkShaderProgram* program, vtkAbstractMapper* mapper, vtkProp* prop,
    vtkOpenGLVertexArrayObject* VAO = nullptr) override;
  vtkMTimeType GetShaderStageMTime() override;

protected:
  vtkSoftShadowPass();
  ~vtkSoftShadowPass() override;

  int Method = AUTO;
  vtkRenderPass* DelegatePass = nullptr;
  int ShadowMapSize = 2048;
  int ReferenceSamples = 32;
  int ReferencePattern = 0;
  int GearsSamples = 16;
  int GearsGrid = 128;
  int GearsRaster = 0;
  bool GearsCountNecessary = false;
  int GearsBackend = 0;
  int PVSMLowResolution = 1024;
  int PVSMGridSize = 64;
  int PVSMMaxTileResolution = 4096;
  double PVSMQuality = 1.0;
  bool PVSMTileCulling = true;
  int PVSMMetric = 0;
  int AverageSamples = 8;
  int AVSMNodes = 8;
  int AVSMSize = 512;
  int AVSMMemory = 256;
  bool ColoredShadows = false;
  int VolumeSteps = 256;
  int VPCSSFilterQuads = 8;
  double ASMMemoryBudget = 16.0;
  int ASMPageSize = 128;
  int ASMCells = 4;
  int ASMMaxDepth = 10;
  double ASMTimeBudget = 20.0;
  int ASMAnalysisStride = 8;
  double ASMQuality = 1.0;
  bool ASMIDTest = true;
  double PCFRadius = 1.5;
  int BlockerSearchSamples = 8;
  int FilterMaxQuads = 24;
  double ConstantBias = 1.0;
  double SlopeBias = 2.0;
  double NormalOffset = 0.0;
  double PositionsOrigin[3] = { 0, 0, 0 };
  bool AutomaticPositionsOrigin = true;
  bool MeasureTimings = false;
  bool AdaptToFrameBudget = true;
  double InteractiveUpdateRate = 0.1;

private:
  vtkSoftShadowPass(const vtkSoftShadowPass&) = delete;
  void operator=(const vtkSoftShadowPass&) = delete;

  // The stages of Render (vtkSoftShadowPass.cxx says which file owns what).
  void PlanFrame(bool unchangedSinceLastFrame, double frameBudgetMs);
  void RenderGBuffer(const vtkRenderState* s);
  void SolveVisibility(const vtkRenderState* s);
  void Shade(const vtkRenderState* s);

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
