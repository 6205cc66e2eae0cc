// GEARS per-pixel kernels, written once and compiled per instruction set:
// ssGearsCells.cxx includes this file for the scalar (baseline x86-64) build,
// ssGearsSIMDAVX2.cxx and ssGearsSIMDAVX512.cxx include it after a
// `#pragma GCC target`, so that the same loops are vectorised for each ISA
// and the solver picks one at run time (GearsOptions::simd). Everything here
// is plain arithmetic on float/double arrays: no library calls, so nothing is
// shared between the instruction sets but this text.
//
// The rejection kernel only culls (pixel, triangle) pairs whose exact raster
// sets no light-sample bit above the pixel's horizon, with margins far above
// float rounding, so the bitmasks never depend on which ISA ran it.
#ifndef ssGearsKernels_h
#define ssGearsKernels_h

#include <algorithm>
#include <cmath>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <cstddef>
#include <cstdint>

namespace ss
{
namespace gears
{
/// A shaft from a box of pixel samples to the light, in the light's frame
/// (x, y along u, v; z the depth in front of the light): every point of a
/// segment from a sample in the box to a light sample satisfies
///   ax + sx z <= x <= bx + tx z,  ay + sy z <= y <= by + ty z,  zlo < z < zhi
/// (zlo = -inf for a directional light). A triangle all of whose vertices
/// violate one of these by more than the margin hides no light sample from
/// any start point in the box.
struct Shaft
{
  float ax, sx, bx, tx, ay, sy, by, ty, zlo, zhi;
};
/// One cell's (or sample group's) triangles for the per-pixel rejection, in
/// float, relative to the cell's centre c in the face's light frame.
struct GroupArrays
{
  const float *x0, *y0, *z0, *x1, *y1, *z1, *x2, *y2, *z2;
  const float* nx; ///< unit plane normal
  const float* ny;
  const float* nz;
  const float* nd;    ///< n . b0
  const float* front; ///< 1: every light sample lies in front of the plane (or the closed-mesh rule, outward)
  const float* back;  ///< 1: every light sample lies behind the plane (or the closed-mesh rule, inward)
  std::size_t n;
};

/// A cell's or group's neighbour entries (the winding count, ssGearsWinding.cxx):
/// the list index, kNbrSameDirection when the edge runs the same way; -1: none.
constexpr std::int32_t kNbrIndex = 0x3FFFFFFF, kNbrSameDirection = 0x40000000;

/// The exact raster's filtered fast path (ssGearsSmallKernels.h): candidates
/// whose sample box is at most kSmallSide a side; their rows of bits from
/// j0, or kUndecided.
constexpr int kSmallSide = 8;
constexpr std::uint32_t kUndecided = 0xFFFFFFFFu; ///< (its top bit tells it from a row index: DrawPixel)
/// Its inputs, compacted by the rejection kernel (no gathers: they were a
/// third of SmallBits on the canopy): x0 y0 z0 x1 y1 z1 x2 y2 z2, nx ny nz nd,
/// the box i0 i1 j0 j1.
constexpr int kSmallColumns = 17;

/// Candidates whose sample box is at most kPointRows x kPointCols get their
/// bits by evaluating the constraints at each sample (SetupBatch).
constexpr int kPointRows = 8, kPointCols = 8;

/// FaceColumns::flags bits: not dropped by the closed-mesh rule; every light
/// sample in front of the plane (or the rule, outward); every one behind it;
/// a sliver whose float plane is not trusted to the margin (its front column
/// in a cell's arrays is then -1: never a member of a winding count).
constexpr std::int32_t kFlagLive = 1, kFlagFront = 2, kFlagBack = 4, kFlagSliver = 8;

/// A face's triangles for the cell kernels, one column per quantity, in
/// float, in the face's light frame: the vertices (x0 y0 z0 x1 .. z2), the
/// unit plane normal, n . B0, the kFlag bits.
struct FaceColumns
{
  const float* p[9];
  const float *nx, *ny, *nz, *nd;
  const std::int32_t* flags;
};

/// Where the exact raster takes a triangle's double light-frame vertices
/// from: the solver's floats (9 per triangle, solver frame) moved into the
/// face's light frame (origin Lc, axes u v n) as FaceTriangles::ToLight
/// does, so no per-cell copy in double is needed; the closed-mesh signs; the
/// light's corners (directional: corner directions) in the light frame.
struct ExactSource
{
  const float* V;
  const std::int8_t* closed;
  double Lc[3], u[3], v[3], n[3];
  double corner[4][3];
  bool dir;
};

/// What SetupBatch found for up to 8 candidate triangles of one pixel.
/// Per lane: the triangle's constraints F_m(i, j) = (A_m + C_m j) + B_m i for
/// the three edge planes (>= 0) and, if nf == 4, its own plane (> 0), over
/// rows j0..j1 (RowsSpan draws them).
struct ExactBatch
{
  double A[4][8];
  double B[4][8];
  double C[4][8];
  std::uint32_t bits[kPointRows][8]; ///< kind 4: rows j0 .. j0 + kPointRows - 1
  int kind[8];                                   ///< 0 nothing, 1 spans, 2 start rule, 4 bits ready
  int nf[8], j0[8], j1[8];
};

/// One pixel sample for the exact raster, in double, in the light frame.
struct ExactPixel
{
  double Sx, Sy, Sz, eps, W, H, invK;
  int k;
  bool dir, project;
};

/// One pixel sample for the rejection kernel.
struct PixelParams
{
  float sx, sy, sz;    ///< S - c
  float cz;            ///< depth of c (so S.z = cz + sz)
  float Sx, Sy, Sz;    ///< S in the light frame (for the projection onto the light)
  float px, py, pz;    ///< pixel normal in the light frame (0: no horizon test)
  float kx, ky, off;   ///< k / W, k / H, k / 2 - 1/2
  float last;          ///< k - 1
  float m;             ///< length margin
  int dir;             ///< directional light (samples are directions)
  int project;         ///< the projection test applies (k > 1, W > 0, H > 0)
  std::uint32_t fullRows = 0; ///< bit j: mask row j is full (0: no covered test)
  float nearEps = 0.0f;       ///< the pixel's start offset (the start rule's reach)
  float ao[3] = { 0.0f, 0.0f, 0.0f }; ///< |c| per axis, c as the group's arrays took it (the float bound)
};
/// A sample group's start points for the winding count's members (in float,
/// relative to the cell's centre): their box, the largest start offset, the
/// margin; a finite light's depth (cz: the centre's depth in front of it).
struct WindingBox
{
  float lo[3], hi[3];
  float cz, eps, m;
  int dir;
};
/// A sample group's winding count over its cell's list (WindingMembers):
/// the group's filter (GroupFilter's shaft and horizon planes) and its
/// start points; out, per cell entry its status (0: no member, 1: a member
/// in front of every start point, 2: behind), the members' columns and the
/// rest of the group's list (GroupFilter's 15 columns).
struct MemberSplit
{
  const Shaft* shaft = nullptr;  ///< the group's shaft (null: the cell's)
  const float* planes = nullptr; ///< np horizon planes (4 floats each)
  int np = 0;
  WindingBox box;
  const std::int32_t* nbr[3];  ///< the cell entries' neighbours (cell indices) per edge
  std::int32_t* status;        ///< per cell entry (every one written)
  float* member[9];            ///< the members' vertices (x0 y0 z0 x1 ... z2)
  std::int32_t* memberNbr[3];  ///< ... their neighbours (cell indices)
  std::int32_t* memberStatus;  ///< ... their status
  std::uint32_t* memberIds;    ///< ... their triangles
  float* rest[15];
  std::uint32_t* restIds;
  std::size_t memberCount = 0, restCount = 0; ///< out: the counts
  std::size_t kept = 0;               ///< out: the group's list (entries the filter keeps)
  std::size_t below = 0;              ///< out: entries in the shaft dropped by the planes
};
/// A group's contour edges (ssGearsWinding.cxx): per edge its member q and
/// edge m (q | m << 30) and its two vertices (relative to the cell's centre),
/// one column each (room for 3 entries' worth plus SS_GEARS_LANES).
struct ContourEdgeList
{
  std::uint32_t* id;
  float* p[6];   ///< xa ya za xb yb zb
  std::size_t n; ///< edges (ContourPixel); ContourEdges returns it
};

/// The kernels compiled for one instruction set.
/// What RejectPairs counted: pairs in rows full already (the raster's
/// covered skips), and straddling pairs outside the pixel's pyramid.
struct RejectCounts
{
  std::size_t covered = 0, outsidePyramid = 0;
};
struct KernelTable
{
  const char* name;
  int lanes; ///< doubles per vector: candidates per SetupBatch
  /// box: 4 columns of `stride` floats (i0, i1, j0, j1 per entry). keep
  /// (null: none): kSmallColumns columns that get each kept entry's
  /// coordinates, plane and box at its place in out (SmallBits reads them).
  std::size_t (*reject)(const GroupArrays&, const PixelParams&, std::uint32_t* out, float* box, std::size_t stride,
    float* const* keep, RejectCounts& counts);
  /// The winding count (ssGearsWindingKernels.h): a sample group's members
  /// (status per entry; the other entries' ids and 15 columns compacted into
  /// restIds / rest, as GroupFilter does, their count returned), their
  /// contour, a pixel's contour edges that may step its count, and their
  /// exact steps (-1: the pixel is declined).
  void (*members)(const GroupArrays& cell, const std::uint32_t* ids, MemberSplit& s);
  std::size_t (*contour)(const MemberSplit& s, ContourEdgeList& out);
  std::size_t (*contourPixel)(const ContourEdgeList& e, const PixelParams& p, std::uint32_t* out);
  int (*steps)(const ExactSource& src, const std::int32_t* ia, const std::int32_t* ib, const double* sg, std::size_t n,
    const ExactPixel& p, std::int16_t* delta);
  bool (*count)(const std::int16_t* delta, int k, std::uint32_t* rows);
  /// The exact raster's bits of small candidates (in: the kSmallColumns
  /// columns reject kept, from candidate 0 of the batch on): out[q] is
  /// candidate q's first row j0, or kUndecided; out[(1 + r) stride + q] its
  /// bits in row j0 + r, in place (0 when undecided). Rows hold n rounded up
  /// to SS_GEARS_LANES entries.
  void (*small)(const float* const* in, const PixelParams&, std::size_t n, std::uint32_t* out, std::size_t stride);
  /// Group lists: the entries that may reach the shaft (null: all) and lie
  /// above one of the np horizon planes (4 floats each; 0 planes: all):
  /// their ids to out, their 15 columns to dst; below += those in the
  /// shaft dropped by the planes.
  std::size_t (*group)(const GroupArrays&, const std::uint32_t* ids, const Shaft* s, const float* planes, int np,
    float* const* dst, std::uint32_t* out, std::size_t& below);
  /// Cell lists: a cluster's live triangles that may reach the shaft (null:
  /// all), appended at `count` (ids to list, the 15 GroupArrays columns
  /// relative to o to out); returns the new count, tested += live triangles.
  std::size_t (*cluster)(const FaceColumns& f, std::uint32_t first, std::uint32_t end, const Shaft* s,
    const float* o, float* const* out, std::uint32_t* list, std::size_t count, std::size_t& tested);
  /// tri: triangle ids (ExactSource), box / gids: their sample boxes
  void (*setup)(ExactBatch& b, const ExactSource& src, const std::uint32_t* tri, const float* const* box,
    const std::uint32_t* gids, const ExactPixel& p, int count);
  bool (*spans)(const ExactBatch& b, int lane, int k, std::uint32_t* rows);
};
const KernelTable& KernelsScalar();
const KernelTable& KernelsAVX2();
const KernelTable& KernelsAVX512();
}
}
#endif

#ifdef SS_GEARS_KERNEL_NAMESPACE
namespace ss
{
namespace gears
{
namespace SS_GEARS_KERNEL_NAMESPACE
{
// GCC vector extensions: SS_GEARS_LANES floats per vector (4: SSE2, 8: AVX2,
// 16: AVX-512), compiled to the instruction set of the including file.
typedef float VF __attribute__((vector_size(4 * SS_GEARS_LANES)));
typedef int VI __attribute__((vector_size(4 * SS_GEARS_LANES)));
typedef unsigned VUI __attribute__((vector_size(4 * SS_GEARS_LANES)));

static inline VF Load(const float* p)
{
  VF v;
  __builtin_memcpy(&v, p, sizeof(v));
  return v;
}
static inline VF Min(VF a, VF b)
{
  return a < b ? a : b;
}
static inline VF Max(VF a, VF b)
{
  return a > b ? a : b;
}
static inline VF Abs(VF a)
{
  // (the sign bit cleared: one AND; a comparison and a select were three)
  return (VF)((VI)a & 0x7fffffff);
}

typedef double VD __attribute__((vector_size(4 * SS_GEARS_LANES)));      // SS_GEARS_LANES / 2 doubles
typedef long long VL __attribute__((vector_size(4 * SS_GEARS_LANES)));   // their comparison masks
typedef std::int32_t VJ __attribute__((vector_size(2 * SS_GEARS_LANES))); // and as many int32
typedef std::uint32_t VU __attribute__((vector_size(2 * SS_GEARS_LANES)));
constexpr int kRowLanes = SS_GEARS_LANES / 2;
constexpr double kSteepKernel = 1e6; // kSteep of ssGearsInternal.h

// Bit q set where lane q of a comparison result (0 or -1) is set.
static inline unsigned LaneMask(VI v)
{
#if SS_GEARS_LANES == 16
  return _mm512_movepi32_mask(reinterpret_cast<const __m512i&>(v));
#elif SS_GEARS_LANES == 8
  return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<const __m256&>(v)));
#else
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<const __m128&>(v)));
#endif
}

// Bit q set where lane q of a double comparison result (0 or -1) is set.
static inline unsigned RowMask(VL v)
{
#if SS_GEARS_LANES == 16
  return _mm512_movepi64_mask(reinterpret_cast<const __m512i&>(v));
#elif SS_GEARS_LANES == 8
  return static_cast<unsigned>(_mm256_movemask_pd(reinterpret_cast<const __m256d&>(v)));
#else
  return static_cast<unsigned>(_mm_movemask_pd(reinterpret_cast<const __m128d&>(v)));
#endif
}

#if SS_GEARS_LANES == 8
// Per 8-lane mask, the kept lanes' indices, a byte each from the lowest: the
// AVX2 compaction's permutation (AVX2 has no compress instruction).
struct CompactTable
{
  std::uint64_t idx[256];
};
static constexpr CompactTable MakeCompactTable()
{
  CompactTable t{};
  for (unsigned m = 0; m < 256; ++m)
  {
    int c = 0;
    for (int q = 0; q < 8; ++q)
    {
      if ((m >> q) & 1u)
      {
        t.idx[m] |= static_cast<std::uint64_t>(q) << (8 * c++);
      }
    }
  }
  return t;
}
static constexpr CompactTable kCompactTable = MakeCompactTable();
#endif

// The lanes of v where keep is set, stored contiguously from dst (which
// must hold SS_GEARS_LANES writable entries: whole vectors are written);
// returns their count.
template <typename V, typename E>
static inline int Compact(const V& v, VI keep, E* dst)
{
  static_assert(sizeof(V) == sizeof(VI) && sizeof(E) == 4, "32-bit lanes");
#if SS_GEARS_LANES == 16
  const __mmask16 mk = _mm512_movepi32_mask(reinterpret_cast<const __m512i&>(keep));
  const __m512i x = _mm512_maskz_compress_epi32(mk, reinterpret_cast<const __m512i&>(v));
  _mm512_storeu_si512(dst, x);
  return __builtin_popcount(mk);
#elif SS_GEARS_LANES == 8
  const unsigned mk = LaneMask(keep);
  const __m256i idx = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(kCompactTable.idx[mk])));
  const __m256i x = _mm256_permutevar8x32_epi32(reinterpret_cast<const __m256i&>(v), idx);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst), x);
  return __builtin_popcount(mk);
#else
  int c = 0;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    dst[c] = v[q];
    c += keep[q] != 0;
  }
  return c;
#endif
}

#include "ssGearsRejectKernels.h"

// Whether points (x, y, z) may lie in the shaft: -1 where no plane of it has
// all three outside (comparisons give -1 where true).
static inline VI InShaftV(const Shaft& s, const VF* x, const VF* y, const VF* z)
{
  // (masks ANDed per plane: on AVX-512 they stay in mask registers)
  VI o0 = VI{} - 1, o1 = o0, o2 = o0, o3 = o0, o4 = o0, o5 = o0;
  for (int m = 0; m < 3; ++m)
  {
    o0 &= x[m] < s.ax + s.sx * z[m];
    o1 &= x[m] > s.bx + s.tx * z[m];
    o2 &= y[m] < s.ay + s.sy * z[m];
    o3 &= y[m] > s.by + s.ty * z[m];
    o4 &= !(z[m] > s.zlo);
    o5 &= !(z[m] < s.zhi);
  }
  return ~(o0 | o1 | o2 | o3 | o4 | o5);
}

// The lanes of `valid` (triangles x, y, z) that may reach the shaft s (null:
// all) and are not below every one of the np planes (a x + b y + c z < d at
// all three vertices); below += those the planes drop. GroupFilter's and
// WindingMembers' test of a group's list.
static inline VI GroupKeep(
  const Shaft* s, const float* planes, int np, const VF* x, const VF* y, const VF* z, VI valid, int& below)
{
  VI k = s ? valid & InShaftV(*s, x, y, z) : valid;
  if (np > 0)
  {
    VI b = k;
    for (int q = 0; q < np; ++q)
    {
      const float* P = planes + 4 * q;
      for (int m = 0; m < 3; ++m)
      {
        b &= (P[0] * x[m] + P[1] * y[m]) + P[2] * z[m] < P[3];
      }
      if (!LaneMask(b))
      {
        break; // every lane is above some plane: kept
      }
    }
    below += __builtin_popcount(LaneMask(b));
    k &= ~b;
  }
  return k;
}

// Entries of a group's arrays that may reach the shaft s (null: all) and
// are not below every one of the np planes (a x + b y + c z < d at all
// three vertices; the horizon rule, ssGearsCull.cxx, with its margin in d),
// written to out (their ids[]) and gathered into dst (15 columns of at
// least n + SS_GEARS_LANES floats); returns their count. ids holds
// SS_GEARS_LANES - 1 readable entries past n.
static inline std::size_t GroupFilter(const GroupArrays& g, const std::uint32_t* ids, const Shaft* s,
  const float* planes, int np, float* const* dst, std::uint32_t* out, std::size_t& belowCount)
{
  int below = 0;
  const std::size_t n = g.n;
  const float* const src[15] = { g.x0, g.y0, g.z0, g.x1, g.y1, g.z1, g.x2, g.y2, g.z2, g.nx, g.ny, g.nz, g.nd,
    g.front, g.back };
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  std::size_t c = 0;
  for (std::size_t i = 0; i < n; i += SS_GEARS_LANES)
  {
    const VF x[3] = { Load(g.x0 + i), Load(g.x1 + i), Load(g.x2 + i) };
    const VF y[3] = { Load(g.y0 + i), Load(g.y1 + i), Load(g.y2 + i) };
    const VF z[3] = { Load(g.z0 + i), Load(g.z1 + i), Load(g.z2 + i) };
    const VI valid = (lane + static_cast<int>(i)) < static_cast<int>(n);
    const VI k = GroupKeep(s, planes, np, x, y, z, valid, below);
    if (!LaneMask(k))
    {
      continue;
    }
    for (int col = 0; col < 15; ++col)
    {
      Compact(Load(src[col] + i), k, dst[col] + c);
    }
    VUI idx;
    __builtin_memcpy(&idx, ids + i, sizeof(idx));
    c += static_cast<std::size_t>(Compact(idx, k, out + c));
  }
  belowCount += static_cast<std::size_t>(below);
  return c;
}

// A cluster's triangles [first, end) into a cell's list: the live ones (not
// dropped by the closed-mesh rule) that may reach the shaft s (null: all),
// with their 15 GroupArrays columns relative to the cell's centre o. The
// face's columns hold SS_GEARS_LANES - 1 readable entries past the last
// triangle; out and list must hold count + end - first + SS_GEARS_LANES entries.
static inline std::size_t ClusterFilter(const FaceColumns& f, std::uint32_t first, std::uint32_t end, const Shaft* s,
  const float* o, float* const* out, std::uint32_t* list, std::size_t count, std::size_t& tested)
{
  VI lane;
  for (int q = 0; q < SS_GEARS_LANES; ++q)
  {
    lane[q] = q;
  }
  const VF zero = VF{} + 0.0f, one = zero + 1.0f;
  for (std::uint32_t t = first; t < end; t += SS_GEARS_LANES)
  {
    VF x[3], y[3], z[3];
    for (int m = 0; m < 3; ++m)
    {
      x[m] = Load(f.p[3 * m] + t);
      y[m] = Load(f.p[3 * m + 1] + t);
      z[m] = Load(f.p[3 * m + 2] + t);
    }
    VI fl;
    __builtin_memcpy(&fl, f.flags + t, sizeof(fl));
    const VI live = ((fl & kFlagLive) != 0) & ((lane + static_cast<int>(t)) < static_cast<int>(end));
    const VI k = s ? live & InShaftV(*s, x, y, z) : live;
    tested += static_cast<std::size_t>(__builtin_popcount(LaneMask(live)));
    if (!LaneMask(k))
    {
      continue;
    }
    for (int m = 0; m < 3; ++m)
    {
      Compact(x[m] - o[0], k, out[3 * m] + count);
      Compact(y[m] - o[1], k, out[3 * m + 1] + count);
      Compact(z[m] - o[2], k, out[3 * m + 2] + count);
    }
    const VF nx = Load(f.nx + t), ny = Load(f.ny + t), nz = Load(f.nz + t);
    Compact(nx, k, out[9] + count);
    Compact(ny, k, out[10] + count);
    Compact(nz, k, out[11] + count);
    Compact(Load(f.nd + t) - ((nx * o[0] + ny * o[1]) + nz * o[2]), k, out[12] + count);
    Compact((fl & kFlagSliver) != 0 ? -one : ((fl & kFlagFront) != 0 ? one : zero), k, out[13] + count);
    Compact((fl & kFlagBack) != 0 ? one : zero, k, out[14] + count);
    count += static_cast<std::size_t>(Compact((VUI)(lane + static_cast<int>(t)), k, list + count));
  }
  return count;
}

// The exact raster [§4.2] (ssGearsRaster.cxx, SetupTriangle / RasterSetup,
// holds the definition): sample (i, j) is hidden iff its direction from S
// passes the three edge planes, F_m(i, j) = (A_m + C_m j) + B_m i >= 0, and,
// for a triangle not wholly between S and the light, lies beyond its plane
// (F_3 > 0). Here the same operations, vectorised: RowsSpan over rows,
// SetupBatch over candidates. The GL backend (K_RASTER) repeats them.

// The bound a constraint puts on a row (RasterSetup's RowBound), for the
// rows in jv: the root x, then the signs at the samples next to it.
static inline VD RowBoundV(double A, double B, double C, double P, double Q, bool steep, VD jv, bool strict, int k)
{
  const VD one = VD{} + 1.0, zero = VD{} + 0.0;
  const VD ej = A + C * jv;
  VD x = steep ? -ej / B : P + Q * jv;
  const VD lowC = VD{} - 2.0, highC = VD{} + (k + 1.0);
  x = x < lowC ? lowC : (x > highC ? highC : x);
  const VD t = __builtin_convertvector(__builtin_convertvector(x, VJ), VD);
  if (B > 0.0)
  {
    const VD c = t + (t < x ? one : zero); // ceil
    const VD em = ej + B * (c - 1.0), e0 = ej + B * c;
    const VL okm = strict ? em > 0.0 : em >= 0.0, ok0 = strict ? e0 > 0.0 : e0 >= 0.0;
    return okm ? c - 1.0 : (ok0 ? c : c + 1.0);
  }
  const VD c = t - (t > x ? one : zero); // floor
  const VD ep = ej + B * (c + 1.0), e0 = ej + B * c;
  const VL okp = strict ? ep > 0.0 : ep >= 0.0, ok0 = strict ? e0 > 0.0 : e0 >= 0.0;
  return okp ? c + 1.0 : (ok0 ? c : c - 1.0);
}

// The rows t.j0..t.j1, kRowLanes at a time, ORed into rows (which must hold
// j1 + kRowLanes entries); returns whether any bit was set.
static inline bool RowsSpan(const ExactBatch& b, int which, int k, std::uint32_t* rows)
{
  struct
  {
    double A[4], B[4], C[4];
    bool strict[4];
    int nf, j0, j1;
  } t;
  t.j0 = b.j0[which];
  t.j1 = b.j1[which];
  if (t.j1 < t.j0)
  {
    return false;
  }
  // A constraint that holds at the four corners of rows j0..j1 x samples
  // 0..k-1 holds at every sample between: F_m as computed here and in
  // RowBoundV, fl(fl(A + fl(C j)) + fl(B i)), is monotone in i and in j
  // (every rounding is monotone; no fused operations in this file), so its
  // extremes over the box lie at corners. It changes no row's span and is
  // left out of the rows' loop. One that fails at all four fails everywhere:
  // no bit. (Most constraints of a large triangle are of the first kind: one
  // or two of its edges cross the light.)
  t.nf = 0;
  const double jc[2] = { double(t.j0), double(t.j1) }, ic[2] = { 0.0, k - 1.0 };
  for (int m = 0; m < b.nf[which]; ++m)
  {
    const double A = b.A[m][which], B = b.B[m][which], C = b.C[m][which];
    const bool strict = m == 3;
    bool all = true, none = true;
    for (const double j : jc)
    {
      const double ej = A + C * j;
      for (const double i : ic)
      {
        const double F = ej + B * i;
        const bool ok = strict ? F > 0.0 : F >= 0.0;
        all = all && ok;
        none = none && !ok;
      }
    }
    if (none)
    {
      return false;
    }
    if (all)
    {
      continue;
    }
    t.A[t.nf] = A;
    t.B[t.nf] = B;
    t.C[t.nf] = C;
    t.strict[t.nf++] = strict;
  }
  if (t.nf == 0)
  {
    std::fill(rows + t.j0, rows + t.j1 + 1, (2u << (k - 1)) - 1u); // (2 << 31 wraps to 0: all 32 bits)
    return true;
  }
  double P[4], Q[4];
  bool steep[4];
  for (int m = 0; m < t.nf; ++m)
  {
    const double B = t.B[m];
    P[m] = B != 0.0 ? -t.A[m] / B : 0.0;
    Q[m] = B != 0.0 ? -t.C[m] / B : 0.0;
    steep[m] = !(std::abs(P[m]) <= kSteepKernel && std::abs(Q[m]) <= kSteepKernel);
  }
  VD lane;
  for (int q = 0; q < kRowLanes; ++q)
  {
    lane[q] = double(q);
  }
  const VD zero = VD{} + 0.0, kmax = VD{} + (k - 1.0);
  VU any = VU{} + 0u;
  for (int j = t.j0; j <= t.j1; j += kRowLanes)
  {
    const VD jv = double(j) + lane;
    VD lo = zero, hi = kmax;
    VL ok = jv <= double(t.j1);
    for (int m = 0; m < t.nf; ++m)
    {
      const bool strict = t.strict[m];
      const double B = t.B[m];
      if (B > 0.0)
      {
        const VD L = RowBoundV(t.A[m], B, t.C[m], P[m], Q[m], steep[m], jv, strict, k);
        lo = lo < L ? L : lo;
      }
      else if (B < 0.0)
      {
        const VD U = RowBoundV(t.A[m], B, t.C[m], P[m], Q[m], steep[m], jv, strict, k);
        hi = U < hi ? U : hi;
      }
      else
      {
        const VD ej = t.A[m] + t.C[m] * jv;
        ok &= strict ? ej > 0.0 : ej >= 0.0;
      }
    }
    ok &= lo <= hi;
    const VU il = (VU)__builtin_convertvector(lo, VJ), ih = (VU)__builtin_convertvector(hi, VJ);
    // bits il..ih; 2 << 31 wraps to 0, which still gives bits il..31
    VU bits = ((VU{} + 2u) << ih) - ((VU{} + 1u) << il);
    bits = __builtin_convertvector(ok, VJ) != 0 ? bits : VU{} + 0u;
    VU cur;
    __builtin_memcpy(&cur, rows + j, sizeof(cur));
    cur |= bits;
    __builtin_memcpy(rows + j, &cur, sizeof(cur));
    any |= bits;
  }
  bool hit = false;
  for (int q = 0; q < kRowLanes; ++q)
  {
    hit = hit || any[q] != 0u;
  }
  return hit;
}

// Lane q of the result is base[idx[q]], widened to double (idx holds kRowLanes
// readable entries; hardware gathers where there are).
static inline VD GatherAt(const float* base, const std::int32_t* idx)
{
#if SS_GEARS_LANES == 16
  const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(idx));
  const __m512d g = _mm512_maskz_cvtps_pd(
    0xFF, _mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, v, _mm256_castsi256_ps(_mm256_set1_epi32(-1)), 4));
  VD r;
  __builtin_memcpy(&r, &g, sizeof(r));
  return r;
#elif SS_GEARS_LANES == 8
  const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(idx));
  const __m256d g =
    _mm256_cvtps_pd(_mm_mask_i32gather_ps(_mm_setzero_ps(), base, v, _mm_castsi128_ps(_mm_set1_epi32(-1)), 4));
  VD r;
  __builtin_memcpy(&r, &g, sizeof(r));
  return r;
#else
  VD r;
  for (int q = 0; q < kRowLanes; ++q)
  {
    r[q] = base[idx[q]];
  }
  return r;
#endif
}

// Lane q of the result is base[9 ids[q]], widened to double: a coordinate of
// triangle ids[q] in the solver's floats.
static inline VD GatherV(const float* base, const std::uint32_t* ids)
{
#if SS_GEARS_LANES == 4
  VD r;
  for (int q = 0; q < kRowLanes; ++q)
  {
    r[q] = base[9 * static_cast<std::size_t>(ids[q])];
  }
  return r;
#else
  std::int32_t idx[kRowLanes];
  for (int q = 0; q < kRowLanes; ++q)
  {
    idx[q] = static_cast<std::int32_t>(9 * ids[q]);
  }
  return GatherAt(base, idx);
#endif
}
static inline VD GatherF(const float* col, const std::uint32_t* ids)
{
  VD r;
  for (int q = 0; q < kRowLanes; ++q)
  {
    r[q] = col[ids[q]];
  }
  return r;
}
static inline VD SqrtV(VD x)
{
#if SS_GEARS_LANES == 16
  __m512d a;
  __builtin_memcpy(&a, &x, sizeof(a));
  a = _mm512_maskz_sqrt_pd(0xFF, a);
  __builtin_memcpy(&x, &a, sizeof(a));
#elif SS_GEARS_LANES == 8
  __m256d a;
  __builtin_memcpy(&a, &x, sizeof(a));
  a = _mm256_sqrt_pd(a);
  __builtin_memcpy(&x, &a, sizeof(a));
#else
  for (int q = 0; q < kRowLanes; ++q)
  {
    x[q] = __builtin_sqrt(x[q]);
  }
#endif
  return x;
}

// The start of the exact raster for kRowLanes candidates at once: their
// light-frame vertices and plane (the operations of FaceTriangles::ToLight
// and glm's cross, dot and length, so every ISA and the GL backend get the
// same doubles), the closed-mesh rule, the start rule's test, the
// constraints (SetupTriangle's operations), and for a candidate whose box
// holds at most kPointRows x kPointCols samples the bits themselves, each
// sample's constraints evaluated as RasterSetup decides them.
static inline void SetupBatch(ExactBatch& b, const ExactSource& src, const std::uint32_t* ids,
  const float* const* box, const std::uint32_t* gids, const ExactPixel& p, int count)
{
  static_assert(kRowLanes <= 8, "ExactBatch holds 8 lanes");
  const VD zero = VD{} + 0.0, one = VD{} + 1.0;
  VD Bv[9];
  for (int m = 0; m < 3; ++m)
  {
    // r = X - Lc; B = (r . u, r . v, r . n), each dot as (x + y) + z
    const VD rx = GatherV(src.V + 3 * m, ids) - src.Lc[0];
    const VD ry = GatherV(src.V + 3 * m + 1, ids) - src.Lc[1];
    const VD rz = GatherV(src.V + 3 * m + 2, ids) - src.Lc[2];
    Bv[3 * m] = (rx * src.u[0] + ry * src.u[1]) + rz * src.u[2];
    Bv[3 * m + 1] = (rx * src.v[0] + ry * src.v[1]) + rz * src.v[2];
    Bv[3 * m + 2] = (rx * src.n[0] + ry * src.n[1]) + rz * src.n[2];
  }
  const VD B0x = Bv[0], B0y = Bv[1], B0z = Bv[2], B1x = Bv[3], B1y = Bv[4], B1z = Bv[5];
  const VD B2x = Bv[6], B2y = Bv[7], B2z = Bv[8];
  // the plane normal glm::cross(B1 - B0, B2 - B0), its length, the light
  // corners' extremes on it
  const VD e1x = B1x - B0x, e1y = B1y - B0y, e1z = B1z - B0z, e2x = B2x - B0x, e2y = B2y - B0y, e2z = B2z - B0z;
  const VD nx = e1y * e2z - e2y * e1z, ny = e1z * e2x - e2z * e1x, nz = e1x * e2y - e2x * e1y;
  const VD pl = SqrtV((nx * nx + ny * ny) + nz * nz);
  VD cmin = VD{} + 1e300, cmax = VD{} - 1e300;
  for (int q = 0; q < 4; ++q)
  {
    const double* c = src.corner[q];
    const VD cx = src.dir ? VD{} + c[0] : c[0] - B0x, cy = src.dir ? VD{} + c[1] : c[1] - B0y;
    const VD cz = src.dir ? VD{} + c[2] : c[2] - B0z;
    const VD v = (nx * cx + ny * cy) + nz * cz;
    cmin = v < cmin ? v : cmin;
    cmax = cmax < v ? v : cmax;
  }
  VD closed;
  for (int q = 0; q < kRowLanes; ++q)
  {
    closed[q] = double(src.closed[ids[q]]);
  }
  // sigma = (S - B0) . n (Dot3)
  const VD sigma = ((p.Sx - B0x) * nx + (p.Sy - B0y) * ny) + (p.Sz - B0z) * nz;
  const VL skipClosed = (closed != 0.0) & (closed * sigma >= 0.0);
  const VD asig = sigma < 0.0 ? -sigma : sigma;
  const VL near = (pl > 0.0) & (asig < p.eps * pl);
  const VL skipNear = near & (((sigma > 0.0) & (cmin >= 0.0)) | ((sigma < 0.0) & (cmax <= 0.0)));
  VL projected = (VL{} + (p.project ? 1 : 0)) != 0;
  projected &= (p.Sz - B0z > 0.0) & (p.Sz - B1z > 0.0) & (p.Sz - B2z > 0.0);
  if (!p.dir)
  {
    projected &= (B0z > 0.0) & (B1z > 0.0) & (B2z > 0.0);
  }
  // SetupTriangle: a, b, c from S; nT = (b - a) x (c - a); det = nT . a
  const VD ax = B0x - p.Sx, ay = B0y - p.Sy, az = B0z - p.Sz;
  const VD bx = B1x - p.Sx, by = B1y - p.Sy, bz = B1z - p.Sz;
  const VD cx = B2x - p.Sx, cy = B2y - p.Sy, cz = B2z - p.Sz;
  const VD ux = bx - ax, uy = by - ay, uz = bz - az, vx = cx - ax, vy = cy - ay, vz = cz - az;
  const VD tx = uy * vz - vy * uz, ty = uz * vx - vz * ux, tz = ux * vy - vx * uy;
  const VD det = (tx * ax + ty * ay) + tz * az;
  const VL flat = !(det != 0.0);
  const VD sg = det > 0.0 ? one : -one;
  // MakeAffine: D0 = -S (finite) or (0, 0, -1) (directional); Du = (W, 0, 0), Dv = (0, H, 0)
  const double D0x = p.dir ? 0.0 : -p.Sx, D0y = p.dir ? 0.0 : -p.Sy, D0z = p.dir ? -1.0 : -p.Sz;
  const double h = 0.5 * p.invK - 0.5;
  VD A[4], Bc[4], C[4];
  auto affine = [&](VD ex, VD ey, VD ez, VD constant, int m) {
    const VD du = (ex * p.W + ey * 0.0) + ez * 0.0, dv = (ex * 0.0 + ey * p.H) + ez * 0.0;
    A[m] = (constant + ((ex * D0x + ey * D0y) + ez * D0z)) + h * (du + dv);
    Bc[m] = du * p.invK;
    C[m] = dv * p.invK;
  };
  // edges: sg (a x b), sg (b x c), sg (c x a) (Cross3)
  affine(sg * (ay * bz - by * az), sg * (az * bx - bz * ax), sg * (ax * by - bx * ay), zero, 0);
  affine(sg * (by * cz - cy * bz), sg * (bz * cx - cz * bx), sg * (bx * cy - cx * by), zero, 1);
  affine(sg * (cy * az - ay * cz), sg * (cz * ax - az * cx), sg * (cx * ay - ax * cy), zero, 2);
  affine(sg * tx, sg * ty, sg * tz, sg * -det, 3);
  const VL cross = ~projected & ((VL{} + (p.dir ? 0 : 1)) != 0);
  // kind 4: at most kPointRows x kPointCols samples in the box; their bits,
  // per sample (as many rows and columns as the largest such box needs)
  const VD i0 = GatherF(box[0], gids), i1 = GatherF(box[1], gids), j0 = GatherF(box[2], gids), j1 = GatherF(box[3], gids);
  const VL small = projected & (i1 - i0 < double(kPointCols)) & (j1 - j0 < double(kPointRows));
  int rowsNeeded = 0, colsNeeded = 0;
  for (int q = 0; q < count; ++q)
  {
    if (small[q])
    {
      rowsNeeded = std::max(rowsNeeded, static_cast<int>(j1[q] - j0[q]) + 1);
      colsNeeded = std::max(colsNeeded, static_cast<int>(i1[q] - i0[q]) + 1);
    }
  }
  // F = (A + C j) + B i: the products B i once per column (the same
  // operations as at each sample: no fused ones, so the same F)
  VD bi[3][kPointCols];
  VL colIn[kPointCols];
  VU colBit[kPointCols];
  for (int c = 0; c < colsNeeded; ++c)
  {
    const VD iv = i0 + double(c);
    for (int m = 0; m < 3; ++m)
    {
      bi[m][c] = Bc[m] * iv;
    }
    colIn[c] = iv <= i1;
    colBit[c] = (VU{} + 1u) << (VU)__builtin_convertvector(iv, VJ);
  }
  for (int r = 0; r < rowsNeeded; ++r)
  {
    const VD jv = j0 + double(r);
    VD ej[3];
    for (int m = 0; m < 3; ++m)
    {
      ej[m] = A[m] + C[m] * jv;
    }
    const VL rowIn = jv <= j1;
    VU rb = VU{} + 0u;
    for (int c = 0; c < colsNeeded; ++c)
    {
      const VL in = rowIn & colIn[c] & (ej[0] + bi[0][c] >= 0.0) & (ej[1] + bi[1][c] >= 0.0) & (ej[2] + bi[2][c] >= 0.0);
      rb |= __builtin_convertvector(in, VJ) != 0 ? colBit[c] : VU{} + 0u;
    }
    __builtin_memcpy(b.bits[r], &rb, sizeof(rb));
  }
  for (int r = rowsNeeded; r < kPointRows; ++r)
  {
    std::fill(b.bits[r], b.bits[r] + 8, 0u); // (the raster ORs all kPointRows rows)
  }
  for (int m = 0; m < 4; ++m)
  {
    __builtin_memcpy(b.A[m], &A[m], sizeof(VD));
    __builtin_memcpy(b.B[m], &Bc[m], sizeof(VD));
    __builtin_memcpy(b.C[m], &C[m], sizeof(VD));
  }
  for (int q = 0; q < count; ++q)
  {
    int kind;
    if (skipClosed[q] || skipNear[q] || flat[q])
    {
      kind = 0;
    }
    else if (near[q])
    {
      kind = 2;
    }
    else if (small[q])
    {
      kind = 4;
    }
    else
    {
      kind = 1;
    }
    b.kind[q] = kind;
    b.nf[q] = cross[q] ? 4 : 3;
    b.j0[q] = static_cast<int>(j0[q]);
    b.j1[q] = static_cast<int>(j1[q]);
  }
}

#include "ssGearsSmallKernels.h"
#include "ssGearsWindingKernels.h"

static inline const KernelTable& Table(const char* name)
{
  static const KernelTable t = { name, kRowLanes, RejectPairs, WindingMembers, ContourEdges, ContourPixel, ContourSteps,
    CountRows, SmallBits, GroupFilter, ClusterFilter, SetupBatch, RowsSpan };
  return t;
}
}
}
}
#endif
