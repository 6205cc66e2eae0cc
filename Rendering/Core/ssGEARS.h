#ifndef ssGEARS_h
#define ssGEARS_h

#include "ssLightFrame.h"
#include "ssSolveProgress.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ss
{
/// How a cell's triangles are rasterised into a pixel's k x k light bitmask.
enum class GearsRaster
{
  EdgePlane, ///< exact: three edge planes through the pixel sample + the triangle's plane [GEARS §4.2]
  LUT        ///< 2-D lookup table of half-plane bitmasks [GEARS §4.3, ED07/SEA08]; approximate
};

/// Which instruction set the per-pixel kernels use. Auto takes the widest
/// the CPU has; asking for one the CPU lacks falls back to the next narrower.
/// Every choice gives the same bitmasks (tested).
enum class GearsSimd
{
  Auto,
  Scalar, ///< the x86-64 baseline (SSE2)
  AVX2,
  AVX512
};

struct GearsOptions
{
  int k = 16;                    ///< k x k regular light samples, 1..32 (point lights: 1)
  /// grid G resolution (G x G cells); 0: automatic, 64 where the winding
  /// count runs, else 128 (§4.3 Table 7's best for the raster; gears.md)
  int grid = 0;
  double eyeDistance = 1.0;      ///< |C L_m| in light diagonals [§3.1]
  bool retractToFarthest = true; ///< the P_far optimisation [§3.1, Fig. 5]
  bool countNecessary = false;   ///< Table 9 "necessary" assignments (no early exit, slower)
  /// With countNecessary: count the assignments as the timed solve makes
  /// them. The winding count runs (where it would), and the pairs it gives
  /// a pixel are the triangles of the contour edges tested there, not every
  /// member of the group (gears.md "Table 9 as the solve assigns"). false:
  /// every pair that survives the culling is drawn and counted.
  bool necessaryWithWinding = false;
  GearsRaster raster = GearsRaster::EdgePlane;
  int lutResolution = 512;       ///< LUT: angles x distances
  // Culling (gears.md, "Fewer assignments"); none of these changes a bitmask.
  bool closedMeshRule = true;    ///< drop faces of closed pieces that cannot bound the shadow (SetPieces)
  bool shaftCulling = true;      ///< cull clusters and triangles against each cell's and group's shaft
  bool pairRejection = true;     ///< per pixel, reject pairs before rasterising (vectorised kernel)
  bool depthOrder = true;        ///< blockers nearest the receivers first (masks fill early)
  bool horizonCulling = true;    ///< cull clusters (per cell) and triangles (per group) below every sample's tangent plane
  bool occluderCulling = true;   ///< cull clusters every segment to which passes through a drawn inner occluder
  /// With the winding count, a cell's inner occluders are drawn into its
  /// masks while they fill at least half of the masks they were drawn into,
  /// judged from the cell's first occluderProbe open samples on (a partly
  /// filled mask saves the winding count little; gears.md, "Inner occluders
  /// drawn where they fill masks"). 0: into every open mask. No mask changes.
  int occluderProbe = 4;
  int groupSize = 0;             ///< split a cell's samples into groups of at most this many (0: 16 with the winding count, else 8)
  int groupMinTriangles = 48;    ///< ... when its culled list has at least this many triangles
  /// A pixel's mask from the contour edges of the triangles of its list that
  /// lie between it and the light (a winding count; same bits as the raster,
  /// gears.md "The winding count") for lists of at least windingMinList
  /// triangles; opaque casters, a rect or directional light, k > 1.
  bool windingCount = true;
  int windingMinList = 32;
  /// A group's rest (the list entries the winding count leaves to the raster)
  /// of at least this many entries is culled again per part of 4 samples of
  /// the group, against the part's shaft and horizons (same bits; gears.md,
  /// ninth and eleventh rounds).
  int restSplitMin = 128;
  /// Small candidates wholly between S and the light get their bits from
  /// their projection in float where every sample is decided beyond the
  /// rounding bound (same bits; gears.md "Small triangles in float"), the
  /// others from the exact raster. It reads its inputs as the per-pair
  /// rejection compacts them, so it runs only with pairRejection.
  bool filteredRaster = true;
  /// A rect or point light deeper than kFarLightRatio scene diagonals in front
  /// of the casters is solved as the directional light a projective map of
  /// the scene turns it into (exact up to float rounding of the mapped
  /// vertices; gears.md "Far lights"); false: in its own float frame, whose
  /// culling margin then outgrows the scene (same V, far slower).
  bool farLightWarp = true;
  /// GL backend: a grid cell's samples are split where their depths leave a
  /// gap into up to this many lists (1-4; same bits, gears.md "Depth layers
  /// on the GL backend"). The CPU backend's sample groups do this there.
  int depthLayers = 2;
  GearsSimd simd = GearsSimd::Auto;
  SolveProgress progress;        ///< optional: called between chunks of step 4's cells; false stops
};

/// The paper's tables for one Solve: stage times (Table 2), grid load
/// (Table 8) and triangle-to-pixel assignments (Table 9).
struct GearsStats
{
  // Table 2 stages, milliseconds
  double msProject = 0;   ///< 3.1 + 3.2: camera C, pixel samples to cells, cell max depth
  double msPrefixSum = 0; ///< 3.3 pass 1: shadow-volume AABBs (with P_far) + prefix sum of cellsN
  double msRelate = 0;    ///< 3.3 pass 2: (triID, cellID) pairs written
  double msSort = 0;      ///< pairs sorted on cellID, per-cell ranges
  double msRaster = 0;    ///< step 4: bitmasks (point light: the one-bit test, irregular z-buffer)
  double msTotal = 0;
  std::size_t triangles = 0;     ///< triangles in the solver
  std::size_t samples = 0;       ///< pixel samples lit by the light (in front of it)
  std::size_t gridCells = 0;     ///< G x G (x faces for a point light)
  int grid = 0;                  ///< G as used (GearsOptions::grid 0: automatic)
  int layers = 0;                ///< GL backend: depth layers per grid cell, the most a face used (depthLayers)
  std::size_t layersRetried = 0; ///< GL backend: faces whose pass 1 found the layers' pairs too many and ran again
  std::size_t nonEmptyCells = 0; ///< cells with at least one pixel sample (GL: lists, a cell's layers each)
  std::size_t pairs = 0;         ///< (triID, cellID) pairs
  std::size_t trianglesPerCellMax = 0;
  double trianglesPerCellAvg = 0; ///< over non-empty cells
  std::size_t samplesPerCellMax = 0;
  double samplesPerCellAvg = 0;
  double assignmentsTotal = 0;     ///< (pixel, triangle) pairs left after the per-pair rejection
  double assignmentsNecessary = -1; ///< of those, triangles hiding >= 1 sample above the pixel's horizon (-1: not counted)
  std::size_t fullGridTriangles = 0; ///< clusters touching the light plane, given every cell
  std::size_t lutFallbacks = 0;      ///< LUT mode: pixel-triangle pairs rasterised by edge planes
  // Beyond the paper: what the culling removed (gears.md, "Fewer assignments")
  double msPrepare = 0;              ///< light-frame triangles, closed-mesh rule, cluster boxes
  std::size_t prepareReused = 0;     ///< faces whose prepared triangles came from the previous solve (same casters and light)
  std::size_t clusters = 0;          ///< triangle clusters
  std::size_t clusterPairs = 0;      ///< (cluster, cell) pairs of pass 2
  std::size_t droppedTriangles = 0;  ///< closed-mesh rule: faces facing away from the whole light
  std::size_t clustersCulled = 0;    ///< (cluster, cell) pairs culled by the cell's shaft
  std::size_t trianglesCulled = 0;   ///< (triangle, cell) pairs culled by the cell's shaft
  std::size_t clustersBelowHorizon = 0;  ///< (cluster, cell) pairs below every sample's tangent plane (horizonCulling)
  double trianglesBelowHorizon = 0;      ///< (triangle, group) pairs below every sample's tangent plane (horizonCulling)
  std::size_t clustersBehindOccluders = 0; ///< (cluster, cell) pairs hidden behind a drawn inner occluder (occluderCulling)
  std::size_t groups = 0;            ///< sample groups (cells split into groups)
  double assignmentsListed = 0;      ///< sum over pixels of their group's list (before per-pair rejection)
  double assignmentsRasterised = 0;  ///< pairs that reached the exact raster (a full mask stops early)
  std::size_t coveredSkips = 0;      ///< pairs not drawn: the samples they may hide are hidden already
  std::size_t outsidePyramid = 0;    ///< pairs straddling S's depth rejected outside the pixel's pyramid to the samples
  std::size_t occluderBoxes = 0;     ///< inner occluders of closed pieces (SetPieces)
  std::string simd;                  ///< the kernels' instruction set
  bool farLightWarped = false;       ///< the light was far: solved through the projective map (farLightWarp)
  /// Step 4's parts in thread time (ms summed over the threads; a profile,
  /// not wall time): cell lists (clusters and triangles against the cell's
  /// shaft with their kernel arrays, the inner occluders' pre-pass), the
  /// sample groups, and the pixels (rejection, exact raster, V).
  double cpuCellLists = 0, cpuGroups = 0, cpuPixels = 0;
  std::size_t cellsInUmbra = 0; ///< cells whose samples the horizon and inner occluders left in umbra
  std::size_t occluderDrawsStopped = 0; ///< cells where an open mask went without the inner occluders' draw (occluderProbe)
  // the winding count (windingCount): pixels it solved, pixels it declined
  // (rasterised instead), members counted and the rest of the lists
  // rasterised (summed over sample groups; GL: over lists, a grid cell's
  // depth layers each), contour edges stepped exactly
  // (summed over pixels)
  std::size_t windingPixels = 0, windingDeclined = 0;
  std::size_t filteredPairs = 0; ///< pairs whose bits the filtered float test gave (filteredRaster)
  double windingMembers = 0, windingRest = 0, windingContour = 0;
  double windingTested = 0; ///< contour edges tested per pixel (summed over pixels): the count's assignments
  /// necessaryWithWinding: the triangles of the contour edges tested per
  /// pixel (each once per pixel; not in assignmentsTotal), and of those the
  /// ones hiding >= 1 sample above the horizon (-1: not counted)
  double contourTriangles = 0, contourNecessary = -1;
  /// necessaryWithWinding: of windingTested, the edges whose own steps change
  /// the count at a sample above the horizon (-1: not counted)
  double contourEdgesNecessary = -1;
};

/// Folds one solve's stats into a frame's (several lights, cube faces): times,
/// counts and pairs summed, maxima kept, averages weighted by non-empty cells,
/// the per-solver facts (triangles, clusters, occluder boxes, kernels) taken
/// from the latest; a "not counted" (-1) stays -1 until a solve counts it.
/// Every field of GearsStats, so that no stat reads 0 when it happened.
void AddGearsStats(GearsStats& a, const GearsStats& st);

/// One pixel's light bitmask: row j (light v axis), bit i (light u axis);
/// a set bit is a blocked (or below-horizon) light sample.
using GearsMask = std::array<std::uint32_t, 32>;

/// Camera C and grid G of one face [§3.1, §3.2], shared by the CPU solver and
/// the GL compute backend. Perspective for rect and point lights (eye behind
/// the light, image plane parallel to it, axes along its edges), orthographic
/// along the light direction for directional lights. All positions are in the
/// solver's frame (relative to the caster centre).
struct GearsGridCamera
{
  bool ortho = false;
  glm::dvec3 E{ 0.0 }, Lc{ 0.0 }, u{ 1, 0, 0 }, v{ 0, 1, 0 }, n{ 0, 0, 1 };
  double eyeDepth = 0.0; ///< depth of E below the light plane (perspective)
  double gx0 = 0, gy0 = 0, sx = 1, sy = 1;
  int G = 1;

  /// Depth of X: distance in front of the light plane (rect, point), or along
  /// the light's direction (directional).
  double Depth(const glm::dvec3& X) const { return glm::dot(X - Lc, n); }
  glm::dvec2 Project(const glm::dvec3& X) const
  {
    const glm::dvec3 r = X - (ortho ? Lc : E);
    if (ortho)
    {
      return { glm::dot(r, u), glm::dot(r, v) };
    }
    const double z = glm::dot(r, n);
    return { glm::dot(r, u) / z, glm::dot(r, v) / z };
  }
  glm::dvec2 ToGrid(const glm::dvec2& p) const { return { (p.x - gx0) * sx, (p.y - gy0) * sy }; }
  int Cell(const glm::dvec2& g) const;
};

/// Face `face`'s axes (rect, directional: the light's; point: cube face
/// +x -x +y -y +z -z) and eye, from the 3-D AABB [lo, hi] of the face's pixel
/// samples; the light corners are added here [§3.1]. L is relative to the
/// solver's frame.
GearsGridCamera GearsFaceCamera(const LightFrame& L, int face, glm::dvec3 lo, glm::dvec3 hi, double eyeDistance);
/// Fits the G x G grid to the 2-D AABB [x0, x1] x [y0, y1] of the projected
/// samples, with a hair of margin [§3.2].
void GearsFitGrid(GearsGridCamera& C, int G, double x0, double x1, double y0, double y1);

/// The solver's triangles as the GL backend uploads them: 9 floats per
/// triangle relative to `center`, one opacity per triangle.
struct GearsTriangleData
{
  const float* vertices = nullptr;
  const float* opacity = nullptr;
  std::size_t count = 0;
  glm::dvec3 center{ 0.0 };
  double extent = 1.0;  ///< all triangles' diagonal (culling margins)
  double scale = 1.0;   ///< the bulk's diagonal: start offsets (ssTriangleSet.h StartOffset)
  bool translucent = false;
  std::uint64_t version = 0; ///< changes with every SetTriangles and SetClusters (for caches)
};

/// Which caster triangles form closed pieces, for the closed-mesh rule
/// (gears.md, "Closed pieces"). A piece is closed when it is a 2-manifold
/// without boundary whose faces are consistently oriented (every edge shared
/// by exactly two of its triangles, in opposite directions) and its winding
/// number is >= 0 everywhere (outward normals, nothing turned inside out).
/// Triangles of such a piece that face away from every light sample hide
/// nothing that its other triangles do not hide already, as long as no light
/// sample lies inside the piece; GEARS checks the latter itself.
struct GearsPieces
{
  /// per input triangle (vertex list / 3, as given to SetTriangles): its piece
  std::vector<std::uint32_t> piece;
  /// per piece: +1 closed with outward normals (counter-clockwise seen from
  /// outside), -1 closed with inward normals, 0 not closed or not known
  std::vector<std::int8_t> orientation;
};

/// The assignment built by step 3, exposed for tests and tools.
struct GearsAssignment
{
  struct Face
  {
    int grid = 0;
    std::vector<std::uint32_t> cellBegin;      ///< grid*grid + 1 offsets into triangles
    std::vector<std::uint32_t> triangles;      ///< per cell: its triangles after the shaft culling
    std::vector<std::uint32_t> groupBegin;     ///< groups + 1 offsets into groupTriangles
    std::vector<std::uint32_t> groupTriangles; ///< per sample group: its triangles (the pixels' lists)
  };
  std::vector<Face> faces;              ///< 1 (rect, directional) or up to 6 (point)
  std::vector<std::int32_t> pixelFace;  ///< per pixel: face, or -1 (not in any cell)
  std::vector<std::int32_t> pixelCell;  ///< per pixel: cell in its face
  std::vector<std::int32_t> pixelGroup; ///< per pixel: sample group in its face
};

/// GEARS (Wang et al., "A General and Efficient Algorithm for Rendering
/// Shadows"): for each pixel sample, the exact fraction of k x k regular
/// light samples it sees, from the triangles that a grid assigns to it.
///
/// The samples, the start offset along the normal and the tangent-plane rule
/// are those of ReferenceSolver with LightSamplePattern::Regular, so both give
/// the same V up to samples that graze an edge. Translucent triangles
/// (0 < opacity < 1) multiply a per-sample transmittance, as in the reference.
///
/// Multithreaded with TBB; no VTK, no GL, so a baking filter can reuse it.
class GearsSolver
{
public:
  GearsSolver();
  ~GearsSolver();
  GearsSolver(const GearsSolver&) = delete;
  GearsSolver& operator=(const GearsSolver&) = delete;

  /// Same contract as ReferenceSolver::SetTriangles: 3 world vertices per
  /// triangle; non-finite and zero-area triangles are skipped; opacity 0
  /// triangles cast nothing and are skipped too.
  void SetTriangles(const std::vector<glm::dvec3>& vertices, const std::vector<float>& opacity);
  std::size_t NumberOfTriangles() const;
  std::size_t SkippedTriangles() const;
  /// Index of solver triangle t in the vertex list given to SetTriangles.
  std::size_t InputIndex(std::size_t t) const;

  /// Closed pieces for the closed-mesh rule (call after SetTriangles; a new
  /// SetTriangles forgets them). Pieces whose triangles are not all opaque
  /// are treated as open. Throws std::invalid_argument if `piece` does not
  /// have one entry per input triangle or names a piece out of range.
  void SetPieces(const GearsPieces& pieces);
  /// Triangle clusters (e.g. from the Filters module): ss::TriangleClusters'
  /// order and first over the input triangles. SetTriangles makes its own
  /// (ss::ClusterTriangles, 32 triangles). Keeps the pieces. Throws
  /// std::invalid_argument if the order is not a permutation of the input.
  void SetClusters(const std::vector<std::size_t>& order, const std::vector<std::size_t>& first);
  std::size_t NumberOfClusters() const;
  /// The closed-mesh rule as Solve applies it for `light` (world): per
  /// solver triangle 0 (rule off), +1 / -1 (its closed piece's orientation,
  /// for the per-pixel test "S behind the outward face"), or 2 (faces away
  /// from every light sample: never drawn). For the GL backend.
  std::vector<std::int8_t> ClosedRuleFlags(const LightFrame& light, const GearsOptions& options) const;
  std::size_t ClosedTriangles() const; ///< triangles of closed pieces (SetPieces)

  /// Same contract as ReferenceSolver::Solve. masks (optional) receives one
  /// GearsMask per pixel (opaque blockers and below-horizon samples).
  std::vector<float> Solve(const LightFrame& light, const glm::dvec3& origin, const float* positions,
    const float* normals, std::size_t n, const GearsOptions& options, GearsStats* stats = nullptr,
    std::vector<GearsMask>* masks = nullptr, GearsAssignment* assignment = nullptr) const;

  /// The start point of pixel rays (world) under `light` (world): surface
  /// point pushed along the normal by the offset the reference uses.
  glm::dvec3 RayStart(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& normal) const;
  /// Triangle t's world vertices (after SetTriangles' filtering).
  std::array<glm::dvec3, 3> Triangle(std::size_t t) const;
  /// The triangles as stored (for the GL backend, which uploads them).
  GearsTriangleData Data() const;
  /// For the GL backend's winding count: per stored triangle t and edge m
  /// (vertices m, m + 1 mod 3) the stored triangle across it, with the same
  /// two bit-identical vertices, as its index | 0x80000000 when the edge runs
  /// the same way in both, or 0xFFFFFFFF (a boundary; an edge held by three
  /// triangles pairs two of them). Computed on each call (0.3 s on 5M).
  std::vector<std::uint32_t> EdgeNeighbours() const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

/// Exact edge-plane rasterisation of one triangle (world vertices) into the
/// k x k bitmask seen from `start` [§4.2]: the bits of the light samples whose
/// segment from start crosses the triangle. Exposed for tests.
void GearsRasterizeTriangle(const LightFrame& light, const glm::dvec3& start,
  const std::array<glm::dvec3, 3>& tri, int k, GearsMask& mask);
/// The brute-force form of the same predicate for light sample (i, j).
bool GearsSampleBlocked(const LightFrame& light, const glm::dvec3& start,
  const std::array<glm::dvec3, 3>& tri, int k, int i, int j);

std::string GearsStatsToJSON(const GearsStats& s);
}

#endif
