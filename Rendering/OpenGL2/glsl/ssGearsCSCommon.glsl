// GEARS on the GPU: the compute kernels of ssGearsGL (GL 4.3 compute, SSBOs,
// atomics). Three files, concatenated by the host in this order:
// ssGearsCSCommon.glsl (buffers, helpers, camera C), ssGearsCSAssign.glsl
// (steps 2-3: samples, grid, shadow volumes, pairs, sort) and
// ssGearsCSRaster.glsl (step 4: bitmasks, V). One kernel per K_* define; the
// host prepends "#version 430", the kernel's define and WG.
//   Wang, Zhou, Ke, Popescu, "GEARS: A General and Efficient Algorithm for
//   Rendering Shadows", CGF 2014 (../shared/papers/gears-exact-soft-shadows.md).
//
// The kernels follow Rendering/Core/ssGEARS.cxx (the CPU backend) step by step.
// The assignment (camera, grid, shadow-volume boxes) only has to be
// conservative; the bitmask arithmetic (K_RASTER) repeats the CPU's double
// operations in the same order, with `precise` so that nothing is fused, so
// that both backends give identical bitmasks on the same inputs.

#ifndef WG
#define WG 64
#endif
layout(local_size_x = WG) in;

// Item index of a 2-D dispatch (work group counts are limited to 65535 per axis).
uint GID()
{
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(WG);
}
uint GroupID()
{
  return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
}

uniform uint uN;     // items of this dispatch (pixels, triangles, pairs, cells)
uniform int uFace;   // cube face (point light) or 0
uniform int uG;      // grid resolution
// depth layers per grid cell (K_CELL): cell c of the G x G grid holds the
// list cells c uLayers .. c uLayers + uLayers - 1, one per slice of its
// samples' depth range (1: no split)
uniform int uLayers;

// ---------------------------------------------------------------- buffers
// Each kernel declares only the buffers it uses (at most 16 per shader).
#ifdef K_START
#define USE_InPos
#define USE_InNrm
#define USE_Smp
#define USE_Face
#define USE_Vis
#define USE_Red
#define USE_Masks
#endif
#ifdef K_PROJECT
#define USE_Smp
#define USE_Face
#define USE_Red
#endif
#ifdef K_CELL
#define USE_Smp
#define USE_Face
#define USE_PixCell
#define USE_CellCnt
#define USE_CellDep
#define USE_CellBox
#endif
#ifdef K_SAT_ROWS
#define USE_CellCnt
#define USE_Sat
#endif
#ifdef K_SAT_COLS
#define USE_CellCnt
#define USE_Sat
#endif
#ifdef K_RMQ
#define USE_CellDep
#define USE_Rmq
#endif
#ifdef K_PASS1
#define USE_TriV
#define USE_Closed
#define USE_Red
#define USE_Sat
#define USE_Rmq
#define USE_Box
#define USE_Off
#define USE_CellCnt
#define USE_CellBox
#endif
#ifdef K_SCAN_BLOCK
#define USE_ScanData
#define USE_ScanSums
#define USE_Red
#endif
#ifdef K_SCAN_ADD
#define USE_ScanData
#define USE_ScanSums
#define USE_Red
#endif
#ifdef K_PASS2
#define USE_Red
#define USE_Off
#define USE_Box
#define USE_CellCnt
#define USE_PairTri
#define USE_PairCell
#define USE_TriV
#define USE_CellBox
#endif
#ifdef K_HIST
#define USE_PairCell
#define USE_CellBegin
#endif
#ifdef K_SCATTER
#define USE_PairCell
#define USE_PairTri
#define USE_CellBegin
#define USE_Cursor
#define USE_Sorted
#ifdef WINDING
#define USE_PairStat
#define USE_SlotStat
#endif
#endif
#ifdef K_FINISH
#define USE_Face
#define USE_Vis
#define USE_Masks
#endif
#ifdef K_PIXSORT
#define USE_Face
#define USE_PixCell
#define USE_PixStart
#define USE_Cursor
#define USE_PixOrder
#endif
#ifdef K_TOLIGHT
#define USE_TriV
#define USE_TriL
#define USE_TriLF
#ifdef WINDING
#define USE_TriN
#endif
#endif
#ifdef K_RASTER
#define USE_PixOrder
#define USE_TriL
#define USE_TriLF
#define USE_TriV
#define USE_Smp
#define USE_Face
#define USE_Vis
#define USE_PixCell
#define USE_CellBegin
#define USE_Sorted
#define USE_Masks
#define USE_Nec
#define USE_Closed
#ifdef WINDING
#define USE_Wind
#endif
#endif
#ifdef K_WFLAG
#define USE_PairTri
#define USE_PairCell
#define USE_PairStat
#define USE_TriL
#define USE_TriV
#define USE_CellBox
#define USE_CellCnt
#define USE_Box
#define USE_Closed
#define USE_Nbr
#define USE_TriN
#endif
#ifdef K_WINDING
#define USE_TriV
#define USE_TriL
#define USE_TriLF
#define USE_Closed
#define USE_PixOrder
#define USE_PixCell
#define USE_Smp
#define USE_CellBegin
#define USE_Sorted
#define USE_SlotStat
#define USE_Masks
#define USE_Wind
#define USE_Red
#endif

#ifdef USE_TriV
layout(std430, binding = 0) readonly buffer TriV { float triV[]; };     // 9 per triangle, caster frame
#endif
#ifdef USE_TriA
layout(std430, binding = 1) readonly buffer TriA { float triA[]; };     // opacity per triangle
#endif
#ifdef USE_InPos
layout(std430, binding = 2) readonly buffer InPos { float inPos[]; };   // 3 per pixel, frame origin
#endif
#ifdef USE_InNrm
layout(std430, binding = 3) readonly buffer InNrm { float inNrm[]; };   // 3 per pixel
#endif
#ifdef USE_Smp
layout(std430, binding = 4) buffer Smp { double smp[]; };              // start xyz, normal xyz, start offset
#endif
#ifdef USE_Face
layout(std430, binding = 5) buffer Face { int pixFace[]; };
#endif
#ifdef USE_Vis
layout(std430, binding = 6) buffer Vis { float vis[]; };
#endif
#ifdef USE_Red
layout(std430, binding = 7) buffer Red { uint red[]; };                // reductions, counters
#endif
#ifdef USE_PixCell
layout(std430, binding = 8) buffer PixCell { uint pixCell[]; };
#endif
#ifdef USE_CellCnt
layout(std430, binding = 9) buffer CellCnt { uint cellCount[]; };
#endif
#ifdef USE_CellDep
layout(std430, binding = 10) buffer CellDep { uint cellDepth[]; };     // ordered float bits
#endif
#ifdef USE_Sat
layout(std430, binding = 11) buffer Sat { uint sat[]; };
#endif
#ifdef USE_Rmq
layout(std430, binding = 12) buffer Rmq { float rmq[]; };
#endif
#ifdef USE_Box
layout(std430, binding = 13) buffer Box { ivec4 box[]; };
#endif
#ifdef USE_Off
layout(std430, binding = 14) buffer Off { uint off[]; };               // cellsN, then offsets
#endif
#ifdef USE_PairTri
layout(std430, binding = 15) buffer PairTri { uint pairTri[]; };
#endif
#ifdef USE_PairCell
layout(std430, binding = 16) buffer PairCell { uint pairCell[]; };
#endif
#ifdef USE_CellBegin
layout(std430, binding = 17) buffer CellBegin { uint cellBegin[]; };
#endif
#ifdef USE_Cursor
layout(std430, binding = 18) buffer Cursor { uint cursor[]; };
#endif
#ifdef USE_Sorted
layout(std430, binding = 19) buffer Sorted { uint sorted[]; };
#endif
#ifdef USE_Masks
layout(std430, binding = 20) buffer Masks { uint masks[]; };           // 32 per pixel
#endif
#ifdef USE_Nec
layout(std430, binding = 21) buffer Nec { uint nec[]; };
#endif
#ifdef USE_ScanData
layout(std430, binding = 22) buffer ScanData { uint scanData[]; };
#endif
#ifdef USE_ScanSums
layout(std430, binding = 23) buffer ScanSums { uint scanSums[]; };
#endif
#ifdef USE_TriL
layout(std430, binding = 24) buffer TriL { double triL[]; };          // 9 per triangle, light frame
#endif
#ifdef USE_Closed
// per triangle, the closed-mesh rule (GearsSolver::ClosedRuleFlags): 0 off,
// +1 / -1 its closed piece's orientation, 2 never drawn
layout(std430, binding = 25) readonly buffer Closed { int closedFlag[]; };
#endif
#ifdef USE_PixStart
layout(std430, binding = 28) readonly buffer PixStart { uint pixStart[]; }; // per cell its first slot in pixOrder
#endif
#ifdef USE_PixOrder
layout(std430, binding = 29) buffer PixOrder { uint pixOrder[]; };     // the face's pixels, cell by cell
#endif
#ifdef USE_TriLF
layout(std430, binding = 27) buffer TriLF { float triLF[]; };         // triL rounded to float (K_RASTER's pre-test)
#endif
// the winding count (glsl/ssGearsCSWinding.glsl)
#ifdef USE_Nbr
// per triangle edge the triangle across it (| 0x80000000: the edge runs the
// same way in both) or 0xFFFFFFFF (GearsSolver::EdgeNeighbours)
layout(std430, binding = 30) readonly buffer Nbr { uint nbr[]; };
#endif
#ifdef USE_PairStat
// per pair (K_WFLAG): bits 0-1 its triangle's status in its cell (0 rest,
// 1 / 2 a member with every start in front of / behind its plane, 3 never
// drawn there), bits 2-4 its edges on the cell's contour
layout(std430, binding = 31) buffer PairStat { uint pairStat[]; };
#endif
#ifdef USE_SlotStat
layout(std430, binding = 32) buffer SlotStat { uint slotStat[]; };    // pairStat per slot of `sorted`
#endif
#ifdef USE_TriN
// per triangle (K_TOLIGHT): its unit normal in the light's frame, rounded to
// float (as bits), and flags: 1 its side is trusted, 2 / 4 the whole light in
// front of / behind its plane (K_WFLAG's Status). Integers, not floats: a
// GPU may flush the flags' bit pattern (a denormal float) to 0.
layout(std430, binding = 34) buffer TriN { uvec4 triN[]; };
#endif
#ifdef USE_Wind
layout(std430, binding = 33) buffer Wind { uint wind[]; };            // per pixel: 1 if the count solved its members
#endif
#ifdef USE_CellBox
// per cell the light-frame box of its samples' starts, 6 ordered float bits,
// all kept with atomicMin: lo x y z rounded down, then -hi x y z (hi rounded up)
layout(std430, binding = 26) buffer CellBox { uint cellBox[]; };
#endif

// Red layout: face f (0..5) at 8 f: min x y z, max x y z, max depth;
// 48..51: 2-D min x, min y, max x, max y; 56: full-grid triangles;
// 57: scan overflow flag; 58: pairs outside their cell's shaft (a statistic:
// it wraps past 2^32); 59: pass 1's estimate of the pairs (uSample); 60: the
// nearest depth of a listed triangle (pass 1, for pass 2's depth buckets);
// 61: the largest start offset (K_START);
// 62, 63: pixels the winding count solved and declined.

// Floats as uints whose order is the floats' order (for atomicMin/Max).
uint Ord(float f)
{
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float Unord(uint u)
{
  return uintBitsToFloat((u & 0x80000000u) != 0u ? (u & 0x7FFFFFFFu) : ~u);
}
// The float nearest below / above a double (conservative bounds in float).
float FloatDown(double d)
{
  float f = float(d);
  if (double(f) > d)
  {
    uint b = floatBitsToUint(f);
    f = f > 0.0 ? uintBitsToFloat(b - 1u) : (f == 0.0 ? -uintBitsToFloat(1u) : uintBitsToFloat(b + 1u));
  }
  return f;
}
float FloatUp(double d)
{
  return -FloatDown(-d);
}
// std::nextafter(f, +large) for finite f (the CPU's cell-depth rounding)
float NextUp(float f)
{
  uint b = floatBitsToUint(f);
  if (f == 0.0)
  {
    return uintBitsToFloat(1u);
  }
  return f > 0.0 ? uintBitsToFloat(b + 1u) : uintBitsToFloat(b - 1u);
}
// float(double) is undefined beyond the float range: such a value becomes
// NaN (the GL raster's float pre-test then passes none of its tests)
float SafeFloat(double d)
{
  return abs(d) < 1e30LF ? float(d) : uintBitsToFloat(0x7FC00000u);
}
vec3 SafeFloat(dvec3 v)
{
  return vec3(SafeFloat(v.x), SafeFloat(v.y), SafeFloat(v.z));
}
bool FiniteF(float f)
{
  return (floatBitsToUint(f) & 0x7F800000u) != 0x7F800000u;
}
bool FiniteD(double d)
{
  return (unpackDouble2x32(d).y & 0x7FF00000u) != 0x7FF00000u;
}

// glm's operation order: dot = (x x' + y y') + z z'; cross as glm::cross.
double Dot(dvec3 a, dvec3 b)
{
  precise double r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}
dvec3 Cross(dvec3 x, dvec3 y)
{
  precise double cx = x.y * y.z - y.y * x.z;
  precise double cy = x.z * y.x - y.z * x.x;
  precise double cz = x.x * y.y - y.x * x.y;
  return dvec3(cx, cy, cz);
}
dvec3 Sub(dvec3 a, dvec3 b)
{
  precise dvec3 r = a - b;
  return r;
}

// The light's corners (w x h in its frame; for a directional light the
// corner directions) against the plane through B0 with normal n: the least
// and the largest n . (corner - B0), or n . corner (K_RASTER's Visit, the
// winding count's PlaneOf).
void LightCornerRange(dvec3 n, dvec3 B0, double w, double h, bool dir, out double lo, out double hi)
{
  lo = 1e300LF;
  hi = -1e300LF;
  for (int q = 0; q < 4; ++q)
  {
    double a1 = (q & 1) != 0 ? 0.5LF : -0.5LF, b1 = (q & 2) != 0 ? 0.5LF : -0.5LF;
    precise dvec3 corner = dvec3(a1 * w, b1 * h, dir ? -1.0LF : 0.0LF);
    precise double v = Dot(n, dir ? corner : Sub(corner, B0));
    lo = min(lo, v);
    hi = max(hi, v);
  }
}

// ---------------------------------------------------------------- camera C
uniform int uOrtho;
uniform dvec3 uE, uLc, uU, uV, uNrm; // eye, light centre, face axes
uniform double uGx0, uGy0, uSx, uSy;

double Depth(dvec3 X)
{
  return dot(X - uLc, uNrm);
}
dvec2 Project(dvec3 X)
{
  dvec3 r = X - (uOrtho != 0 ? uLc : uE);
  if (uOrtho != 0)
  {
    return dvec2(dot(r, uU), dot(r, uV));
  }
  double z = dot(r, uNrm);
  return dvec2(dot(r, uU) / z, dot(r, uV) / z);
}
dvec2 ToGrid(dvec2 p)
{
  return dvec2((p.x - uGx0) * uSx, (p.y - uGy0) * uSy);
}
uint CellOf(dvec2 g)
{
  int x = clamp(int(floor(g.x)), 0, uG - 1);
  int y = clamp(int(floor(g.y)), 0, uG - 1);
  return uint(y * uG + x);
}
#ifdef USE_Smp
dvec3 Start(uint i)
{
  return dvec3(smp[7 * i], smp[7 * i + 1], smp[7 * i + 2]);
}
#endif

// world (caster frame) to the light's frame, as ssGEARS.cxx's toLight
dvec3 ToLight(dvec3 X)
{
  dvec3 r = Sub(X, uLc);
  return dvec3(Dot(r, uU), Dot(r, uV), Dot(r, uNrm));
}

