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

#include <functional> // for function
#include <memory> // for unique_ptr
#include <string> // for string

class vtkActor;
class vtkFloatArray;
class vtkMatrix4x4;
class vtkOpenGLRenderWindow;
class vtkInformationIntegerKey;
class vtkProp;
class vtkRenderPass;
class vtkRenderWindow;
class vtkRenderer;
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
   * The visibility solver used for every shadow-casting light. A number
   * outside GetMethodMinValue()..GetMethodMaxValue() is an error and the
   * method is kept (stop 45; before, it was clamped: 99 gave avsm in silence,
   * where ParaView's view refuses it).
   */
  virtual void SetMethod(int method);
  vtkGetMacro(Method, int);
  /** SetMethod accepts this range: every registered method (ssSolverRegistry). */
  virtual int GetMethodMinValue();
  virtual int GetMethodMaxValue();
  /**
   * By name: auto, hard, pcf, pcss, none, reference, gears, pvsm, hardavg, vpcss, asm, avsm. An unknown
   * name is an error naming it (the method is kept) and returns false.
   */
  bool SetMethodByName(const char* name);
  /** The number of the method of this name; -1 (and no error) for an unknown name. */
  static int FindMethod(const char* name);
  /** The method's name; "unknown" for a number that is no method. */
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
   * Options of the solvers (issue 19), declared once in each solver's own
   * files (its `DeclaredOptions()` list, pointed at by its registry line): key, type
   * (int, double, bool or enum), range or value names, default, label and
   * help. The CLI's `--option key=value` and the ParaView view's properties
   * are made from the same descriptors. Keys are the CLI's: "pvsm_quality",
   * "gears_backend", ... (`softshadows --help`, GetSolverOptionKey).
   *
   * SetSolverOption refuses a value outside the option's range (or a name
   * that is not one of its enum names, or a non-integer for an int/bool/enum
   * option) with an error naming the key, keeps the previous value and
   * returns false; an unknown key is an error too. Enum options take their
   * index (int) or their name (string).
   */
  bool SetSolverOption(const char* key, double value);
  bool SetSolverOption(const char* key, int value);
  bool SetSolverOption(const char* key, const char* value);
  /** The value (enum: its index; bool: 0 or 1); NaN and an error for an unknown key. */
  double GetSolverOption(const char* key);
  /** The value as text: the name of an enum option, the number otherwise ("" for an unknown key). */
  std::string GetSolverOptionAsString(const char* key);
  /** Back to every solver option's default. */
  void ResetSolverOptions();
  /** Enumeration, in the registry's order; out-of-range indices give null / NaN / 0. */
  static int GetNumberOfSolverOptions();
  static int FindSolverOption(const char* key); ///< its index, or -1
  static const char* GetSolverOptionKey(int i);
  static const char* GetSolverOptionPropertyName(int i); ///< "PVSMQuality": Set/Get<name> forwarders, ParaView
  static const char* GetSolverOptionLabel(int i);
  static const char* GetSolverOptionHelp(int i);
  static const char* GetSolverOptionType(int i); ///< "int", "double", "bool" or "enum"
  static double GetSolverOptionMinimum(int i);
  static double GetSolverOptionMaximum(int i);
  static double GetSolverOptionDefault(int i);
  static int GetSolverOptionNumberOfNames(int i); ///< enum: its names (0 for other types)
  static const char* GetSolverOptionName(int i, int value);
  /** What its value may be, as usage lines say it: "1..32", "0.05..64", "0|1", "edge|lut". */
  static std::string GetSolverOptionValues(int i);
  /** Its default as text: the number, or the enum's name. */
  static std::string GetSolverOptionDefaultAsString(int i);
  /** The methods whose registry line declares it, comma-separated ("reference, gears"). */
  static const char* GetSolverOptionMethods(int i);
  ///@}

  ///@{
  /**
   * Deprecated forwarders of the solver options (kept for Python scripts,
   * ParaView state files and C++ callers; use SetSolverOption): each sets the
   * option of the same property name (GetSolverOptionPropertyName), clamped
   * to its range as before, e.g. SetPVSMQuality(q) is
   * SetSolverOption("pvsm_quality", q). What each means: the solver's
   * DeclaredOptions() list, `softshadows --help`, Documentation/methods.md.
   */
  // reference and gears (ssTriangleSolver)
  virtual void SetReferenceSamples(int v);
  virtual int GetReferenceSamples();
  virtual void SetReferencePattern(int v);
  virtual int GetReferencePattern();
  virtual void SetGearsSamples(int v);
  virtual int GetGearsSamples();
  virtual void SetGearsGrid(int v);
  virtual int GetGearsGrid();
  virtual void SetGearsRaster(int v);
  virtual int GetGearsRaster();
  virtual void SetGearsCountNecessary(bool v);
  virtual bool GetGearsCountNecessary();
  virtual void SetGearsFindPieces(bool v);
  virtual bool GetGearsFindPieces();
  virtual void GearsFindPiecesOn();
  virtual void GearsFindPiecesOff();
  virtual void SetGearsCellCulling(bool v);
  virtual bool GetGearsCellCulling();
  virtual void GearsCellCullingOn();
  virtual void GearsCellCullingOff();
  virtual void SetGearsWinding(bool v);
  virtual bool GetGearsWinding();
  virtual void GearsWindingOn();
  virtual void GearsWindingOff();
  virtual void SetGearsGLLayers(int v);
  virtual int GetGearsGLLayers();
  virtual void SetGearsBackend(int v);
  virtual int GetGearsBackend();
  // pvsm (ssPVSMSolver)
  virtual void SetPVSMLowResolution(int v);
  virtual int GetPVSMLowResolution();
  virtual void SetPVSMGridSize(int v);
  virtual int GetPVSMGridSize();
  virtual void SetPVSMMaxTileResolution(int v);
  virtual int GetPVSMMaxTileResolution();
  virtual void SetPVSMQuality(double v);
  virtual double GetPVSMQuality();
  virtual void SetPVSMMetric(int v);
  virtual int GetPVSMMetric();
  virtual void SetPVSMTileCulling(bool v);
  virtual bool GetPVSMTileCulling();
  virtual void PVSMTileCullingOn();
  virtual void PVSMTileCullingOff();
  // asm, avsm, vpcss: caster clusters culled per cell or view (ssASMSolver)
  virtual void SetCasterCulling(bool v);
  virtual bool GetCasterCulling();
  virtual void CasterCullingOn();
  virtual void CasterCullingOff();
  // hardavg (ssHardAverageSolver)
  virtual void SetAverageSamples(int v);
  virtual int GetAverageSamples();
  // vpcss and avsm (ssTranslucentSolver)
  virtual void SetAVSMNodes(int v);
  virtual int GetAVSMNodes();
  virtual void SetAVSMSize(int v);
  virtual int GetAVSMSize();
  virtual void SetAVSMMemory(int v);
  virtual int GetAVSMMemory();
  virtual void SetColoredShadows(bool v);
  virtual bool GetColoredShadows();
  virtual void ColoredShadowsOn();
  virtual void ColoredShadowsOff();
  virtual void SetVolumeSteps(int v);
  virtual int GetVolumeSteps();
  virtual void SetVPCSSFilterQuads(int v);
  virtual int GetVPCSSFilterQuads();
  // asm (ssASMSolver)
  virtual void SetASMMemoryBudget(double v);
  virtual double GetASMMemoryBudget();
  virtual void SetASMPageSize(int v);
  virtual int GetASMPageSize();
  virtual void SetASMCells(int v);
  virtual int GetASMCells();
  virtual void SetASMMaxDepth(int v);
  virtual int GetASMMaxDepth();
  virtual void SetASMTimeBudget(double v);
  virtual double GetASMTimeBudget();
  virtual void SetASMAnalysisStride(int v);
  virtual int GetASMAnalysisStride();
  virtual void SetASMQuality(double v);
  virtual double GetASMQuality();
  virtual void SetASMIDTest(bool v);
  virtual bool GetASMIDTest();
  virtual void ASMIDTestOn();
  virtual void ASMIDTestOff();
  // hard, pcf and pcss (ssShadowMapSolver)
  virtual void SetPCFRadius(double v);
  virtual double GetPCFRadius();
  virtual void SetBlockerSearchSamples(int v);
  virtual int GetBlockerSearchSamples();
  virtual void SetFilterMaxQuads(int v);
  virtual int GetFilterMaxQuads();
  ///@}

  /**
   * The backend GEARS ran on in the last frame: "cpu", "gl", or "none" (no
   * GEARS solve in it: no shadow-casting light or no casters; or no GEARS
   * frame yet).
   */
  const char* GetLastGearsBackend();

  /**
   * The bounds of the casters' bulk among `ren`'s props, in world coordinates
   * (ss::BulkOfTriangles: without stray triangles far away or needles to a
   * lost vertex), gathered now (the next frame reuses the caster set). What a
   * view can size and place its lights by where a broken mesh reaches 1e10.
   * False without casters.
   */
  bool ComputeCasterBulkBounds(vtkRenderer* ren, double bounds[6]);
  /**
   * Whether the last frame's ASM lights are still being refined (the view
   * is not final yet; render again to refine further). False for other methods.
   */
  bool GetASMRefining();

  ///@{
  /** Shadow map resolution (texels per side, rounded up to a power of two), default 2048. */
  vtkSetClampMacro(ShadowMapSize, int, 64, 16384);
  vtkGetMacro(ShadowMapSize, int);
  ///@}

  ///@{
  /**
   * Depth bias in shadow-map texels (constant and slope-scaled), default 1 and 2.
   */
  void SetConstantBias(double texels); ///< NaN or inf: an error, the bias kept
  vtkGetMacro(ConstantBias, double);
  void SetSlopeBias(double texels); ///< NaN or inf: an error, the bias kept
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
  void SetNormalOffset(double texels); ///< clamped to 0..16; NaN: an error, the offset kept
  vtkGetMacro(NormalOffset, double);
  ///@}

  ///@{
  /**
   * Fit the shadow-map views to the visible receivers (default on): each
   * light's perspective views are cut to the receiver points the camera sees
   * (the G-buffer) and the reach of what can shadow them, and a rect light
   * gets side views only when a visible receiver lies beyond its main view
   * (Documentation/methods.md, "Shadow maps"). Off: every view covers the
   * receivers' bounds, as a conventional shadow map does; the maps then do
   * not change with the camera (a tiled frame always uses the bounds).
   */
  vtkSetMacro(FitViewsToVisibleReceivers, bool);
  vtkGetMacro(FitViewsToVisibleReceivers, bool);
  vtkBooleanMacro(FitViewsToVisibleReceivers, bool);
  ///@}

  ///@{
  /**
   * Origin of the positions buffer and of all float computations. By default
   * (AutomaticPositionsOrigin on) the camera focal point of each frame.
   */
  /// (non-finite coordinates or beyond 1e30: an error, the origin kept)
  void SetPositionsOrigin(double x, double y, double z);
  void SetPositionsOrigin(const double origin[3]) { this->SetPositionsOrigin(origin[0], origin[1], origin[2]); }
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
  ///@}

  ///@{
  /**
   * KeepRequestedMethod: every light gets the requested method as asked,
   * also where the planner would give it an equivalent, cheaper one (off by
   * default: a requested vpcss gives pcss to a light with no translucent
   * caster in its view, where VPCSS's filter is PCSS's). For comparing a
   * solver with that equivalent and for testing it (plan reason: "requested
   * vpcss"). Frame-wide (a planner input), not a solver option.
   */
  vtkSetMacro(KeepRequestedMethod, bool);
  vtkGetMacro(KeepRequestedMethod, bool);
  vtkBooleanMacro(KeepRequestedMethod, bool);
  void SetInteractiveUpdateRate(double rate); ///< clamped to 1e-6..1e6; NaN: an error, the rate kept
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
  /**
   * For applications (C++ and Python) whose data may hold broken geometry
   * reaching far out, such as a lost vertex at 1e10. VTK's
   * ResetCameraClippingRange() spans every prop's bounds and keeps the near
   * plane at 1/1000 of the far one, so such a vertex puts the near plane past
   * the scene and the picture comes out empty.
   * ResetClippingRangeToVisibleCells sets the active camera's range from the
   * cells in view instead, and moves the near plane to the nearest cell where
   * it passed it (ssClippingRange.h; the CLI and ParaView's Soft Shadow View
   * do this). Call it after the camera moves; it walks the cells, in runs
   * cached while the data is unchanged.
   * ShiftFarReachingMappersToTheFocalPoint draws a mesh whose bounds' centre
   * lies more than 100 camera distances from the focal point, while its
   * bounds come within 100, with float coordinates shifted to the focal
   * point: VTK's shift to its bounds' centre puts its near part on a coarse
   * grid (a strip from the scene to 1e10 vanished).
   */
  static void ResetClippingRangeToVisibleCells(vtkRenderer* renderer);
  static void ShiftFarReachingMappersToTheFocalPoint(vtkRenderer* renderer);
  ///@}

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
   * The V of translucent receivers (props not in the G-buffer, whose
   * fragments compute V in the shading stage; VPCSS and AVSM), for tests
   * and diagnostics. With CaptureTranslucentReceivers set to a shadow
   * light's index (default -1: off), the next frames' shading also stores,
   * per pixel, the V that light's solver gave the translucent fragment drawn
   * there last, that fragment's position (relative to
   * GetLastPositionsOrigin) and the normal of the plane its filter used.
   * GetTranslucentReceiverImages reads the last frame's back (1, 3 and 3
   * components per pixel, NaN where no translucent receiver was shaded);
   * false when nothing was captured. The capture needs GL 4.4; the shaders
   * carry its code only while it is on.
   */
  vtkSetMacro(CaptureTranslucentReceivers, int);
  vtkGetMacro(CaptureTranslucentReceivers, int);
  /**
   * Translucent receivers' V once per fragment. With depth peeling, a
   * translucent receiver's fragment takes part in every peel, and llvmpipe
   * runs its whole shader in each; without, it runs its lookup at the lanes
   * its small triangles fill. With ListTranslucentFragments on (default),
   * the pass draws the translucent receivers once first, listing their
   * fragments per pixel, runs VPCSS's or hard AVSM's per-fragment lookup
   * once per listed fragment in a full-screen pass, and the shading reads
   * each fragment's V from the lists (ssFragmentLists): the same V. Off, or
   * past the lists' memory budget, the shading (every peel) runs the
   * lookup. The stats' "translucent_receivers" tells which.
   */
  vtkSetMacro(ListTranslucentFragments, bool);
  vtkGetMacro(ListTranslucentFragments, bool);
  vtkBooleanMacro(ListTranslucentFragments, bool);
  bool GetTranslucentReceiverImages(vtkFloatArray* visibility, vtkFloatArray* positions, vtkFloatArray* normals);
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

#ifndef __VTK_WRAP__
  /**
   * The visible actors of a renderer (assembly leaves included) with their
   * world matrices, as the pass walks them for its caster set. C++ only;
   * the GEARS bench captures the same triangles with it.
   */
  static void ForEachVisibleActor(vtkRenderer* ren, const std::function<void(vtkActor*, vtkMatrix4x4*)>& f);
#endif

protected:
  vtkSoftShadowPass();
  ~vtkSoftShadowPass() override;

  int Method = AUTO;
  vtkRenderPass* DelegatePass = nullptr;
  int ShadowMapSize = 2048;
  double ConstantBias = 1.0;
  double SlopeBias = 2.0;
  double NormalOffset = 0.0;
  bool FitViewsToVisibleReceivers = true;
  double PositionsOrigin[3] = { 0, 0, 0 };
  bool AutomaticPositionsOrigin = true;
  bool MeasureTimings = false;
  bool AdaptToFrameBudget = true;
  bool KeepRequestedMethod = false;
  int CaptureTranslucentReceivers = -1;
  bool ListTranslucentFragments = true;
  double InteractiveUpdateRate = 0.1;

private:
  vtkSoftShadowPass(const vtkSoftShadowPass&) = delete;
  void operator=(const vtkSoftShadowPass&) = delete;

  // The stages of Render (vtkSoftShadowPass.cxx says which file owns what).
  void PlanFrame(bool unchangedSinceLastFrame, double frameBudgetMs);
  void RenderGBuffer(const vtkRenderState* s);
  void SolveVisibility(const vtkRenderState* s);
  void FindTranslucentReceivers(const vtkRenderState* s);
  void RecordTranslucentReceivers(const vtkRenderState* s);
  void Shade(const vtkRenderState* s);

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
