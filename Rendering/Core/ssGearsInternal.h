// Internals of the GEARS CPU solver (ssGEARS.h), shared by its stages:
//   ssGearsGrid.cxx    grid camera C, pixel samples to cells [§3.1, §3.2]
//   ssGearsPairs.cxx   per-solve triangle and cluster data, the closed-mesh
//                      rule, cluster shadow volumes with P_far, pairs [§3.3]
//   ssGearsSort.cxx    the counting sort of pairs on their cell [§4.2]
//   ssGearsCells.cxx   per cell: shaft culling, split into sample groups,
//                      per-pixel rejection, bitmasks, V
//   ssGearsCull.cxx    culling rules beyond the shafts: horizon, inner occluders
//   ssGearsRaster.cxx  the exact bitmask of one triangle (edge planes, LUT) [§4.2, §4.3]
//   ssGearsSIMD*.cxx   the per-pixel rejection and row raster in AVX2 / AVX-512
//   ssGearsWinding.cxx a sample group's members, their contour edges, a pixel's count (kernels in ssGearsWindingKernels.h)
//   ssGearsFarLight.cxx a far rect or point light as the directional light it maps to
//   ssGearsSilhouette.cxx  a closed piece's mask from its silhouette edges (own header; not called by Solve yet)
//   ssGEARS.cxx        GearsSolver: input, options, statistics
// Not installed; not part of the API.
#ifndef ssGearsInternal_h
#define ssGearsInternal_h

#include "ssGEARS.h"
#include "ssGearsKernels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace ss
{
namespace gears
{
using Clock = std::chrono::steady_clock;
inline double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

/// bits lo..hi inclusive (0 <= lo <= hi <= 31)
inline std::uint32_t RowBits(int lo, int hi)
{
  return static_cast<std::uint32_t>(((std::uint64_t(2) << hi) - (std::uint64_t(1) << lo)) & 0xFFFFFFFFull);
}

/// The light's sample rectangle in its frame: a rect light's width and
/// height; a directional light's tangent square 2 tan(theta / 2), or, for the
/// directional light a far light maps to (MakeFarLightWarp; only Solve makes
/// such frames), the tangent rectangle held in its width and height.
inline glm::dvec2 SampleSides(const LightFrame& L)
{
  if (L.type != LightType::Directional || (L.width > 0.0 && L.height > 0.0))
  {
    return { L.width, L.height };
  }
  const double T = 2.0 * std::tan(0.5 * L.angularDiameter);
  return { T, T };
}

// Light sample directions seen from a start point S:
//   d(i, j) = D0 + su_i Du + sv_j Dv,  su_i = (i + 1/2)/k - 1/2  (same for v)
// rect: D0 = L_c - S, Du = w u, Dv = h v (the ReferenceSolver's regular samples);
// directional: D0 = -n, Du = T u, Dv = T v with T = 2 tan(theta/2) (directions);
// point: D0 = L_c - S, Du = Dv = 0 (k = 1).
struct SampleSpace
{
  glm::dvec3 D0, Du, Dv;
  int k = 1;
  double invK = 1.0;   ///< 1 / k
  bool segment = true; ///< finite light: a blocker must lie before the sample (t < 1)
};

/// An affine function of the sample indices, F(i, j) = A + B i + C j, of the
/// dot product of a fixed vector with d(i, j).
struct Affine
{
  double A, B, C;
};

/// x . y as every exact path (and the GL backend) evaluates it.
inline double Dot3(const glm::dvec3& x, const glm::dvec3& y)
{
  return (x.x * y.x + x.y * y.y) + x.z * y.z;
}
/// x x y as every exact path (and the GL backend) evaluates it.
inline glm::dvec3 Cross3(const glm::dvec3& x, const glm::dvec3& y)
{
  return { x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y };
}

inline Affine MakeAffine(const SampleSpace& s, const glm::dvec3& e, double constant = 0.0)
{
  const double du = Dot3(e, s.Du), dv = Dot3(e, s.Dv);
  const double h = 0.5 * s.invK - 0.5;
  return { (constant + Dot3(e, s.D0)) + h * (du + dv), du * s.invK, dv * s.invK };
}

/// The one evaluation order of an affine sample function: F(i, j) =
/// (A + C j) + B i. A sample's bit is decided by the signs of these values
/// alone (edge planes >= 0, the triangle's plane > 0), so every way of
/// finding a row's samples (per sample, or a span corrected at its ends)
/// gives the same bits.
inline double RowValue(const Affine& f, double j)
{
  return f.A + f.C * j;
}

/// x clamped to [-2, k + 1]: the integers of [0, k - 1] a bound selects stay
/// the same, and floor/ceil below stay exact.
inline double ClampRange(double x, int k)
{
  return x < -2.0 ? -2.0 : (x > k + 1.0 ? k + 1.0 : x);
}
/// floor and ceil for |x| < 2^62 (the baseline x86-64 has no rounding
/// instruction; std::floor would be a library call per row)
inline double FloorSmall(double x)
{
  const double t = static_cast<double>(static_cast<long long>(x));
  return t > x ? t - 1.0 : t;
}
inline double CeilSmall(double x)
{
  const double t = static_cast<double>(static_cast<long long>(x));
  return t < x ? t + 1.0 : t;
}

/// Integer [il, ih] of real [lo, hi] for inclusive (ceil/floor) or strict
/// bounds (the strict constraint's interval is open: exclude exact endpoints).
inline bool IntRange(double lo, double hi, bool strictLo, bool strictHi, int k, int& il, int& ih)
{
  if (!(lo <= hi))
  {
    return false;
  }
  lo = ClampRange(lo, k);
  hi = ClampRange(hi, k);
  double l = CeilSmall(lo), h = FloorSmall(hi);
  if (strictLo && l == lo)
  {
    l += 1.0;
  }
  if (strictHi && h == hi)
  {
    h -= 1.0;
  }
  l = std::max(l, 0.0);
  h = std::min(h, static_cast<double>(k - 1));
  if (l > h)
  {
    return false;
  }
  il = static_cast<int>(l);
  ih = static_cast<int>(h);
  return true;
}

/// The triangle's constraint functions as seen from start S [§4.2]: three
/// edge planes (through S and an edge, oriented so the triangle is inside)
/// and, for a finite light, the triangle's plane separating S from the light
/// sample.
struct TriangleSetup
{
  Affine edge[3];
  Affine cross; ///< -sign(g) (g + nT.d) > 0 : the sample lies beyond the triangle's plane
  bool hasCross = false;
};

/// The light's frame seen from one pixel sample S (all in light coordinates:
/// origin L_c, axes u, v, n). Light sample (i, j) is (su W, sv H, 0) for a
/// finite light, or the direction (su T, sv T, -1) for a directional one.
struct LightSpace
{
  SampleSpace s;
  glm::dvec3 S;
  double W = 0, H = 0;
  double kx = 0, ky = 0, hk = 0; ///< k / W, k / H, k / 2 - 1/2: light plane to sample-index units
  bool dir = false;
};
LightSpace MakeLightSpace(const glm::dvec3& S, double W, double H, bool dir, int k);

/// 2-D lookup table of half-plane masks [§4.3, ED07, SEA08].
struct HalfPlaneLUT
{
  int k = 0, res = 0;
  double R = 0.75; ///< |r| beyond which a half-plane holds all or none of the samples
  std::vector<std::uint32_t> rows; ///< res * res * k
  void Build(int k, int res);
  /// mask of the half-plane left of p->q (interior side), into out (k rows)
  void Edge(double px, double py, double qx, double qy, std::uint32_t* out) const;
};

/// Beyond this |P| or |Q| a row's root is taken per row (RasterSetup).
constexpr double kSteep = 1e6;

/// The constraints of a triangle seen from S (SetupTriangle): edge planes,
/// and its own plane when `cross`; false if S lies in its plane.
bool SetupTriangle(const SampleSpace& s, const glm::dvec3& S, const glm::dvec3& B0, const glm::dvec3& B1,
  const glm::dvec3& B2, bool cross, TriangleSetup& t);
/// Rows [j0, j1] of the samples every constraint admits, ORed into rows.
bool RasterSetup(const TriangleSetup& t, int k, int j0, int j1, std::uint32_t* rows);

/// The exact bitmask of one triangle (light coordinates) seen from l.S
/// [§4.2]: the samples whose direction from S passes the three edge planes
/// (and the triangle's own plane, unless all three vertices lie strictly
/// between S and the light, where it holds anyway). [j0, j1]: the rows it
/// may touch; with a LUT [§4.3], triangles wholly between S and the light use
/// the table (fallback: this one could not).
bool RasterizeTriangle(const LightSpace& l, const glm::dvec3& S, const glm::dvec3& B0, const glm::dvec3& B1,
  const glm::dvec3& B2, const HalfPlaneLUT* lut, std::uint32_t* rows, int& j0, int& j1, bool& fallback);
/// Table 9's test: a triangle's rows j0..j1 hide a sample not below the
/// horizon (below: the pixel's below-horizon rows).
inline bool HidesAboveHorizon(const std::uint32_t* rows, const std::uint32_t* below, int j0, int j1)
{
  bool above = false;
  for (int j = j0; j <= j1; ++j)
  {
    above = above || (rows[j] & ~below[j]) != 0u;
  }
  return above;
}
/// The reference's start rule for a triangle whose plane passes within eps of
/// S: the samples its edge planes and plane cover, minus those whose hit
/// (Moeller-Trumbore distance) lies closer than eps to S. Samples set in
/// `known` (already hidden) are skipped.
bool RasterizeNearTriangle(const LightSpace& l, const glm::dvec3& B0, const glm::dvec3& B1, const glm::dvec3& B2,
  double eps, std::uint32_t* rows, const std::uint32_t* known);
/// Rows of the samples below the tangent plane with normal N (light frame).
void BelowHorizonRows(const SampleSpace& s, const glm::dvec3& N, std::uint32_t* rows);
SampleSpace MakeSampleSpace(const LightFrame& L, const glm::dvec3& Lc, const glm::dvec3& S, int k);

/// Which instruction set the per-pixel kernels use (GearsOptions::simd).
enum class Isa
{
  Scalar,
  AVX2,
  AVX512
};
/// The widest of `wanted` and what the CPU supports.
Isa ResolveIsa(GearsSimd wanted);
/// Whether the vector kernels' 32-bit float offsets into SolverData::V (9 t
/// + 8 for triangle t) reach every one of nt triangles: 9 nt - 1 < 2^31, up
/// to 238,609,294. Past that the solver runs the scalar kernels (64-bit
/// offsets) and without the winding count.
inline bool KernelOffsetsFit(std::size_t nt)
{
  return nt <= (static_cast<std::size_t>(1) << 31) / 9;
}
const char* IsaName(Isa isa);


// ---------------------------------------------------------------------------
// Grid
/// 2-D range-maximum table over the grid's cell max depths: O(1) P_far queries.
struct RangeMax
{
  int G = 0, L = 0;
  std::vector<float> t; ///< [ly][lx][y][x]
  float Get(int lx, int ly, int x, int y) const
  {
    return t[((static_cast<std::size_t>(ly) * L + lx) * G + y) * G + x];
  }
  void Build(const std::vector<float>& depth, int g);
  float Query(int x0, int y0, int x1, int y1) const; ///< inclusive
};

struct Box2
{
  int x0, y0, x1, y1; ///< inclusive cell range; empty if x0 > x1
  bool Empty() const { return x0 > x1 || y0 > y1; }
};

/// One face's pixel samples in their cells [§3.2].
struct FaceGrid
{
  GearsGridCamera C;
  std::vector<std::size_t> pix;        ///< pixels of this face
  std::vector<std::uint32_t> pixCell;  ///< per face pixel: its cell
  std::vector<std::uint32_t> cellStart; ///< NC + 1 offsets into cellPix
  std::vector<std::uint32_t> cellPix;  ///< face pixel indices sorted by cell
  std::vector<float> cellDepth;        ///< farthest sample depth per cell (rounded up)
  std::vector<std::uint32_t> sat;      ///< summed-area table of non-empty cells
  double maxDepth = 0.0;
  std::size_t nonEmpty = 0;
  std::uint32_t Count(std::size_t c) const { return cellStart[c + 1] - cellStart[c]; }
  std::uint32_t SatCount(const Box2& b) const
  {
    const int G = C.G;
    return sat[(b.y1 + 1) * (G + 1) + b.x1 + 1] - sat[b.y0 * (G + 1) + b.x1 + 1] -
      sat[(b.y1 + 1) * (G + 1) + b.x0] + sat[b.y0 * (G + 1) + b.x0];
  }
};
/// Camera C from the face's samples, the grid over their projections, the
/// samples sorted into cells, cell depths and the summed-area table.
void BuildFaceGrid(const LightFrame& L, int face, const std::vector<glm::dvec3>& start,
  const std::vector<std::int8_t>& pixelFace, std::size_t n, const GearsOptions& opt, FaceGrid& g);

// ---------------------------------------------------------------------------
// The solver's triangles (set once per SetTriangles / SetPieces / SetClusters)
struct SolverData
{
  glm::dvec3 center{ 0.0 };
  double extent = 1.0; ///< all triangles' diagonal (culling margins)
  double scale = 1.0;  ///< the bulk's diagonal (start offsets; ssTriangleSet.h)
  std::vector<float> V;                ///< 9 floats per triangle, relative to center, in cluster order
  std::vector<float> opacity;          ///< per triangle
  std::vector<std::size_t> input;      ///< input index per triangle
  std::vector<std::uint32_t> clusterFirst; ///< cluster c: triangles [first[c], first[c+1])
  std::vector<std::int8_t> orient;     ///< per triangle: its closed piece's orientation (0: not closed)
  std::vector<std::uint32_t> piece;    ///< per triangle: its piece (solver-local index)
  std::vector<double> pieceBox;        ///< per piece: min xyz, max xyz (solver frame)
  std::size_t skipped = 0, closedTriangles = 0;
  /// The real triangles are [0, real) in realClusters clusters; after them
  /// come the inner occluders of closed pieces (ssGearsOccluders.cxx), 12
  /// triangles and one cluster per box, kept here to append again.
  std::size_t real = 0, realClusters = 0;
  std::vector<float> occV;             ///< 108 floats per box
  std::vector<std::uint32_t> occPiece; ///< per box: its piece
  std::vector<double> occBox;          ///< per box: min xyz, max xyz (solver frame)
  bool translucent = false;
  std::uint64_t version = 0;
  std::uint64_t arrangement = 0; ///< changes whenever the triangles are arranged (GearsNeighbours)
  std::size_t Triangles() const { return opacity.size(); }
  std::size_t Clusters() const { return clusterFirst.empty() ? 0 : clusterFirst.size() - 1; }
  glm::dvec3 Vertex(std::size_t t, int j) const
  {
    const float* p = &V[9 * t + 3 * j];
    return { p[0], p[1], p[2] };
  }
};

constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu, kSameDirection = 0x80000000u, kSameCluster = 0x40000000u,
                        kNeighbourId = 0x3FFFFFFFu;
/// The winding count's edge neighbours of a SolverData's real triangles
/// (ssGearsWinding.cxx), built by the first solve that uses them.
struct GearsNeighbours
{
  /// Per real triangle t and edge m (vertices m, m + 1 mod 3): the triangle
  /// on the other side, with an edge between the same two bit-identical
  /// vertices (kSameDirection: running the same way), as its index in t's
  /// cluster (kSameCluster) or as an index into `across`, or kNoNeighbour (a
  /// boundary; an edge held by three triangles pairs two of them). Empty:
  /// none (too many triangles for the kernels' 32-bit offsets).
  std::vector<std::uint32_t> nbr;
  /// A neighbour in another cluster: that cluster and the neighbour's index
  /// in it (a cell's list finds it without a lookup per triangle id; in
  /// triangle order, so a cell reads it nearly in sequence).
  struct Across
  {
    std::uint32_t cluster, local;
  };
  std::vector<Across> across;
  std::uint64_t arrangement = 0; ///< the SolverData::arrangement they are of (0: none)
};
/// Per real triangle t and edge m: the triangle on the other side with the
/// same two bit-identical vertices, by its solver index (| kSameDirection when
/// running the same way), or kNoNeighbour (BuildNeighbours' pairing; the GL
/// backend's winding count). Empty beyond kNeighbourId triangles.
void GlobalNeighbours(const SolverData& d, std::vector<std::uint32_t>& out);
void BuildNeighbours(const SolverData& d, GearsNeighbours& out);

// ---------------------------------------------------------------------------
// Per-solve triangle data
/// The shaft of the light-frame box [lo, hi] of start points; W, H the
/// light's extent in the frame (world units; directional: tangents), `dir`
/// for a directional light, m the margin.
Shaft MakeShaft(const glm::dvec3& lo, const glm::dvec3& hi, double W, double H, bool dir, double m);

/// The triangles of one face in its light frame, for culling in float.
struct FaceTriangles
{
  glm::dvec3 Lc, u, v, n;          ///< the face's light frame (solver coordinates)
  /// Per triangle, one column each (kPad readable floats past the end):
  /// light-frame vertices x0 y0 z0 x1 y1 z1 x2 y2 z2 in float, the unit
  /// normal of the light-frame triangle and n . B0, and kFlag* bits. A
  /// cell's kernel arrays are these minus the cell's centre (ClusterFilter),
  /// so nothing per triangle is recomputed per cell.
  std::vector<float> p[9];
  std::vector<float> nx, ny, nz, nd;
  std::vector<std::int32_t> flags;
  std::vector<std::int8_t> closed; ///< per triangle: closed-rule sign (0: rule off)
  std::vector<std::uint8_t> drop;  ///< per triangle: faces away from every light sample of its closed piece
  std::vector<float> cbox;         ///< per cluster: light-frame AABB of its kept triangles (6 floats)
  std::vector<std::uint32_t> clusterOrder; ///< clusters sorted by depth, far from the light first
  std::size_t dropped = 0;
  double margin = 0.0; ///< float culling margin (world units)
  glm::dvec3 ToLight(const glm::dvec3& X) const
  {
    const glm::dvec3 r = X - Lc;
    return { glm::dot(r, u), glm::dot(r, v), glm::dot(r, n) };
  }
  FaceColumns Columns() const
  {
    FaceColumns c;
    for (int q = 0; q < 9; ++q)
    {
      c.p[q] = p[q].data();
    }
    c.nx = nx.data();
    c.ny = ny.data();
    c.nz = nz.data();
    c.nd = nd.data();
    c.flags = flags.data();
    return c;
  }
  /// What SetupBatch needs to compute a triangle's exact light-frame
  /// vertices from the solver's floats, as ToLight does.
  ExactSource Exact(const SolverData& D, const glm::dvec3* corner, bool dir) const
  {
    ExactSource e;
    e.V = D.V.data();
    e.closed = closed.data();
    for (int a = 0; a < 3; ++a)
    {
      e.Lc[a] = Lc[a];
      e.u[a] = u[a];
      e.v[a] = v[a];
      e.n[a] = n[a];
      for (int q = 0; q < 4; ++q)
      {
        e.corner[q][a] = corner[q][a];
      }
    }
    e.dir = dir;
    return e;
  }
};

/// Cluster c's box is empty (every triangle dropped).
inline bool ClusterEmpty(const float* b)
{
  return !(b[0] <= b[3]);
}

/// Occluders: pieces with at least this many triangles get inner boxes from
/// a grid of kOccluderGrid voxels along their longest side, at most
/// kOccluderBoxes boxes of at least kOccluderMinVoxels voxels.
constexpr std::size_t kOccluderMinTriangles = 256, kOccluderBoxes = 64, kOccluderMinVoxels = 8;
/// The triangle arrays reserve 1/kOccluderHeadroom more for the occluders'
/// faces (12 per box; the 5M assembly's 10,262 boxes add 2.5%). Past that an
/// append reallocates, which is only slower.
constexpr std::size_t kOccluderHeadroom = 8;
constexpr int kOccluderGrid = 32;
/// D.pieceBox for np pieces: each the box of its real triangles (D.piece).
void PieceBoxes(SolverData& D, std::size_t np);
/// The inner occluders of D's closed pieces (into occV, occPiece).
void BuildOccluders(SolverData& D);
/// D's arrays cut back to the real triangles, then the occluders appended.
void AppendOccluders(SolverData& D);

/// The projective map that takes a far rect or point light to a directional
/// one (ssGearsFarLight.cxx): points relative to the scene's centre, world
/// axes, to their images (same origin and axes).
struct FarLightWarp
{
  glm::dvec3 c{ 0.0 };                 ///< the scene's centre in the light's frame (xc, yc, zc)
  glm::dvec3 u{ 1, 0, 0 }, v{ 0, 1, 0 }, n{ 0, 0, 1 }; ///< the light's frame
  glm::dvec3 Point(const glm::dvec3& d) const;
  /// The image of the plane through d with normal N: its unit normal.
  glm::dvec3 Normal(const glm::dvec3& d, const glm::dvec3& N) const;
  /// Whether d lies in front of the light by more than half the scene's depth.
  bool InFront(const glm::dvec3& d) const;
  /// The mapped depths' scale |c| / zc (lengths along the central ray kept).
  double Kappa() const { return glm::length(c) / c.z; }
  /// The map's length factor at d along the ray to the light's centre (the
  /// start rule's reach there is eps times this).
  double Reach(const glm::dvec3& d) const;
  /// d's offset from the scene's centre in the light's frame (dx, dy, dz).
  glm::dvec3 Local(const glm::dvec3& d) const { return { glm::dot(d, u), glm::dot(d, v), glm::dot(d, n) }; }
};
/// The map is used while the scene lies within this slope of the light's
/// axis (|(xc, yc)| <= slope zc, 88 degrees): the float images' rounding
/// grows with the slope (6e-8 of the scene each), and must stay well below
/// the start offset (1e-5 of the scene).
constexpr double kFarLightMaxSlope = 30.0;
/// For a rect or point light L (relative to the scene's centre) whose depth
/// to the scene's centre exceeds kFarLightRatio x extent: the map and the
/// directional light (tangent rectangle W / |c| x H / |c|) the scene's images
/// are solved under. False otherwise.
bool MakeFarLightWarp(const LightFrame& L, double extent, FarLightWarp& w, LightFrame& warped);
/// D's real triangles mapped by w (same order, clusters, pieces and
/// neighbours), the pieces' boxes and inner occluders found again.
void WarpSolverData(const SolverData& D, const FarLightWarp& w, SolverData& out);

/// The closed-mesh rule for light L (solver frame) per triangle: 0 rule off
/// (open piece, translucent piece, light inside the piece's box), +-1 the
/// closed piece's orientation (world frame), 2 dropped (faces away from every
/// light sample). Returns the number dropped.
std::size_t ClosedRuleFlags(
  const SolverData& D, const LightFrame& L, const GearsOptions& opt, std::vector<std::int8_t>& flags);

/// The face's triangles in its light frame (C.u, C.v, C.n at the light
/// centre), the closed-mesh rule's flags, the clusters' boxes and their
/// order by depth. L is in the solver's frame.
void PrepareFaceTriangles(
  const SolverData& D, const LightFrame& L, const GearsGridCamera& C, const GearsOptions& opt, FaceTriangles& ft);

/// Pass 1 and 2 at the level of clusters [§3.3]: each cluster's shadow
/// volume (its light-frame box extruded from the light corners, retracted
/// to P_far) as a box of grid cells; (cluster, cell) pairs for the non-empty
/// cells, sorted by cell (stable: clusters keep their depth order).
struct FacePairs
{
  std::vector<std::uint32_t> cellBegin; ///< NC + 1 offsets into clusters
  std::vector<std::uint32_t> clusters;  ///< cluster ids sorted by cell
  std::size_t fullGrid = 0;             ///< clusters touching the light plane (all cells)
};
struct PairScratch
{
  RangeMax rmax;
  std::vector<Box2> box;
  std::vector<std::uint32_t> cellsN, pairItem, pairCell, hist;
  std::vector<std::size_t> offset;
};
/// The grid cells (C's) the shadow volume of the light-frame box cb (x0 y0
/// z0 x1 y1 z1, grown by m) may reach up to depth far [§3.1, Fig. 4]: the box
/// of its projected corners and their extrusions from the light's corners.
Box2 VolumeGridBox(
  const GearsGridCamera& C, const LightFrame& L, const FaceTriangles& ft, const float* cb, double m, double far);
void BuildPairs(const SolverData& D, const LightFrame& L, const FaceGrid& g, const FaceTriangles& ft,
  const GearsOptions& opt, PairScratch& w, FacePairs& out, GearsStats& st);

/// What the cells stage counts (summed over threads and faces).
struct CellCounters
{
  double listed = 0;     ///< sum over pixels of their group list's length
  double total = 0;      ///< pairs left after the per-pair rejection (Table 9 "total")
  double rasterised = 0; ///< pairs that reached the exact raster (before a mask filled)
  double necessary = 0;  ///< pairs hiding >= 1 light sample above the horizon (countNecessary)
  double cellTriangles = 0; ///< sum over non-empty cells of their list's length after culling
  std::size_t cellTrianglesMax = 0;
  std::size_t clustersTested = 0, clustersCulled = 0, trianglesTested = 0, trianglesCulled = 0;
  std::size_t clustersBelowHorizon = 0; ///< horizon rule, per cell
  std::size_t clustersBehindOccluders = 0; ///< inner-occluder rule, per cell
  double trianglesBelowHorizon = 0;     ///< horizon rule, per group
  std::size_t groups = 0, lutFallbacks = 0, coveredSkips = 0, cellsInUmbra = 0, occluderDrawsStopped = 0;
  // the winding count (ssGearsWinding.cxx): pixels solved by it and declined
  // (a contour vertex on a sample row, an edge along one), members and the
  // rest of the lists (summed over groups), contour edges stepped (summed
  // over pixels)
  std::size_t windingPixels = 0, windingDeclined = 0;
  std::size_t filtered = 0; ///< pairs whose bits the filtered float test gave (ssGearsSmallKernels.h)
  double windingMembers = 0, windingRest = 0, windingContour = 0;
  double windingTested = 0; ///< contour edges tested, summed over pixels
  double contourTriangles = 0, contourNecessary = 0; ///< necessaryWithWinding (CountContour)
  double contourEdgesNecessary = 0; ///< ... contour edges whose own steps change a sample above the horizon
  std::size_t outsidePyramid = 0; ///< straddling pairs the rejection dropped outside the pixel's pyramid
  // thread time (ms, summed over threads) of the parts of step 4: cell
  // lists with their kernel arrays (and the occluders' pre-pass), the
  // groups, and the pixels (rejection and exact raster)
  double msLists = 0, msGroups = 0, msReject = 0, msExact = 0;
  void Add(const CellCounters& o);
};

/// Step 4 for one face: per non-empty cell, its triangles from the cell's
/// clusters culled against the cell's shaft, the samples split into groups
/// with their own shafts, per pixel the rejection kernel and the exact
/// raster, V and the masks. `assign` (optional) gets the cell and group lists.
struct CellJob
{
  const SolverData* D;
  const LightFrame* L;
  const FaceGrid* g;
  const FaceTriangles* ft;
  const FacePairs* pairs;
  const std::vector<glm::dvec3>* start;
  const std::vector<glm::dvec3>* normal;
  const GearsOptions* opt;
  int k;
  std::uint32_t fullRow;
  const double* eps; ///< per pixel: its start offset (ssTriangleSet.h StartOffset)
  double W, H;
  bool dir;
  const HalfPlaneLUT* lut;
  Isa isa;
  float* V;
  GearsMask* masks;
  const GearsNeighbours* neighbours = nullptr; ///< the winding count's (null: it does not run)
  int face = 0, numFaces = 1; ///< for the progress fraction (opt->progress)
};
/// Returns false when opt->progress asked to stop (cells not reached keep V).
bool SolveCells(const CellJob& job, CellCounters& counters, GearsAssignment::Face* assign, std::int32_t* pixelGroup);

constexpr std::size_t kPad = 16; ///< floats past the end of a kernel's arrays

/// Scratch arrays only grow: resizing them down and up again per cell and
/// group zero-filled them every time (5% of step 4 in a profile).
template <typename T>
inline void Grow(std::vector<T>& v, std::size_t n)
{
  if (v.size() < n)
  {
    v.resize(n);
  }
}

/// Every one of the k rows full (from the first row on: a pixel not in
/// umbra stops at its first open row).
inline bool Umbra(const std::uint32_t* rows, int k, std::uint32_t fullRow)
{
  int j = 0;
  while (j < k && rows[j] == fullRow)
  {
    ++j;
  }
  return j == k;
}

/// One pixel sample's mask while its cell is drawn.
struct PixelState
{
  std::uint32_t rows[40];  ///< the row kernels write whole vectors past row 31
  std::uint32_t below[40]; ///< the samples below its horizon
  bool full = false, haveTrans = false;
};

/// ssGearsCull.cxx, the horizon rule: the tangent planes (light frame; xyz
/// the unit normal, w = n . S) of the samples that can still change.
struct HorizonPlanes
{
  std::vector<glm::dvec4> p;
  bool usable = false; ///< every open sample has a normal, and one is open
};

/// A cluster's run of surviving triangles in a cell's list.
struct CellRun
{
  std::uint32_t cluster, start, count;
};

/// A thread's buffers for the cells stage, kept between cells.
struct CellScratch
{
  // the winding count (ssGearsWinding.cxx): the cell list's cluster runs
  // (runOf is indexed by cluster and validated against runs, never cleared),
  // their slots, per cell entry the list index of each edge's neighbour and
  // its member status in the current group; the group's members, the other
  // entries of its list (the rest), its contour edges, and a pixel's contour
  // edges with their steps
  std::vector<CellRun> runs;
  std::vector<std::uint32_t> runOf, runBase, gcell, iota;
  std::vector<std::int32_t> slot, cellNbr, status;
  std::vector<float> mf[9];            ///< the group's members' vertices
  std::vector<std::int32_t> mnbr[3], mstatus; ///< ... their neighbours (cell indices) and status
  std::vector<std::uint32_t> mtri;     ///< ... their triangles
  std::vector<float> rf[15];           ///< the rest of a group's list (GroupArrays order)
  std::vector<std::uint32_t> rtri;     ///< ... its triangles
  std::vector<std::uint32_t> edgeId;   ///< the group's contour edges: member q | m << 30
  std::vector<float> edgeP[6];         ///< ... their vertices
  std::size_t edgeCount = 0;
  std::vector<std::uint32_t> kept;     ///< a pixel's contour edges that may step its count
  std::vector<std::int32_t> stepA, stepB; ///< ... their vertices (float offsets into SolverData::V)
  std::vector<double> stepSg;          ///< ... and the side of S their raster takes
  std::int16_t delta[32 * 33];         ///< a pixel's count steps, k rows of k + 1
  std::vector<glm::dvec3> S, N;         ///< the cell's starts and normals (light frame)
  std::vector<std::size_t> pixel;       ///< the cell's pixels
  std::vector<PixelState> state;
  std::vector<std::vector<float>> trans; ///< per sample: transmittance of translucent casters
  std::vector<std::uint32_t> sampleOrder, groupEnd, subEnd;
  std::vector<std::uint32_t> list;       ///< the cell's triangles (their first entries are valid)
  std::vector<std::uint32_t> drawnBoxes; ///< the inner occluders drawn into the cell's masks
  std::vector<float> f[15];             ///< the list in float relative to the cell's centre (GroupArrays order)
  std::vector<float> gf[15];            ///< one group's gathered arrays
  std::vector<std::uint32_t> glist;     ///< one group's triangles
  std::vector<float> box;
  std::vector<std::uint32_t> cand;
  std::vector<std::uint32_t> smallBits; ///< the filtered float test's bits per candidate
  std::vector<float> smallIn[kSmallColumns]; ///< ... and its inputs, per candidate (the rejection kernel's)
  std::uint64_t groupSerial = 0;               ///< counts the thread's sample groups (GroupView::serial)
  std::uint64_t filteredGroup = 0;             ///< the group whose last pixel tried the filtered test ...
  bool filteredPaid = true;                    ///< ... and whether it decided enough candidates
  ExactBatch batch;
  CellCounters counters;
  HorizonPlanes horizons; ///< the cell's or the group's (horizon rule)
};

/// One sample group's list: the kernel arrays, each entry's triangle, its
/// length and the cell's centre.
struct GroupView
{
  GroupArrays ga;
  const ExactSource* exact; ///< where the exact raster takes the triangles from
  const std::uint32_t* tri; ///< per entry: its triangle (solver index)
  std::size_t ng;
  glm::dvec3 o;
  bool counting; ///< false for the inner occluders' faces (not the scene's triangles)
  bool countListed = true; ///< false: a winding count's rest (its group's list was counted)
  std::uint64_t serial = 0; ///< the sample group (CellScratch::groupSerial; 0: none)
};

/// ssGearsWinding.cxx: the neighbours of the cell's list (w.list[0, nl), its
/// runs in w.runs) into w.cellNbr, 3 columns of stride nl + kPad.
void CellNeighbours(const SolverData& D, const GearsNeighbours& N, CellScratch& w, std::size_t nl);
/// A sample group's winding count over its cell's list `cell` (with its
/// neighbours in w.cellNbr): the group's list (the entries the group shaft
/// and the horizon planes keep; its length into `kept`, below += those the
/// planes dropped), its members (w.mf ..., for the open samples among
/// samples[0, count)) as `members`, their contour edges (w.edgeId, edgeP,
/// edgeCount: returned) and the rest of the list (w.rf, rtri) as `rest`,
/// which each pixel rasterises after WindingPixel.
struct GroupFilterSpec
{
  const Shaft* shaft = nullptr; ///< null: the cell's list is the group's
  const float* planes = nullptr;
  int np = 0;
};
std::size_t WindingGroup(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& cell,
  const GroupFilterSpec& filter, const std::uint32_t* samples, std::size_t count, GroupView& members,
  GroupView& rest, std::size_t& kept, std::size_t& below);
/// Sample sq's count from the group's contour edges ORed into its mask;
/// false (mask untouched) when the pixel is declined: rasterise the group's
/// list (or the cell's) instead. members: WindingGroup's.
bool WindingPixel(
  const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& members, std::uint32_t sq);
/// The rejection kernel's parameters for sample sq of the list gv.
PixelParams MakePixelParams(const CellJob& job, const CellScratch& w, const GroupView& gv, std::uint32_t sq);

/// The planes of samples ids[0..count) (null: 0..count-1) of w not full yet.
void CollectHorizons(const CellScratch& w, const std::uint32_t* ids, std::size_t count, HorizonPlanes& h);
/// Whether the light-frame box b (min xyz, max xyz) lies below every plane by more than margin.
bool BoxBelowHorizons(const HorizonPlanes& h, const float* b, double margin);
/// The group kernel's horizon planes (KernelTable::group): at most this many.
constexpr int kMaxHorizonPlanes = 64;
/// h's planes for coordinates relative to o, lowered by margin, in float
/// (4 per plane: a point is below when a x + b y + c z < d); 0 when h is not
/// usable or has more than kMaxHorizonPlanes planes (nothing is dropped then).
int HorizonPlanesFloat(const HorizonPlanes& h, const glm::dvec3& o, double margin, float* planes);

/// [t0, t1] narrowed to the t at which P + t d lies strictly inside box B
/// (min xyz, max xyz) shrunk by m; false once that is empty.
inline bool SlabClip(const glm::dvec3& P, const glm::dvec3& d, const double* B, double m, double& t0, double& t1)
{
  for (int ax = 0; ax < 3; ++ax)
  {
    const double lo = B[ax] + m, hi = B[3 + ax] - m;
    if (!(lo < hi))
    {
      return false; // (a box thinner than 2 m holds nothing)
    }
    if (d[ax] == 0.0)
    {
      if (!(P[ax] > lo && P[ax] < hi))
      {
        return false;
      }
      continue;
    }
    double ta = (lo - P[ax]) / d[ax], tb = (hi - P[ax]) / d[ax];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 < t1))
    {
      return false;
    }
  }
  return true;
}
/// ssGearsCull.cxx, the inner-occluder rule: whether every segment from the
/// light-frame box [alo, ahi] to the light-frame box [clo, chi] passes
/// through the interior of box B (solver frame, min xyz max xyz) shrunk by
/// m: then what lies in [clo, chi] changes no mask that B's faces were drawn
/// into, for start points in [alo, ahi].
bool SegmentsThroughBox(const FaceTriangles& ft, const glm::dvec3& alo, const glm::dvec3& ahi, const glm::dvec3& clo,
  const glm::dvec3& chi, const double* B, double m);

/// ssGearsPixel.cxx: a sample's starting mask (horizon), the occluders'
/// pre-pass of a cell's samples, a sample's list, and its V and mask.
void PixelStart(const CellJob& job, CellScratch& w, std::uint32_t sq);
/// Whether every segment from the points `from` to the light (job.L: its
/// corners, or corner directions) passes through inner occluder `box`
/// (solver frame): their points at some common parameter t all lie in it.
bool UmbraBox(const CellJob& job, const glm::dvec3* from, int count, const double* box);
void DrawPixel(const CellJob& job, const KernelTable& K, CellScratch& w, const GroupView& gv, std::uint32_t sq);
void PixelFinish(const CellJob& job, CellScratch& w, std::uint32_t sq);

/// Stable counting sort of `count` (item, cell) pairs on the cell, in parallel
/// chunks; cellBegin (NC + 1) gets the per-cell ranges of `sorted`.
void SortPairsByCell(const std::uint32_t* item, const std::uint32_t* cell, std::size_t count, std::size_t NC,
  std::vector<std::uint32_t>& hist, std::vector<std::uint32_t>& cellBegin, std::vector<std::uint32_t>& sorted);
}
}

#endif
