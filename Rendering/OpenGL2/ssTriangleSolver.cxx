#include "ssTriangleSolver.h"

#include "vtkSoftShadowPass.h"

#include "ssCasterSet.h"
#include "ssFrameState.h"
#include "ssGBuffer.h"
#include "ssGearsGL.h"
#include "ssPassStats.h"
#include "ssVisibilityLayers.h"
#include "ssVolumeCasters.h"

#include "vtkObject.h"
#include "vtkOpenGLError.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkSetGet.h"

#include <algorithm>
#include <sstream>

namespace ss
{
TriangleSolver::TriangleSolver(Method method)
  : VisibilitySolver(method)
{
}

TriangleSolver::~TriangleSolver() = default;

const OptionList& TriangleSolver::DeclaredOptions()
{
  // key, property (Python, ParaView), label, range or names, default, help
  static const OptionList options = {
    IntOption("reference_samples", "ReferenceSamples", "Reference Samples", 1, 64, 32,
      "reference: k x k light samples"),
    EnumOption("reference_pattern", "ReferencePattern", "Reference Pattern", { "regular", "stratified" }, 0,
      "reference: light sample pattern"),
    IntOption("gears_samples", "GearsSamples", "Gears Samples", 1, 32, 16, "gears: k x k light samples"),
    IntOption("gears_grid", "GearsGrid", "Gears Grid", 0, 1024, 0,
      "gears: grid cells a side (0: automatic, 64 with the winding count, else 128)"),
    EnumOption("gears_raster", "GearsRaster", "Gears Raster", { "edge", "lut" }, 0,
      "gears: exact edge planes or the lookup table"),
    EnumOption("gears_backend", "GearsBackend", "Gears Backend", { "cpu", "gl" }, 0,
      "gears: CPU (TBB) or GL 4.3 compute (without GL 4.3: the CPU, with one warning)"),
    BoolOption("gears_necessary", "GearsCountNecessary", "Gears Count Necessary", false,
      "gears: count Table 9's necessary assignments (slower)"),
    BoolOption("gears_find_pieces", "GearsFindPieces", "Gears Find Pieces", true,
      "gears: find the closed pieces of casters that are not prepared (closed-mesh rule, inner occluders; same V)"),
    BoolOption("gears_winding", "GearsWinding", "Gears Winding", true,
      "gears: on dense meshes, each pixel's mask from the contour edges of the triangles between it and the light (a winding count; same V)"),
    BoolOption("gears_cell_culling", "GearsCellCulling", "Gears Cell Culling", true,
      "gears: cull clusters and triangles per grid cell and sample group (shaft, horizon, inner occluders; same V)"),
    IntOption("gears_gl_layers", "GearsGLLayers", "Gears GL Layers", 1, 4, 2,
      "gears, GL backend: split each grid cell's samples where their depths leave a gap into up to this many "
      "lists (same V)"),
  };
  return options;
}

void TriangleSolver::Configure(vtkSoftShadowPass* pass)
{
  const auto opt = [pass](const char* key) { return static_cast<int>(pass->GetSolverOption(key)); };
  this->Opt.Reference.k = opt("reference_samples");
  this->Opt.Reference.pattern =
    opt("reference_pattern") == 1 ? LightSamplePattern::Stratified : LightSamplePattern::Regular;
  this->Opt.Gears.k = opt("gears_samples");
  this->Opt.Gears.grid = opt("gears_grid");
  this->Opt.Gears.windingCount = opt("gears_winding") != 0;
  this->Opt.Gears.depthLayers = opt("gears_gl_layers");
  this->Opt.Gears.raster = opt("gears_raster") == 1 ? GearsRaster::LUT : GearsRaster::EdgePlane;
  this->Opt.Gears.countNecessary = opt("gears_necessary") != 0;
  this->Opt.GearsOnGL = opt("gears_backend") == vtkSoftShadowPass::GEARS_BACKEND_GL;
  this->Opt.GearsFindPieces = opt("gears_find_pieces") != 0;
  // 0: the paper's assignment (every triangle to every cell its shadow
  // volume's box covers), for measuring what the culling saves
  const bool cellCulling = opt("gears_cell_culling") != 0;
  this->Opt.Gears.shaftCulling = cellCulling;
  this->Opt.Gears.horizonCulling = cellCulling;
  this->Opt.Gears.occluderCulling = cellCulling;
}

void TriangleSolver::BeginFrame(SolverFrame&, const std::vector<const ShadowLight*>& lights)
{
  this->Active = !lights.empty();
  this->SolveMs = 0.0;
  this->HaveTriangles = false;
  this->LastReferenceStats = ReferenceStats{};
  this->LastGearsStats = GearsStats{};
  this->GearsLights = 0;
  this->PiecesThisFrame = false;
  this->PiecesAborted = false;
  this->BackendUsed = "none"; // (until a GEARS solve runs this frame)
  this->BackendNote.clear();
}

void TriangleSolver::Compute(SolverFrame& frame, const ShadowLight& l)
{
  // --- the input: the caster set (again when it changed) and the G-buffer
  const auto t0 = Clock::now();
  const bool reference = this->GetMethod() == Method::Reference;
  const CasterSet& casters = *frame.Casters;
  // a frame that searches for closed pieces gives the search the first half
  // of its first light's progress and the solve the second
  double searchShare = 0.0;
  if (!this->HaveTriangles)
  {
    if (reference && (!this->Reference || this->Version != casters.Version))
    {
      if (!this->Reference)
      {
        this->Reference.reset(new ReferenceSolver);
      }
      this->Reference->SetTriangles(casters.WorldVertices(), casters.Opacity);
      this->Version = casters.Version;
    }
    if (reference)
    {
      // the volumes attenuate the rays as in the AVSM march: exp(-integral
      // of sigma) of the same grids (ssVolumeCasters; issue 20), so the
      // reference's error against vpcss/avsm is meaningful for volumes
      if (!this->HaveVolumes || this->VolumeGridsVersion != casters.VolumeVersion)
      {
        this->Volumes.Update(casters, frame.Reporter);
        this->Reference->SetVolumes(this->Volumes.Grids());
        this->VolumeGridsVersion = casters.VolumeVersion;
        this->HaveVolumes = true;
      }
    }
    if (!reference &&
      (!this->Gears || this->Version != casters.Version || this->PiecesFound != this->Opt.GearsFindPieces))
    {
      if (!this->Gears)
      {
        this->Gears.reset(new GearsSolver);
      }
      const std::vector<glm::dvec3> world = casters.WorldVertices();
      this->Gears->SetTriangles(world, casters.Opacity);
      // the closed pieces, for the closed-mesh rule and the inner occluders:
      // prepared casters' (vtkShadowCasterPreparation upstream) from their
      // tables, the others' found here, per actor, once per caster set
      this->FoundPieces = GearsPieceCounts{};
      this->PiecesMs = this->PiecesSolverMs = 0.0;
      if (this->Opt.GearsFindPieces)
      {
        // a render abort stops the search between its stages; Version and
        // PiecesFound are set only below, so the next frame searches again
        searchShare = 0.5;
        const auto tp = Clock::now();
        const GearsPieces pieces =
          casters.FindPieces(world, this->FoundPieces, SubProgress(frame.Progress, 0.0, searchShare));
        const auto ts = Clock::now();
        this->PiecesMs = ss::Milliseconds(tp, ts);
        if (this->FoundPieces.aborted)
        {
          this->PiecesAborted = true;
          frame.Timings->Add("gears_pieces", this->PiecesMs);
          return;
        }
        this->Gears->SetPieces(pieces);
        this->PiecesSolverMs = ss::Milliseconds(ts, Clock::now());
        this->PiecesThisFrame = true;
        frame.Timings->Add("gears_pieces", this->PiecesMs + this->PiecesSolverMs);
      }
      else if (!casters.Piece.empty())
      {
        GearsPieces pieces;
        pieces.piece = casters.Piece;
        pieces.orientation = casters.PieceOrientation;
        this->Gears->SetPieces(pieces);
      }
      this->PiecesFound = this->Opt.GearsFindPieces;
      this->Version = casters.Version;
    }
    this->HaveTriangles = true;
  }
  const std::vector<float>* positions = nullptr;
  const std::vector<float>* normals = nullptr;
  const int W = frame.State->Width, H = frame.State->Height;
  frame.GBuffer->ReadForCPU(frame.Window, frame.FBO, W, H, positions, normals);
  const float* pos = positions->data();
  const float* nrm = normals->data();
  const std::size_t n = static_cast<std::size_t>(W) * H;
  frame.Timings->Add("triangle_solver_input", ss::Milliseconds(t0, Clock::now()));

  // --- the light; its frame is relative to the frame origin, the solvers want
  // world. The CPU solvers take a far light as it is (double precision; GEARS
  // maps it exactly, gears.md "Far lights"). The GL backend has no such map,
  // so it declines a light the pass approximated (the CPU backend runs).
  const glm::dvec3& origin = frame.State->Origin;
  LightFrame world = l.TrueFrame, approximated = l.Frame;
  world.center += origin;
  approximated.center += origin;
  const auto tl = Clock::now();
  std::vector<float> V;
  if (reference)
  {
    ReferenceStats st;
    ReferenceOptions opt = this->Opt.Reference;
    opt.progress = frame.Progress;
    V = this->Reference->Solve(world, origin, pos, nrm, n, opt, &st);
    this->LastReferenceStats.rays += st.rays;
    this->LastReferenceStats.milliseconds += st.milliseconds;
  }
  else
  {
    GearsStats st;
    bool onGPU = false;
    if (this->Opt.GearsOnGL)
    {
      if (!this->GL)
      {
        this->GL.reset(new GearsGL);
      }
      // raw GL programs: VTK's shader cache must rebind its own afterwards
      frame.Window->GetShaderCache()->ReleaseCurrentShader();
      std::string why;
      if (l.Frame.type != l.TrueFrame.type)
      {
        why = "GEARS GL backend: a far light (the CPU backend maps it exactly; the GL backend would draw the "
              "pass's directional approximation)";
      }
      else
      {
        onGPU =
          this->GL->Solve(*this->Gears, approximated, origin, pos, nrm, n, this->Opt.Gears, V, &st, nullptr, &why);
      }
#ifdef VTK_REPORT_OPENGL_ERRORS
#define ssReporterError(x) vtkErrorWithObjectMacro(frame.Reporter, x)
      vtkOpenGLCheckErrorMacroImpl(ssReporterError, "after the GEARS compute backend");
#undef ssReporterError
#endif
      if (!onGPU)
      {
        this->BackendNote = why;
        if (this->Warned != why)
        {
          vtkWarningWithObjectMacro(frame.Reporter, << why << "; GEARS runs on the CPU.");
          this->Warned = why;
        }
      }
    }
    if (!onGPU)
    {
      GearsOptions opt = this->Opt.Gears;
      opt.progress = SubProgress(frame.Progress, searchShare, 1.0);
      V = this->Gears->Solve(world, origin, pos, nrm, n, opt, &st);
    }
    this->BackendUsed = onGPU ? "gl" : "cpu";
    this->Accumulate(st);
  }
  this->SolveMs += ss::Milliseconds(tl, Clock::now());
  frame.Visibility->Upload(l.Layer, V);
}

void TriangleSolver::EndFrame(SolverFrame& frame)
{
  this->LastReferenceStats.raysPerSecond = this->LastReferenceStats.milliseconds > 0
    ? this->LastReferenceStats.rays / (this->LastReferenceStats.milliseconds * 1e-3)
    : 0.0;
  if (this->Active)
  {
    frame.Timings->Set(this->GetMethod() == Method::Reference ? "reference" : "gears", this->SolveMs);
  }
}

void TriangleSolver::Accumulate(const GearsStats& st)
{
  AddGearsStats(this->LastGearsStats, st); // (ssGEARS.h: every field)
  ++this->GearsLights;
}

std::string TriangleSolver::GetStatsJSON() const
{
  std::ostringstream o;
  o.precision(17);
  if (this->GetMethod() == Method::Reference)
  {
    o << "{\"samples_per_axis\": " << this->Opt.Reference.k << ", \"rays\": " << this->LastReferenceStats.rays
      << ", \"rays_per_second\": " << this->LastReferenceStats.raysPerSecond << "}";
    return o.str();
  }
  o << "{\"samples_per_axis\": " << this->Opt.Gears.k << ", \"grid\": " << this->Opt.Gears.grid
    << ", \"raster\": \"" << (this->Opt.Gears.raster == GearsRaster::LUT ? "lut" : "edge")
    << "\", \"backend\": \"" << this->BackendUsed << "\", \"backend_requested\": \""
    << (this->Opt.GearsOnGL ? "gl" : "cpu") << "\", \"backend_note\": \"" << JSONEscape(this->BackendNote) << "\""
    << ", \"lights\": " << this->GearsLights << ", \"stats\": " << GearsStatsToJSON(this->LastGearsStats)
    << ", \"pieces\": {\"find\": " << (this->PiecesFound ? "true" : "false")
    << ", \"found_this_frame\": " << (this->PiecesThisFrame ? "true" : "false")
    << ", \"search_aborted\": " << (this->PiecesAborted ? "true" : "false")
    << ", \"pieces_found\": " << this->FoundPieces.pieces << ", \"closed_pieces\": " << this->FoundPieces.closedPieces
    << ", \"closed_triangles\": " << this->FoundPieces.closedTriangles << ", \"find_ms\": " << this->PiecesMs
    << ", \"set_ms\": " << this->PiecesSolverMs
    << ", \"solver_closed_triangles\": " << (this->Gears ? this->Gears->ClosedTriangles() : 0) << "}}";
  return o.str();
}

void TriangleSolver::ReleaseGraphicsResources(vtkWindow*)
{
  if (this->GL)
  {
    this->GL->ReleaseGraphicsResources();
    this->GL.reset();
  }
}
}
