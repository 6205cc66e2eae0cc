// GEARS on the GPU: the compute kernels of ssGearsGL (GL 4.3 compute, SSBOs,
// atomics). One source, one kernel per K_* define; the host prepends
// "#version 430", the kernel's define and KMAX (the bitmask size k).
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
#define USE_Red
#define USE_Sat
#define USE_Rmq
#define USE_Box
#define USE_Off
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
#define USE_Off
#define USE_Box
#define USE_CellCnt
#define USE_PairTri
#define USE_PairCell
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
#endif
#ifdef K_FINISH
#define USE_Face
#define USE_Vis
#define USE_Masks
#endif
#ifdef K_TOLIGHT
#define USE_TriV
#define USE_TriL
#endif
#ifdef K_RASTER
#define USE_TriL
#define USE_TriV
#define USE_Smp
#define USE_Face
#define USE_Vis
#define USE_PixCell
#define USE_CellBegin
#define USE_Sorted
#define USE_Masks
#define USE_Nec
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
layout(std430, binding = 4) buffer Smp { double smp[]; };              // start xyz, normal xyz
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

// Red layout: face f (0..5) at 8 f: min x y z, max x y z, max depth;
// 48..51: 2-D min x, min y, max x, max y; 56: full-grid triangles;
// 57: scan overflow flag.

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
  return dvec3(smp[6 * i], smp[6 * i + 1], smp[6 * i + 2]);
}
#endif

// world (caster frame) to the light's frame, as ssGEARS.cxx's toLight
dvec3 ToLight(dvec3 X)
{
  dvec3 r = Sub(X, uLc);
  return dvec3(Dot(r, uU), Dot(r, uV), Dot(r, uNrm));
}

#ifdef K_TOLIGHT
// per face, every triangle's vertices in the light's frame once (the CPU
// backend does this once per cell), instead of once per pixel and triangle
void main()
{
  uint t = GID();
  if (t < uN)
  {
    for (int m = 0; m < 3; ++m)
    {
      dvec3 B = ToLight(dvec3(triV[9 * t + 3 * m], triV[9 * t + 3 * m + 1], triV[9 * t + 3 * m + 2]));
      triL[9 * t + 3 * m] = B.x;
      triL[9 * t + 3 * m + 1] = B.y;
      triL[9 * t + 3 * m + 2] = B.z;
    }
  }
}
#endif

#if defined(K_START) || defined(K_PROJECT)
shared uint sRed[56];
bool IsMinSlot(uint q)
{
  return q < 48u ? q % 8u < 3u : q < 50u;
}
void SharedInit()
{
  for (uint q = gl_LocalInvocationID.x; q < 56u; q += WG)
  {
    sRed[q] = IsMinSlot(q) ? 0xFFFFFFFFu : ((q < 48u && q % 8u == 6u) ? Ord(0.0) : 0u);
  }
  barrier();
}
void SharedFlush()
{
  barrier();
  for (uint q = gl_LocalInvocationID.x; q < 56u; q += WG)
  {
    if (IsMinSlot(q))
    {
      atomicMin(red[q], sRed[q]);
    }
    else
    {
      atomicMax(red[q], sRed[q]);
    }
  }
}
#endif

#ifdef K_START
// Step 2: pixel samples with the reference's rules (start offset along the
// normal, one-sided rect light, point light's cube faces); per face the 3-D
// AABB of the starts and the farthest depth, rounded outwards.
uniform dvec3 uRel, uLn;   // frame origin - caster centre; light normal
uniform double uEps;
uniform int uType;          // 0 rect, 1 directional, 2 point
uniform uint uFullRow;
void main()
{
  SharedInit();
  uint i = GID();
  if (i < uN)
  {
    pixFace[i] = -1;
    vec3 pf = vec3(inPos[3 * i], inPos[3 * i + 1], inPos[3 * i + 2]);
    if (FiniteF(pf.x) && FiniteF(pf.y) && FiniteF(pf.z))
    {
      precise dvec3 p = uRel + dvec3(pf);
      dvec3 N = dvec3(inNrm[3 * i], inNrm[3 * i + 1], inNrm[3 * i + 2]);
      precise double l = sqrt(Dot(N, N));
      precise dvec3 Nn = N / l;
      N = (l > 0.0 && FiniteD(l)) ? Nn : dvec3(0.0);
      if (uType == 0 && Dot(Sub(p, uLc), uLn) <= 0.0)
      {
        vis[i] = 0.0; // behind the one-sided light: every sample hidden
        for (int j = 0; j < 32; ++j)
        {
          masks[32 * i + j] = uFullRow;
        }
      }
      else
      {
        precise dvec3 S = p + N * uEps;
        int face = 0;
        dvec3 n = uLn;
        bool ok = true;
        if (uType == 2)
        {
          dvec3 d = S - uLc;
          dvec3 a = abs(d);
          int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
          if (!(a[axis] > 0.0))
          {
            vis[i] = 1.0; // at the light itself
            ok = false;
          }
          face = 2 * axis + (d[axis] < 0.0 ? 1 : 0);
          n = dvec3(0.0);
          n[axis] = (face % 2) != 0 ? -1.0 : 1.0;
        }
        if (ok)
        {
          pixFace[i] = face;
          smp[6 * i] = S.x;
          smp[6 * i + 1] = S.y;
          smp[6 * i + 2] = S.z;
          smp[6 * i + 3] = N.x;
          smp[6 * i + 4] = N.y;
          smp[6 * i + 5] = N.z;
          uint b = uint(8 * face);
          for (int c = 0; c < 3; ++c)
          {
            atomicMin(sRed[b + c], Ord(FloatDown(S[c])));
            atomicMax(sRed[b + 3 + c], Ord(FloatUp(S[c])));
          }
          atomicMax(sRed[b + 6], Ord(FloatUp(dot(S - uLc, n))));
        }
      }
    }
  }
  SharedFlush();
}
#endif

#ifdef K_PROJECT
// 3.2: the 2-D AABB of the face's projected samples (rounded outwards).
void main()
{
  SharedInit();
  uint i = GID();
  if (i < uN && pixFace[i] == uFace)
  {
    dvec2 q = Project(Start(i));
    atomicMin(sRed[48], Ord(FloatDown(q.x)));
    atomicMin(sRed[49], Ord(FloatDown(q.y)));
    atomicMax(sRed[50], Ord(FloatUp(q.x)));
    atomicMax(sRed[51], Ord(FloatUp(q.y)));
  }
  SharedFlush();
}
#endif

#ifdef K_CELL
// 3.2: samples to cells; per cell the count and the farthest depth, rounded up.
void main()
{
  uint i = GID();
  if (i < uN && pixFace[i] == uFace)
  {
    dvec3 S = Start(i);
    uint c = CellOf(ToGrid(Project(S)));
    pixCell[i] = c;
    atomicAdd(cellCount[c], 1u);
    atomicMax(cellDepth[c], Ord(NextUp(float(Depth(S)))));
  }
}
#endif

#ifdef K_SAT_ROWS
// summed-area table of non-empty cells: prefix along x per row, then y
void main()
{
  uint y = GID();
  if (y < uint(uG))
  {
    uint run = 0u;
    uint G1 = uint(uG) + 1u;
    for (uint x = 0u; x < uint(uG); ++x)
    {
      run += cellCount[y * uint(uG) + x] > 0u ? 1u : 0u;
      sat[(y + 1u) * G1 + x + 1u] = run;
    }
  }
}
#endif

#ifdef K_SAT_COLS
void main()
{
  uint x = GID();
  if (x < uint(uG))
  {
    uint G1 = uint(uG) + 1u;
    for (uint y = 1u; y < uint(uG); ++y)
    {
      sat[(y + 1u) * G1 + x + 1u] += sat[y * G1 + x + 1u];
    }
  }
}
#endif

// 2-D range-maximum table of the cells' far depths: [ly][lx][y][x]
uniform int uL, uLx, uLy;
uint RmqIndex(int lx, int ly, int x, int y)
{
  return uint(((ly * uL + lx) * uG + y) * uG + x);
}

#ifdef K_RMQ
void main()
{
  uint c = GID();
  if (c < uint(uG * uG))
  {
    int x = int(c) % uG, y = int(c) / uG;
    if (uLx == 0 && uLy == 0)
    {
      rmq[RmqIndex(0, 0, x, y)] = Unord(cellDepth[c]);
    }
    else if (x + (1 << uLx) <= uG && y + (1 << uLy) <= uG)
    {
      rmq[RmqIndex(uLx, uLy, x, y)] = uLx > 0
        ? max(rmq[RmqIndex(uLx - 1, uLy, x, y)], rmq[RmqIndex(uLx - 1, uLy, x + (1 << (uLx - 1)), y)])
        : max(rmq[RmqIndex(uLx, uLy - 1, x, y)], rmq[RmqIndex(uLx, uLy - 1, x, y + (1 << (uLy - 1)))]);
    }
  }
}
#endif

#ifdef K_PASS1
// 3.3 pass 1: per triangle the 2-D AABB of its 15-point shadow volume,
// extruded to the farthest sample and retracted to P_far of the cells it
// touches [§3.1, Fig. 5]; cellsN = its non-empty cells (summed-area table).
uniform double uMaxDepth, uMinDepth;
uniform int uCorners, uRetract;
uniform dvec3 uCorner[4], uAway[4];
int Log2(int n)
{
  int l = 0;
  while ((2 << l) <= n)
  {
    ++l;
  }
  return l;
}
float RangeMax(ivec4 b)
{
  int lx = Log2(b.z - b.x + 1), ly = Log2(b.w - b.y + 1);
  int xb = b.z - (1 << lx) + 1, yb = b.w - (1 << ly) + 1;
  return max(max(rmq[RmqIndex(lx, ly, b.x, b.y)], rmq[RmqIndex(lx, ly, xb, b.y)]),
    max(rmq[RmqIndex(lx, ly, b.x, yb)], rmq[RmqIndex(lx, ly, xb, yb)]));
}
ivec4 VolumeBox(dvec3 B[3], double d[3], double far)
{
  double bx0 = 1e300LF, by0 = 1e300LF, bx1 = -1e300LF, by1 = -1e300LF;
  for (int m = 0; m < 3; ++m)
  {
    for (int c = -1; c < uCorners; ++c)
    {
      if (c >= 0 && far <= d[m])
      {
        break; // this vertex is beyond every sample: no extrusion
      }
      dvec3 X = c < 0 ? B[m]
                      : (uOrtho != 0 ? B[m] + (far - d[m]) * uAway[c]
                                     : uCorner[c] + (far / d[m]) * (B[m] - uCorner[c]));
      dvec2 g = ToGrid(Project(X));
      bx0 = min(bx0, g.x);
      bx1 = max(bx1, g.x);
      by0 = min(by0, g.y);
      by1 = max(by1, g.y);
    }
  }
  double e = 1e-7LF * double(uG);
  ivec4 r;
  r.x = max(int(floor(max(bx0 - e, -1.0LF))), 0);
  r.y = max(int(floor(max(by0 - e, -1.0LF))), 0);
  r.z = min(int(floor(min(bx1 + e, double(uG)))), uG - 1);
  r.w = min(int(floor(min(by1 + e, double(uG)))), uG - 1);
  if (!(bx1 + e >= 0.0 && by1 + e >= 0.0 && bx0 - e < double(uG) && by0 - e < double(uG)))
  {
    r = ivec4(1, 1, 0, 0);
  }
  return r;
}
void main()
{
  uint t = GID();
  if (t >= uN)
  {
    return;
  }
  ivec4 b = ivec4(1, 1, 0, 0);
  dvec3 B[3];
  double d[3];
  bool behind = true, touching = false;
  for (int m = 0; m < 3; ++m)
  {
    B[m] = dvec3(triV[9 * t + 3 * m], triV[9 * t + 3 * m + 1], triV[9 * t + 3 * m + 2]);
    d[m] = Depth(B[m]);
    behind = behind && d[m] <= 0.0;
    touching = touching || d[m] <= uMinDepth;
  }
  double dMin = min(min(d[0], d[1]), d[2]);
  if (uOrtho != 0)
  {
    touching = false;
    behind = false;
  }
  if (behind || dMin >= uMaxDepth)
  {
    // behind the light plane, or beyond every sample: blocks nothing
  }
  else if (touching)
  {
    b = ivec4(0, 0, uG - 1, uG - 1); // unbounded extrusion: every cell
    atomicAdd(red[56], 1u);
  }
  else
  {
    b = VolumeBox(B, d, uMaxDepth);
    if (uRetract != 0 && b.x <= b.z && b.y <= b.w)
    {
      double pfar = double(RangeMax(b));
      if (!(pfar > dMin))
      {
        b = ivec4(1, 1, 0, 0);
      }
      else if (pfar < uMaxDepth)
      {
        b = VolumeBox(B, d, pfar);
      }
    }
  }
  box[t] = b;
  uint n = 0u;
  if (b.x <= b.z && b.y <= b.w)
  {
    uint G1 = uint(uG) + 1u;
    n = sat[uint(b.w + 1) * G1 + uint(b.z + 1)] - sat[uint(b.y) * G1 + uint(b.z + 1)] -
      sat[uint(b.w + 1) * G1 + uint(b.x)] + sat[uint(b.y) * G1 + uint(b.x)];
  }
  off[t] = n;
}
#endif

#define SCAN_ELEMS 1024u
#ifdef K_SCAN_BLOCK
// Exclusive prefix sum, 4 WG = SCAN_ELEMS elements per workgroup (WG 256), block totals to
// scanSums; an overflow of 32 bits raises red[57].
shared uint sSum[WG];
void main()
{
  uint t = gl_LocalInvocationID.x;
  uint base = GroupID() * SCAN_ELEMS + 4u * t;
  uint v[4];
  uint run = 0u;
  bool over = false;
  for (int q = 0; q < 4; ++q)
  {
    uint x = base + uint(q) < uN ? scanData[base + uint(q)] : 0u;
    v[q] = run;
    over = over || run + x < run;
    run += x;
  }
  sSum[t] = run;
  barrier();
  for (uint s = 1u; s < uint(WG); s <<= 1)
  {
    uint add = t >= s ? sSum[t - s] : 0u;
    barrier();
    over = over || sSum[t] + add < add;
    sSum[t] += add;
    barrier();
  }
  uint before = t > 0u ? sSum[t - 1u] : 0u;
  for (int q = 0; q < 4; ++q)
  {
    if (base + uint(q) < uN)
    {
      over = over || v[q] + before < before;
      scanData[base + uint(q)] = v[q] + before;
    }
  }
  if (t == uint(WG) - 1u)
  {
    scanSums[GroupID()] = sSum[t];
  }
  if (over)
  {
    atomicOr(red[57], 1u);
  }
}
#endif

#ifdef K_SCAN_ADD
void main()
{
  uint i = GID();
  if (i < uN)
  {
    uint add = scanSums[i / SCAN_ELEMS];
    uint x = scanData[i];
    if (x + add < add)
    {
      atomicOr(red[57], 1u);
    }
    scanData[i] = x + add;
  }
}
#endif

#ifdef K_PASS2
// 3.3 pass 2: the (triID, cellID) pairs at the prefix-sum offsets
void main()
{
  uint t = GID();
  if (t >= uN)
  {
    return;
  }
  uint o = off[t];
  if (off[t + 1u] == o)
  {
    return;
  }
  ivec4 b = box[t];
  for (int y = b.y; y <= b.w; ++y)
  {
    for (int x = b.x; x <= b.z; ++x)
    {
      uint c = uint(y * uG + x);
      if (cellCount[c] != 0u)
      {
        pairTri[o] = t;
        pairCell[o] = c;
        ++o;
      }
    }
  }
}
#endif

#ifdef K_HIST
void main()
{
  uint q = GID();
  if (q < uN)
  {
    atomicAdd(cellBegin[pairCell[q]], 1u);
  }
}
#endif

#ifdef K_SCATTER
void main()
{
  uint q = GID();
  if (q < uN)
  {
    uint c = pairCell[q];
    sorted[cellBegin[c] + atomicAdd(cursor[c], 1u)] = pairTri[q];
  }
}
#endif


#ifdef K_RASTER
// Step 4 [§4.2]: per pixel sample the k x k bitmask of hidden light samples
// from its cell's triangles, in the light's frame (origin L_c, axes u v n).
// The arithmetic repeats RasterizeTriangle / RasterizeNearTriangle /
// RasterSetup of ssGEARS.cxx operation for operation.
uniform int uK, uDir, uCountNecessary;
uniform int uPre; // the triangles' light-frame vertices are in triL (K_TOLIGHT)
uniform uint uFullRow;
uniform double uW, uH, uEps, uXlo, uXhi, uYlo, uYhi;

struct Affine
{
  double A, B, C;
};
// the sample space seen from S: d(i, j) = D0 + su_i Du + sv_j Dv
dvec3 gD0, gDu, gDv;
Affine MakeAffine(dvec3 e, double constant)
{
  precise double du = Dot(e, gDu);
  precise double dv = Dot(e, gDv);
  precise double h = 0.5LF / double(uK) - 0.5LF;
  precise double A = constant + Dot(e, gD0) + h * (du + dv);
  precise double B = du / double(uK);
  precise double C = dv / double(uK);
  return Affine(A, B, C);
}
uint RowBits(int lo, int hi)
{
  return (2u << uint(hi)) - (1u << uint(lo));
}
bool IntRange(double lo, double hi, bool strictLo, bool strictHi, out int il, out int ih)
{
  il = 0;
  ih = -1;
  if (!(lo <= hi))
  {
    return false;
  }
  double l = ceil(lo), h = floor(hi);
  if (strictLo && l == lo)
  {
    l += 1.0;
  }
  if (strictHi && h == hi)
  {
    h -= 1.0;
  }
  l = max(l, 0.0LF);
  h = min(h, double(uK - 1));
  if (l > h)
  {
    return false;
  }
  il = int(l);
  ih = int(h);
  return true;
}
void IndexRange(double lo, double hi, out int a, out int b)
{
  precise double xa = (lo + 0.5LF) * double(uK) - 0.5LF - 1e-9LF;
  precise double xb = (hi + 0.5LF) * double(uK) - 0.5LF + 1e-9LF;
  a = max(0, int(ceil(xa)));
  b = min(uK - 1, int(floor(xb)));
}

uint rows[32];
uint tmpRows[32];
int gFull; // rows of `rows` that are full (umbra when == k)
void OrRow(int j, uint bits)
{
  bool was = rows[j] == uFullRow;
  rows[j] |= bits;
  gFull += (!was && rows[j] == uFullRow) ? 1 : 0;
}

// constraints: edge[3] (+ cross) as in TriangleSetup
Affine gF[4];
bool gHasCross;

void EdgeConstraint(int m, double Pm, double Qm, int j, inout double lo, inout double hi, inout bool ok)
{
  double B = gF[m].B;
  precise double x = Pm + Qm * double(j);
  if (B > 0.0)
  {
    lo = max(lo, x);
  }
  else if (B < 0.0)
  {
    hi = min(hi, x);
  }
  else
  {
    precise double f = gF[m].A + gF[m].C * double(j);
    ok = ok && f >= 0.0;
  }
}

bool RasterSetup(int j0, int j1, bool toTmp)
{
  int nf = gHasCross ? 4 : 3;
  double P[4], Q[4];
  for (int m = 0; m < nf; ++m)
  {
    precise double B = gF[m].B;
    precise double p = B != 0.0 ? -gF[m].A / B : 0.0LF;
    precise double q = B != 0.0 ? -gF[m].C / B : 0.0LF;
    P[m] = p;
    Q[m] = q;
  }
  bool any = false;
  for (int j = j0; j <= j1; ++j)
  {
    precise double lo = -1e300LF, hi = 1e300LF;
    bool ok = true;
    // the three edges written out (no loop: llvmpipe's loop budget)
    EdgeConstraint(0, P[0], Q[0], j, lo, hi, ok);
    EdgeConstraint(1, P[1], Q[1], j, lo, hi, ok);
    EdgeConstraint(2, P[2], Q[2], j, lo, hi, ok);
    bool strictLo = false, strictHi = false;
    if (nf == 4)
    {
      double B = gF[3].B;
      precise double x = P[3] + Q[3] * double(j);
      if (B > 0.0 && x >= lo)
      {
        lo = x;
        strictLo = true;
      }
      else if (B < 0.0 && x <= hi)
      {
        hi = x;
        strictHi = true;
      }
      else if (B == 0.0)
      {
        precise double f = gF[3].A + gF[3].C * double(j);
        ok = ok && f > 0.0;
      }
    }
    int il, ih;
    if (ok && IntRange(lo, hi, strictLo, strictHi, il, ih))
    {
      if (toTmp)
      {
        tmpRows[j] |= RowBits(il, ih);
      }
      else
      {
        OrRow(j, RowBits(il, ih));
      }
      any = true;
    }
  }
  return any;
}

// three edge planes through S and the triangle's plane (finite light) [§4.2]
bool SetupTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2)
{
  dvec3 a = Sub(B0, S), b = Sub(B1, S), c = Sub(B2, S);
  dvec3 nT = Cross(Sub(b, a), Sub(c, a));
  precise double det = Dot(nT, a);
  if (!(det != 0.0))
  {
    return false;
  }
  double sg = det > 0.0 ? 1.0LF : -1.0LF;
  precise dvec3 e0 = sg * Cross(a, b);
  precise dvec3 e1 = sg * Cross(b, c);
  precise dvec3 e2 = sg * Cross(c, a);
  gF[0] = MakeAffine(e0, 0.0LF);
  gF[1] = MakeAffine(e1, 0.0LF);
  gF[2] = MakeAffine(e2, 0.0LF);
  gHasCross = uDir == 0;
  if (gHasCross)
  {
    precise dvec3 en = sg * nT;
    precise double cn = sg * -det;
    gF[3] = MakeAffine(en, cn);
  }
  return true;
}

bool SetupProjectedTriangle(double X[3], double Y[3])
{
  precise double area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
  if (!(area != 0.0))
  {
    return false;
  }
  double sg = area > 0.0 ? 1.0LF : -1.0LF;
  for (int m = 0; m < 3; ++m)
  {
    int q = (m + 1) % 3;
    precise double ex = X[q] - X[m];
    precise double ey = Y[q] - Y[m];
    precise double A = sg * (ey * X[m] - ex * Y[m]);
    precise double B = sg * -ey;
    precise double C = sg * ex;
    gF[m] = Affine(A, B, C);
  }
  gHasCross = false;
  return true;
}

bool RasterizeTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2, bool toTmp, out int j0, out int j1)
{
  j0 = 0;
  j1 = uK - 1;
  double su[3], sv[3];
  bool projected = uK > 1 && uW > 0.0 && uH > 0.0;
  dvec3 B[3] = dvec3[3](B0, B1, B2);
  for (int m = 0; m < 3 && projected; ++m)
  {
    precise double den = S.z - B[m].z;
    projected = den > 0.0 && (uDir != 0 || B[m].z > 0.0);
    if (projected)
    {
      precise double g = uDir != 0 ? 1.0LF / den : S.z / den;
      precise double u = ((uDir != 0 ? 0.0LF : S.x) + (B[m].x - S.x) * g) / uW;
      precise double v = ((uDir != 0 ? 0.0LF : S.y) + (B[m].y - S.y) * g) / uH;
      su[m] = u;
      sv[m] = v;
    }
  }
  if (projected)
  {
    int i0, i1;
    IndexRange(min(min(su[0], su[1]), su[2]), max(max(su[0], su[1]), su[2]), i0, i1);
    IndexRange(min(min(sv[0], sv[1]), sv[2]), max(max(sv[0], sv[1]), sv[2]), j0, j1);
    if (i0 > i1 || j0 > j1)
    {
      return false;
    }
    double X[3], Y[3];
    for (int m = 0; m < 3; ++m)
    {
      precise double x = (su[m] + 0.5LF) * double(uK) - 0.5LF;
      precise double y = (sv[m] + 0.5LF) * double(uK) - 0.5LF;
      X[m] = x;
      Y[m] = y;
    }
    return SetupProjectedTriangle(X, Y) && RasterSetup(j0, j1, toTmp);
  }
  return SetupTriangle(S, B0, B1, B2) && RasterSetup(j0, j1, toTmp);
}

// the reference's start rule near the triangle's plane: per-sample
// Moeller-Trumbore, hits closer than eps ignored (RasterizeNearTriangle)
// One light sample of RasterizeNearTriangle (the reference's Moeller-Trumbore
// with tnear = eps), for sample i of the current row.
dvec3 gE1, gE2, gTv, gQ;
bool NearSample(int i, double sv)
{
  precise double su = (double(i) + 0.5LF) / double(uK) - 0.5LF;
  precise dvec3 d = gD0 + su * gDu + sv * gDv;
  dvec3 p = Cross(d, gE2);
  precise double det = Dot(gE1, p);
  if (det == 0.0)
  {
    return false;
  }
  precise double a = Dot(gTv, p) / det;
  precise double b = Dot(d, gQ) / det;
  precise double t = Dot(gE2, gQ) / det;
  precise double tl = t * sqrt(Dot(d, d));
  return a >= 0.0 && b >= 0.0 && a + b <= 1.0 && tl >= uEps && (uDir != 0 || t < 1.0);
}
#define NEAR1(I) if ((I) < uK && NearSample(I, sv)) { rb |= 1u << uint(I); }
#define NEAR4(I) NEAR1(I) NEAR1((I) + 1) NEAR1((I) + 2) NEAR1((I) + 3)
#define NEAR16(I) NEAR4(I) NEAR4((I) + 4) NEAR4((I) + 8) NEAR4((I) + 12)

// the reference's start rule near the triangle's plane: per-sample
// Moeller-Trumbore, hits closer than eps ignored (RasterizeNearTriangle).
// The samples of a row are written out, not looped over: llvmpipe ends any
// invocation after 65535 loop iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS,
// shared by every loop of a shader), so per-triangle loops stay at k.
bool RasterizeNearTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2, bool toTmp)
{
  gE1 = Sub(B1, B0);
  gE2 = Sub(B2, B0);
  gTv = Sub(S, B0);
  gQ = Cross(gTv, gE1);
  bool any = false;
  for (int j = 0; j < uK; ++j)
  {
    precise double sv = (double(j) + 0.5LF) / double(uK) - 0.5LF;
    uint rb = 0u;
    NEAR16(0)
    NEAR16(16)
    if (rb != 0u)
    {
      if (toTmp)
      {
        tmpRows[j] |= rb;
      }
      else
      {
        OrRow(j, rb);
      }
      any = true;
    }
  }
  return any;
}


// Chunk uChunk of the pixel's cell list (uChunkSize triangles): the rows
// persist in masks[] between chunks and K_FINISH turns them into V.
uniform uint uChunk, uChunkSize;
void main()
{
  uint i = GID();
  if (i >= uN || pixFace[i] != uFace)
  {
    return;
  }
  uint c = pixCell[i];
  uint a0 = cellBegin[c] + uChunk * uChunkSize;
  uint end = min(cellBegin[c + 1u], a0 + uChunkSize);
  if (uChunk > 0u && a0 >= end)
  {
    return; // this cell's list ended in an earlier chunk
  }
  dvec3 S = ToLight(Start(i));
  gD0 = uDir != 0 ? dvec3(0.0, 0.0, -1.0) : -S;
  gDu = dvec3(uW, 0.0, 0.0);
  gDv = dvec3(0.0, uH, 0.0);
  for (int j = 0; j < 32; ++j)
  {
    rows[j] = 0u;
  }
  if (uChunk == 0u)
  {
    // light samples below the tangent plane are not seen (reference rule)
    dvec3 Nw = dvec3(smp[6 * i + 3], smp[6 * i + 4], smp[6 * i + 5]);
    if (Nw != dvec3(0.0))
    {
      dvec3 N = dvec3(Dot(Nw, uU), Dot(Nw, uV), Dot(Nw, uNrm));
      Affine below = MakeAffine(-N, 0.0LF);
      for (int j = 0; j < uK; ++j)
      {
        precise double blo = -1e300LF, bhi = 1e300LF;
        precise double a = below.A + below.C * double(j);
        double b = below.B;
        if (b > 0.0)
        {
          blo = max(blo, -a / b);
        }
        else if (b < 0.0)
        {
          bhi = min(bhi, a / -b);
        }
        else if (!(a > 0.0))
        {
          blo = 1.0;
          bhi = 0.0;
        }
        int il, ih;
        if (IntRange(blo, bhi, b > 0.0, b < 0.0, il, ih))
        {
          rows[j] |= RowBits(il, ih);
        }
      }
    }
  }
  else
  {
    for (int j = 0; j < uK; ++j)
    {
      rows[j] = masks[32u * i + uint(j)];
    }
  }
  gFull = 0;
  for (int j = 0; j < uK; ++j)
  {
    gFull += rows[j] == uFullRow ? 1 : 0;
  }
  uint necessary = 0u;
  bool dirLight = uDir != 0;
  double sx = S.x, sy = S.y, sd = S.z;
  for (uint a = a0; a < end; ++a)
  {
    if (gFull == uK && uCountNecessary == 0)
    {
      break; // umbra: no further triangle changes V
    }
    uint tri = sorted[a];
    dvec3 Bv[3];
    for (int m = 0; m < 3; ++m)
    {
      Bv[m] = uPre != 0 ? dvec3(triL[9 * tri + 3 * m], triL[9 * tri + 3 * m + 1], triL[9 * tri + 3 * m + 2])
                        : ToLight(dvec3(triV[9 * tri + 3 * m], triV[9 * tri + 3 * m + 1], triV[9 * tri + 3 * m + 2]));
    }
    // cheap rejection (the CPU's candidate filter)
    int out0 = 0, out1 = 0, out2 = 0, out3 = 0, valid = 0, beyondPixel = 0, behindLight = 0;
    for (int m = 0; m < 3; ++m)
    {
      double bx = Bv[m].x, by = Bv[m].y, bd = Bv[m].z;
      precise double den = sd - bd;
      beyondPixel += !(den > 0.0) ? 1 : 0;
      behindLight += (!dirLight && !(bd > 0.0)) ? 1 : 0;
      valid += (den > 0.0 && (dirLight || bd > 0.0)) ? 1 : 0;
      double fx = dirLight ? 1.0LF : sd, gx = dirLight ? 0.0LF : sx;
      precise double ux = (gx - uXlo) * den + (bx - sx) * fx;
      precise double vx = (gx - uXhi) * den + (bx - sx) * fx;
      precise double uy = ((dirLight ? 0.0LF : sy) - uYlo) * den + (by - sy) * fx;
      precise double vy = ((dirLight ? 0.0LF : sy) - uYhi) * den + (by - sy) * fx;
      out0 += ux < 0.0 ? 1 : 0;
      out1 += vx > 0.0 ? 1 : 0;
      out2 += uy < 0.0 ? 1 : 0;
      out3 += vy > 0.0 ? 1 : 0;
    }
    if (beyondPixel == 3 || behindLight == 3 || (valid == 3 && (out0 == 3 || out1 == 3 || out2 == 3 || out3 == 3)))
    {
      continue;
    }
    // opaque casters only (translucent scenes run on the CPU backend)
    bool toTmp = uCountNecessary != 0;
    if (toTmp)
    {
      for (int j = 0; j < uK; ++j)
      {
        tmpRows[j] = 0u;
      }
    }
    int j0 = 0, j1 = uK - 1;
    dvec3 pn = Cross(Sub(Bv[1], Bv[0]), Sub(Bv[2], Bv[0]));
    precise double pl = sqrt(Dot(pn, pn));
    precise double dist = abs(Dot(Sub(S, Bv[0]), pn));
    precise double lim = uEps * pl;
    bool near = pl > 0.0 && dist < lim;
    bool hit = near ? RasterizeNearTriangle(S, Bv[0], Bv[1], Bv[2], toTmp)
                    : RasterizeTriangle(S, Bv[0], Bv[1], Bv[2], toTmp, j0, j1);
    if (hit && toTmp)
    {
      ++necessary;
      for (int j = j0; j <= j1; ++j)
      {
        OrRow(j, tmpRows[j]);
      }
    }
  }
  for (int j = 0; j < uK; ++j)
  {
    masks[32u * i + uint(j)] = rows[j];
  }
  if (uCountNecessary != 0)
  {
    nec[i] += necessary;
  }
}
#endif

#ifdef K_FINISH
// V from the rows of K_RASTER: the fraction of light samples not hidden
uniform int uK;
uniform uint uFullRow;
void main()
{
  uint i = GID();
  if (i >= uN || pixFace[i] != uFace)
  {
    return;
  }
  precise double visible = 0.0LF;
  for (int j = 0; j < uK; ++j)
  {
    visible += double(bitCount(~masks[32u * i + uint(j)] & uFullRow));
  }
  precise double kk = double(uK) * double(uK);
  vis[i] = float(visible / kk);
}
#endif
