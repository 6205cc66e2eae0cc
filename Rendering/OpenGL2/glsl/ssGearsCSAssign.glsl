// GEARS GL, steps 2-3 (after ssGearsCSCommon.glsl): pixel samples, grid,
// shadow-volume boxes with P_far, prefix sums, pairs, the sort on the cell.

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
uniform double uScale;      // the casters' bulk diagonal: StartOffset (ssTriangleSet.h)
uniform dvec3 uLu, uLv;     // the light's axes and half size: DistanceToLight (ssLightFrame.h)
uniform dvec2 uLhalf;
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
        precise double eps = uScale > 0.0 ? 1e-5LF * max(uScale, sqrt(Dot(p, p))) : 0.0LF;
        if (uType != 1)
        {
          // at most 1e-3 of the distance to the light (StartOffset)
          precise dvec3 f = Sub(p, uLc);
          precise double du = max(abs(Dot(f, uLu)) - uLhalf.x, 0.0LF);
          precise double dv = max(abs(Dot(f, uLv)) - uLhalf.y, 0.0LF);
          precise double dn = Dot(f, uLn);
          precise double dl = sqrt(du * du + dv * dv + dn * dn);
          eps = uScale > 0.0 ? min(eps, 1e-3LF * dl) : eps;
        }
        precise dvec3 S = p + N * eps;
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
          smp[7 * i] = S.x;
          smp[7 * i + 1] = S.y;
          smp[7 * i + 2] = S.z;
          smp[7 * i + 3] = N.x;
          smp[7 * i + 4] = N.y;
          smp[7 * i + 5] = N.z;
          smp[7 * i + 6] = eps;
          uint b = uint(8 * face);
          for (int c = 0; c < 3; ++c)
          {
            atomicMin(sRed[b + c], Ord(FloatDown(S[c])));
            atomicMax(sRed[b + 3 + c], Ord(FloatUp(S[c])));
          }
          atomicMax(sRed[b + 6], Ord(FloatUp(dot(S - uLc, n))));
          atomicMax(red[61], Ord(FloatUp(eps))); // (the winding count's margin)
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
// 3.2: samples to cells; per cell the count, the farthest depth (rounded up)
// and the light-frame box of the starts (rounded outwards) for pass 2's shaft.
//
// With depth layers (uLayers > 1; the GL backend's form of the CPU's sample
// groups) a grid cell's samples are split where their depths leave a gap, so
// that a list cell holds samples of one layer of the surface (an isosurface's
// sheets, a part and the floor below it) and more of the triangles it lists
// lie between all of them and the light (K_WFLAG's members). Three dispatches:
// - uStage 0: each grid cell's range of depths (cellDepth[c] the farthest,
//   cellDepth[G^2 + c] the nearest);
// - uStage 1: which of 32 equal bins of that range hold a sample (a bit each,
//   cellDepth[2 G^2 + c]);
// - uStage 2 (alone without layers): each sample's list cell, c uLayers plus
//   the number of the cell's uLayers - 1 longest empty runs of bins below its
//   bin. A cell with fewer gaps keeps fewer layers; one whose depths leave
//   none (a tilted plane) stays whole.
// The layers only choose which samples share a list: each list cell's box is
// its own samples', so no bit depends on them.
uniform int uStage;
// (NaN or an empty range: bin 0)
uint DepthBin(double d, uint c)
{
  uint G2 = uint(uG * uG);
  double lo = double(Unord(cellDepth[G2 + c])), hi = double(Unord(cellDepth[c]));
  double f = 32.0LF * (d - lo) / (hi - lo);
  return f >= 31.0LF ? 31u : (f > 0.0LF ? uint(f) : 0u);
}
// the layer of bin b among the bins in use (occ): the number of the uLayers - 1
// longest empty runs between used bins that lie below b (the lower first on ties)
uint LayerOf(uint occ, uint b)
{
  uint taken = 0u; // bins of the runs already chosen
  uint layer = 0u;
  for (int g = 0; g < uLayers - 1; ++g)
  {
    uint bestLen = 0u, bestAt = 0u, len = 0u;
    bool seen = false;
    for (uint q = 0u; q < 32u; ++q)
    {
      bool used = (occ & (1u << q)) != 0u;
      if (used)
      {
        if (seen && len > bestLen && (taken & (1u << (q - 1u))) == 0u)
        {
          bestLen = len;
          bestAt = q - 1u;
        }
        seen = true;
        len = 0u;
      }
      else if (seen)
      {
        ++len;
      }
    }
    if (bestLen == 0u)
    {
      break;
    }
    taken |= 1u << bestAt; // (a run is marked by its last bin)
    layer += bestAt < b ? 1u : 0u;
  }
  return layer;
}
void main()
{
  uint i = GID();
  if (i < uN && pixFace[i] == uFace)
  {
    dvec3 S = Start(i);
    uint c = CellOf(ToGrid(Project(S)));
    double d = Depth(S);
    uint G2 = uint(uG * uG);
    if (uStage == 0)
    {
      atomicMax(cellDepth[c], Ord(NextUp(float(d))));
      atomicMin(cellDepth[G2 + c], Ord(FloatDown(d)));
      return;
    }
    if (uStage == 1)
    {
      atomicOr(cellDepth[2u * G2 + c], 1u << DepthBin(d, c));
      return;
    }
    atomicMax(cellDepth[c], Ord(NextUp(float(d))));
    if (uLayers > 1)
    {
      c = c * uint(uLayers) + LayerOf(cellDepth[2u * G2 + c], DepthBin(d, c));
    }
    pixCell[i] = c;
    atomicAdd(cellCount[c], 1u);
    dvec3 B = ToLight(S);
    atomicMin(cellBox[6u * c], Ord(FloatDown(B.x)));
    atomicMin(cellBox[6u * c + 1u], Ord(FloatDown(B.y)));
    atomicMin(cellBox[6u * c + 2u], Ord(FloatDown(B.z)));
    atomicMin(cellBox[6u * c + 3u], Ord(FloatDown(-B.x)));
    atomicMin(cellBox[6u * c + 4u], Ord(FloatDown(-B.y)));
    atomicMin(cellBox[6u * c + 5u], Ord(FloatDown(-B.z)));
  }
}
#endif

#ifdef K_SAT_ROWS
// grid cell c (of the G x G) has samples in one of its depth layers
bool NonEmpty(uint c)
{
  uint n = 0u;
  for (uint l = 0u; l < uint(uLayers); ++l)
  {
    n += cellCount[c * uint(uLayers) + l];
  }
  return n != 0u;
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
      run += NonEmpty(y * uint(uG) + x) ? 1u : 0u;
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

#if defined(K_PASS1) || defined(K_PASS2) || defined(K_WFLAG)
// The cell shafts (issue 23's twelfth round; the CPU backend's cell culling,
// ssGearsCells.cxx): a pair whose triangle lies wholly outside the shaft from
// the cell's samples (K_CELL's box of their starts) to the light is not
// listed: no segment from a start in the cell to a light sample can meet the
// triangle, so no bit changes. Pass 1 counts the cells that pass and pass 2
// writes them, so the pairs' buffer holds only those.
uniform int uShaft, uDir;
uniform double uW, uH, uShaftMargin;
// One side of MakeShaft (ssGearsPairs.cxx) in double: every point of a
// segment from a start in [lo1, hi1] x [loz, hiz] to the light satisfies
// a + sl z <= x <= b + tl z.
// (`precise` throughout: K_WFLAG repeats pass 2's test for a neighbour and
// must get the same answer from its own compilation)
dvec4 ShaftSide(double lo1, double hi1, double side, double loz, double hiz)
{
  if (uDir != 0)
  {
    precise dvec4 r = dvec4(lo1 - 0.5LF * side * hiz, 0.5LF * side, hi1 + 0.5LF * side * hiz, -0.5LF * side);
    return r;
  }
  precise double a0 = (lo1 + 0.5LF * side) / loz, a1 = (lo1 + 0.5LF * side) / hiz;
  precise double b0 = (hi1 - 0.5LF * side) / loz, b1 = (hi1 - 0.5LF * side) / hiz;
  return dvec4(-0.5LF * side, min(a0, a1), 0.5LF * side, max(b0, b1));
}
// vertex coordinate x at depth z beyond a + s z by more than m on the low
// (below) or the high side
bool Below(double x, double z, double a, double s, double m)
{
  precise double bound = a + s * z - m;
  return x < bound;
}
bool Above(double x, double z, double a, double s, double m)
{
  precise double bound = a + s * z + m;
  return x > bound;
}
// Whether all three vertices lie beyond one plane of cell c's shaft by more
// than the margin (written out: llvmpipe's loop budget counts every loop).
// Cell c's shaft: its box of starts and its four sides (none where a start
// lies on the light's plane: no finite slopes).
struct Shaft
{
  dvec3 lo, hi;
  dvec4 sx, sy;
  bool finite;
};
Shaft CellShaft(uint c)
{
  Shaft s;
  s.lo = dvec3(Unord(cellBox[6u * c]), Unord(cellBox[6u * c + 1u]), Unord(cellBox[6u * c + 2u]));
  s.hi = -dvec3(Unord(cellBox[6u * c + 3u]), Unord(cellBox[6u * c + 4u]), Unord(cellBox[6u * c + 5u]));
  s.finite = uDir != 0 || s.lo.z > 0.0;
  s.sx = ShaftSide(s.lo.x, s.hi.x, uW, s.lo.z, s.hi.z);
  s.sy = ShaftSide(s.lo.y, s.hi.y, uH, s.lo.z, s.hi.z);
  return s;
}
bool OutsideShaftOf(dvec3 A, dvec3 B, dvec3 C, Shaft s)
{
  if (!s.finite)
  {
    return false;
  }
  dvec3 hi = s.hi;
  dvec4 sx = s.sx, sy = s.sy;
  double m = uShaftMargin;
  if (Below(A.x, A.z, sx.x, sx.y, m) && Below(B.x, B.z, sx.x, sx.y, m) && Below(C.x, C.z, sx.x, sx.y, m))
  {
    return true;
  }
  if (Above(A.x, A.z, sx.z, sx.w, m) && Above(B.x, B.z, sx.z, sx.w, m) && Above(C.x, C.z, sx.z, sx.w, m))
  {
    return true;
  }
  if (Below(A.y, A.z, sy.x, sy.y, m) && Below(B.y, B.z, sy.x, sy.y, m) && Below(C.y, C.z, sy.x, sy.y, m))
  {
    return true;
  }
  if (Above(A.y, A.z, sy.z, sy.w, m) && Above(B.y, B.z, sy.z, sy.w, m) && Above(C.y, C.z, sy.z, sy.w, m))
  {
    return true;
  }
  precise double mz = -m, hz = hi.z + m;
  if (uDir == 0 && A.z < mz && B.z < mz && C.z < mz)
  {
    return true; // behind the light's plane
  }
  return A.z > hz && B.z > hz && C.z > hz; // beyond every start
}
bool CellKeepsOf(uint c, Shaft s, dvec3 A, dvec3 B, dvec3 C)
{
  return cellCount[c] != 0u && (uShaft == 0 || !OutsideShaftOf(A, B, C, s));
}
bool CellKeeps(uint c, dvec3 A, dvec3 B, dvec3 C)
{
  return CellKeepsOf(c, CellShaft(c), A, B, C);
}
#if defined(K_PASS1) || defined(K_PASS2)
// The list cells of grid cell c (its depth layers, K_CELL) that keep the
// triangle, a bit each. Written out, not looped: llvmpipe's loop budget
// counts these as pass 1's and 2's G^2 iterations each (at most 4 layers).
uint KeptLayers(uint c, dvec3 A, dvec3 B, dvec3 C)
{
  uint L = uint(uLayers), m = CellKeeps(c * L, A, B, C) ? 1u : 0u;
  if (L > 1u && CellKeeps(c * L + 1u, A, B, C))
  {
    m |= 2u;
  }
  if (L > 2u && CellKeeps(c * L + 2u, A, B, C))
  {
    m |= 4u;
  }
  if (L > 3u && CellKeeps(c * L + 3u, A, B, C))
  {
    m |= 8u;
  }
  return m;
}
#endif
dvec3 LightVertex(uint t, uint m)
{
  return ToLight(dvec3(triV[9u * t + 3u * m], triV[9u * t + 3u * m + 1u], triV[9u * t + 3u * m + 2u]));
}
#endif

#ifdef K_PASS1
// 3.3 pass 1: per triangle the 2-D AABB of its 15-point shadow volume,
// extruded to the farthest sample and retracted to P_far of the cells it
// touches [§3.1, Fig. 5]; cellsN = its non-empty cells (summed-area table),
// or, with the cell shafts, those of them whose shaft it may reach.
uniform double uMaxDepth, uMinDepth;
uniform int uCorners, uRetract;
uniform dvec3 uCorner[4], uAway[4];
// > 0: an estimate (ssGearsGL.cxx, kLayerSample): triangles uSample i only,
// their lists' count summed into red[59] (a wrap sets red[57]), nothing else
// kept (the host resets the counters this touches)
uniform uint uSample;
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
  uint t = GID() * max(uSample, 1u);
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
  if (behind || dMin >= uMaxDepth || closedFlag[t] == 2)
  {
    // behind the light plane, beyond every sample, or a closed piece's face
    // turned away from the whole light: changes no bit
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
  if (uSample == 0u)
  {
    box[t] = b;
  }
  uint n = 0u;
  if (b.x <= b.z && b.y <= b.w && uShaft != 0)
  {
    // the cells pass 2 will list (at most G + G^2 iterations, as pass 2)
    dvec3 L0 = LightVertex(t, 0u), L1 = LightVertex(t, 1u), L2 = LightVertex(t, 2u);
    uint nonEmpty = 0u;
    for (int y = b.y; y <= b.w; ++y)
    {
      for (int x = b.x; x <= b.z; ++x)
      {
        uint c = uint(y * uG + x), L = uint(uLayers);
        nonEmpty += (cellCount[c * L] != 0u ? 1u : 0u) + (L > 1u && cellCount[c * L + 1u] != 0u ? 1u : 0u) +
          (L > 2u && cellCount[c * L + 2u] != 0u ? 1u : 0u) + (L > 3u && cellCount[c * L + 3u] != 0u ? 1u : 0u);
        n += uint(bitCount(KeptLayers(c, L0, L1, L2)));
      }
    }
    if (nonEmpty > n)
    {
      atomicAdd(red[58], nonEmpty - n); // pairs outside their cell's shaft
    }
  }
  else if (b.x <= b.z && b.y <= b.w)
  {
    uint G1 = uint(uG) + 1u;
    n = sat[uint(b.w + 1) * G1 + uint(b.z + 1)] - sat[uint(b.y) * G1 + uint(b.z + 1)] -
      sat[uint(b.w + 1) * G1 + uint(b.x)] + sat[uint(b.y) * G1 + uint(b.x)];
  }
  if (n > 0u)
  {
    // the nearest listed depth (pass 2's order; clamped: float(double) is
    // undefined beyond the float range)
    atomicMin(red[60], Ord(FloatDown(clamp(dMin, -1e38LF, 1e38LF))));
  }
  if (uSample != 0u)
  {
    uint before = atomicAdd(red[59], n);
    if (before + n < before)
    {
      atomicOr(red[57], 1u);
    }
    return;
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
// 3.3 pass 2: the (triID, cellID) pairs at the prefix-sum offsets: the
// non-empty cells of the triangle's box that pass 1 counted, the same test
// in the same order (so exactly cellsN of them).
// Each pair's cell comes as c uBuckets + the triangle's depth bucket, so
// that the counting sort on it puts a cell's list in depth order, the
// farthest from the light (nearest the receivers) first: the CPU backend's
// depth order, with which umbra masks fill early. The buckets split the
// listed triangles' depths (pass 1's nearest, red[60], to the farthest
// sample); only the order depends on them, not a bit.
uniform int uBuckets;
uniform uint uCellKeys; // sort keys per cell: uBuckets, times 4 with the winding count's classes (K_WFLAG)
uniform double uMaxDepth;
void Put(inout uint o, uint t, uint c, uint bucket)
{
  pairTri[o] = t;
  pairCell[o] = c * uCellKeys + bucket;
  ++o;
}
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
  dvec3 L0 = LightVertex(t, 0u), L1 = LightVertex(t, 1u), L2 = LightVertex(t, 2u);
  double zlo = double(Unord(red[60]));
  double f = double(uBuckets) * (uMaxDepth - max(max(L0.z, L1.z), L2.z)) / (uMaxDepth - zlo);
  // (a NaN depth: the first bucket; only the order depends on it)
  uint bucket = f >= double(uBuckets) ? uint(uBuckets - 1) : (f > 0.0 ? uint(f) : 0u);
  ivec4 b = box[t];
  for (int y = b.y; y <= b.w; ++y)
  {
    for (int x = b.x; x <= b.z; ++x)
    {
      uint c = uint(y * uG + x), L = uint(uLayers);
      uint m = KeptLayers(c, L0, L1, L2);
      if ((m & 1u) != 0u)
      {
        Put(o, t, c * L, bucket);
      }
      if ((m & 2u) != 0u)
      {
        Put(o, t, c * L + 1u, bucket);
      }
      if ((m & 4u) != 0u)
      {
        Put(o, t, c * L + 2u, bucket);
      }
      if ((m & 8u) != 0u)
      {
        Put(o, t, c * L + 3u, bucket);
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
    uint a = cellBegin[c] + atomicAdd(cursor[c], 1u);
    sorted[a] = pairTri[q];
#ifdef WINDING
    slotStat[a] = pairStat[q];
#endif
  }
}
#endif


