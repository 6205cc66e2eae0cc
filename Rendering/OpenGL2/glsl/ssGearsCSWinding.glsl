// GEARS GL, the winding count (after ssGearsCSRaster.glsl, whose exact
// raster functions it uses): the CPU backend's idea (Rendering/Core/
// ssGearsWinding.cxx; gears.md, "The winding count"; Laine et al. 2005,
// "Soft shadow volumes for ray tracing", §3) with cells as the groups.
//
// The OR of the masks of a set T of triangles that lie strictly between S and
// the light is the set of samples where the count of T's triangles covering
// them is positive, and along a sample row that count changes only at the
// row bounds of T's contour edges: edges shared by two members whose edge
// functions are exact negations (bit-identical vertices; S on the same side
// of both planes and opposite traversal, or opposite sides and the same
// traversal) cancel. So per pixel only the contour edges' exact steps are
// needed, with the raster's own operations (SetupTriangle, MakeAffine,
// RowBound), and the members are not rasterised.
//
// K_WFLAG, per (triangle, cell) pair before the sort: the triangle's status
//   in the cell, decided for every start of the cell at once (its light-frame
//   box of starts, K_CELL), which of its edges lie on the cell's contour, and
//   its class in the cell's list (the sort key's): 0 a member with contour
//   edges, 1 the rest, 2 the other members, 3 never drawn there.
// K_WINDING, per pixel, before the raster's first chunk: the steps of its
//   cell's contour edges, the counts along the rows, the rows into masks[]
//   and wind[i] = 1; or declined (wind[i] = 0: the raster draws the members
//   too), where a contour vertex lies within 1e-7 (relative) of a sample row
//   near the samples, an edge runs along the rows, a member's side of S is
//   not the status's, a count is negative, or llvmpipe's loop budget would
//   be passed. Same bits as the raster either way.

#if defined(K_WFLAG) || defined(K_WINDING)
dvec3 L3(uint t, uint m)
{
  return dvec3(triL[9u * t + 3u * m], triL[9u * t + 3u * m + 1u], triL[9u * t + 3u * m + 2u]);
}
#endif

#if defined(K_TOLIGHT) && defined(WINDING)
uniform int uDir;
uniform double uW, uH;
uniform double uMargin; // K_WFLAG's: the shafts' plus 1e-6 of uFar
uniform double uFar;    // the face's reach: the farthest start plus the farthest vertex (light frame)
// Per triangle, what K_WFLAG's Status needs of its plane whatever the cell:
// the unit normal, whether its side can be trusted, and the light's side.
// The side is trusted only where it is far above every rounding: not a
// sliver (|e1 x e2| > 1e-9 |e1| |e2|, the sine of the angle at B0, which is
// what the cross product's relative error depends on: the unit normal is
// then good to 1e-7 relative, 2e-7 once rounded to float, so a distance measured with it errs
// by less than the margin's 1e-6 uFar), and where the raster's det =
// (e1 x e2) . (B0 - S), from coordinates relative to S, which errs by about
// 4u uFar^2 |e| + 3u |e1 x e2| uFar (u = 2^-53), is below |e1 x e2| uMargin
// (at least the distance of every start, for a member) 100 times over.
void PlaneOf(uint t, dvec3 B0, dvec3 B1, dvec3 B2)
{
  dvec3 e1 = Sub(B1, B0), e2 = Sub(B2, B0);
  dvec3 pn = Cross(e1, e2);
  precise double len = sqrt(Dot(pn, pn));
  precise double l1 = sqrt(Dot(e1, e1)), l2 = sqrt(Dot(e2, e2));
  uint flags = 0u;
  vec3 nf = vec3(0.0);
  if (len > 1e-9LF * l1 * l2 && len * uMargin > 5e-14LF * uFar * (uFar * max(l1, l2) + len))
  {
    precise dvec3 un = pn / len;
    nf = vec3(un);
    double cmin, cmax;
    LightCornerRange(un, B0, uW, uH, uDir != 0, cmin, cmax);
    double lm = uDir != 0 ? 1e-6LF : uMargin;
    flags = 1u | (cmin > lm ? 2u : 0u) | (cmax < -lm ? 4u : 0u);
  }
  triN[t] = uvec4(floatBitsToUint(nf.x), floatBitsToUint(nf.y), floatBitsToUint(nf.z), flags);
}
#endif

#ifdef K_WFLAG
uniform double uEpsMax; // the face's largest start offset (K_START, rounded up)
uniform double uMargin; // the shafts' margin plus 1e-6 of the face's reach (PlaneOf)
uniform int uHand;

// Triangle t's status for every start in [lo, hi] (light frame), for a
// triangle strictly between every start and the light (the raster's
// `projected`, so only the three edge planes bound it; the others: 0):
// 1 (every start in front of its plane: the raster's det < 0, sg = -1) or
//   2 (behind: sg = +1) for a member: every start farther from its plane
//   than the largest start offset and the margin (never near S: the start
//   rule does not apply), drawn by the closed-mesh rule;
// 3 where it can hide nothing from any start: every start and the whole
//   light on one side of its plane (Visit's plane test; the CPU's group
//   filter), or the closed-mesh rule skips it for every start;
// 0 for the rest.
uint Status(uint t, dvec3 lo, dvec3 hi)
{
  dvec3 B0 = L3(t, 0u);
  double z1 = triL[9u * t + 5u], z2 = triL[9u * t + 8u];
  if (!(B0.z < lo.z && z1 < lo.z && z2 < lo.z && (uDir != 0 || (B0.z > 0.0 && z1 > 0.0 && z2 > 0.0))))
  {
    return 0u;
  }
  uvec4 nb = triN[t];
  uint flags = nb.w;
  if ((flags & 1u) == 0u)
  {
    return 0u; // its side is not trusted (PlaneOf)
  }
  dvec3 un = dvec3(uintBitsToFloat(nb.x), uintBitsToFloat(nb.y), uintBitsToFloat(nb.z));
  precise dvec3 ctr = 0.5LF * (lo + hi);
  precise dvec3 hw = 0.5LF * (hi - lo);
  precise double sigma = Dot(un, ctr) - Dot(un, B0);
  precise double ext = abs(un.x) * hw.x + abs(un.y) * hw.y + abs(un.z) * hw.z;
  bool front = sigma - ext > uMargin, back = sigma + ext < -uMargin;
  if (!front && !back)
  {
    return 0u;
  }
  // the closed-mesh rule as K_RASTER's Visit: skipped where csl sigma >= 0
  int cs = closedFlag[t];
  int csl = cs == 2 ? 0 : cs * uHand;
  if ((front && (flags & 2u) != 0u) || (back && (flags & 4u) != 0u) || cs == 2 ||
    (csl != 0 && (front ? csl > 0 : csl < 0)))
  {
    return 3u;
  }
  precise double reach = uEpsMax + uMargin;
  return sigma - ext > reach ? 1u : (sigma + ext < -reach ? 2u : 0u);
}
// Whether the edge with neighbour entry v of a member with status st cancels
// in cell c: the neighbour is a member, its edge function the exact negation
// (same side and opposite traversal, or opposite sides and the same
// traversal), and pass 2 listed it in c: c in its box from pass 1 and the
// same CellKeeps on the same vertices (`precise`: the same answer as pass
// 2's compilation).
bool Cancels(uint v, uint c, Shaft sh, uint st)
{
  if (v == 0xFFFFFFFFu)
  {
    return false;
  }
  uint n = v & 0x7FFFFFFFu;
  ivec4 b = box[n];
  int x = int(c / uint(uLayers)) % uG, y = int(c / uint(uLayers)) / uG; // (the grid cell of list cell c)
  if (x < b.x || x > b.z || y < b.y || y > b.w)
  {
    return false;
  }
  uint sn = Status(n, sh.lo, sh.hi);
  bool same = (v & 0x80000000u) != 0u;
  if (!((sn == 1u || sn == 2u) && (same ? sn != st : sn == st)))
  {
    return false;
  }
  // (triL holds LightVertex's values: the same `precise` ToLight, K_TOLIGHT)
  return CellKeepsOf(c, sh, L3(n, 0u), L3(n, 1u), L3(n, 2u));
}
uniform uint uBuckets, uCellKeys;
void main()
{
  uint q = GID();
  if (q >= uN)
  {
    return;
  }
  uint t = pairTri[q], key = pairCell[q];
  uint c = key / uCellKeys;
  Shaft sh = CellShaft(c);
  uint st = Status(t, sh.lo, sh.hi);
  uint e = 0u;
  if (st == 1u || st == 2u)
  {
    e |= Cancels(nbr[3u * t], c, sh, st) ? 0u : 1u;
    e |= Cancels(nbr[3u * t + 1u], c, sh, st) ? 0u : 2u;
    e |= Cancels(nbr[3u * t + 2u], c, sh, st) ? 0u : 4u;
  }
  pairStat[q] = st | (e << 2);
  uint cls = st == 3u ? 3u : (st == 0u ? 1u : (e != 0u ? 0u : 2u));
  pairCell[q] = key + cls * uBuckets;
}
#endif

#ifdef K_WINDING
uniform uint uBuckets, uCellKeys;
uniform uint uMinList; // shorter lists: the raster alone (the CPU's windingMinList)
// llvmpipe's loop budget (65535 iterations in all, ssGearsGL.cxx). It counts
// the iterations of a SIMD vector of invocations: an inner loop runs while
// any of its pixels needs it, so a pixel's own count does not bound it. The
// bound is per slot of the list (the vector's pixels share a cell's list, or
// take the longest of theirs): the slot, 3 edges, at most k rows each; and
// 2 k (k + 1) for the steps' table. A cell with more contour slots than
// that allows is declined (ListBudget).
int delta[1056]; // the count's steps: k rows of k + 1
uint ListBudget()
{
  return uint((65535 - 2 * uK * (uK + 1) - 64) / (3 * uK + 4));
}

// a projected vertex (sample units) within rounding of a sample row near the
// samples (ex, ey: the rounding's bounds from the magnitudes, EdgeSteps)
bool NearRow(double px, double py, double ex, double ey)
{
  double yr = floor(py + 0.5LF);
  return yr >= 0.0 && yr <= double(uK - 1) && abs(py - yr) <= 1e-7LF * (1.0LF + abs(py)) + ey && px >= -1.0 - ex &&
    px <= double(uK) + ex;
}
// The steps of the contour edge from Ba to Bb of a member whose raster takes
// side sg: ContourSteps of Rendering/Core/ssGearsWindingKernels.h, with the
// edge function of SetupTriangle and the row bounds of RowBound (RasterSetup,
// non-strict). The edge steps the rows between its projected vertices
// (half-open: y0 <= j < y1): +1 at its first sample where B > 0, -1 after its
// last where B < 0. False: declined.
bool EdgeSteps(dvec3 Ba, dvec3 Bb, double sg)
{
  double kx = double(uK) / uW, ky = double(uK) / uH, hk = 0.5LF * double(uK) - 0.5LF;
  double g = gDirLight ? 1.0LF : gSd;
  double ox = gDirLight ? 0.0LF : gSx, oy = gDirLight ? 0.0LF : gSy;
  precise double qa = g / (gSd - Ba.z);
  precise double qb = g / (gSd - Bb.z);
  precise double pxa = (ox + (Ba.x - gSx) * qa) * kx + hk;
  precise double pya = (oy + (Ba.y - gSy) * qa) * ky + hk;
  precise double pxb = (ox + (Bb.x - gSx) * qb) * kx + hk;
  precise double pyb = (oy + (Bb.y - gSy) * qb) * ky + hk;
  // 1e-14 of the magnitudes the projection's sums cancel (sample units): about
  // 9 times their rounding; they matter only for a light tiny beside its
  // distance (below about 1e-7 of it the 1e-7 terms no longer cover it)
  precise double exa = 1e-14LF * ((abs(ox) + (abs(Ba.x) + abs(gSx)) * abs(qa)) * kx);
  precise double eya = 1e-14LF * ((abs(oy) + (abs(Ba.y) + abs(gSy)) * abs(qa)) * ky);
  precise double exb = 1e-14LF * ((abs(ox) + (abs(Bb.x) + abs(gSx)) * abs(qb)) * kx);
  precise double eyb = 1e-14LF * ((abs(oy) + (abs(Bb.y) + abs(gSy)) * abs(qb)) * ky);
  if (!(FiniteD(pxa) && FiniteD(pya) && FiniteD(pxb) && FiniteD(pyb)) || NearRow(pxa, pya, exa, eya) ||
    NearRow(pxb, pyb, exb, eyb))
  {
    return false;
  }
  double top = double(uK) + 1.0LF;
  double c0 = clamp(min(pya, pyb), -2.0LF, top), c1 = clamp(max(pya, pyb), -2.0LF, top);
  int j0 = max(int(ceil(c0)), 0), j1 = min(int(ceil(c1)) - 1, uK - 1);
  if (j0 > j1 || min(pxa, pxb) > double(uK - 1) + 1e-7LF * (1.0LF + abs(pxa) + abs(pxb)) + exa + exb)
  {
    return true; // no row, or right of every sample: no step
  }
  precise dvec3 e = sg * Cross(Sub(Ba, gS), Sub(Bb, gS));
  gF[0] = MakeAffine(e, 0.0LF);
  double B = gF[0].B;
  if (!(B != 0.0))
  {
    return false; // along the rows
  }
  precise double p = -gF[0].A / B;
  precise double q = -gF[0].C / B;
  gP[0] = p;
  gQ4[0] = q;
  gSteep[0] = !(abs(p) <= 1e6LF && abs(q) <= 1e6LF);
  int step = B > 0.0 ? 1 : -1;
  for (int j = j0; j <= j1; ++j)
  {
    double jd = double(j);
    precise double ej = gF[0].A + gF[0].C * jd;
    double r = RowBound(0, ej, jd, false);
    double at = B > 0.0 ? r : r + 1.0LF;
    if (at <= double(uK - 1))
    {
      delta[j * (uK + 1) + int(max(at, 0.0LF))] += step;
    }
  }
  return true;
}
bool Count(uint i, uint a0, uint a1)
{
  int nd = uK * (uK + 1);
  for (int q = 0; q < nd; ++q)
  {
    delta[q] = 0;
  }
  for (uint a = a0; a < a1; ++a)
  {
    uint s = slotStat[a];
    uint st = s & 3u, edges = s >> 2;
    if (st == 0u || st == 3u || edges == 0u)
    {
      continue; // not a member, or no edge on the contour
    }
    uint t = sorted[a];
    dvec3 B0 = L3(t, 0u), B1 = L3(t, 1u), B2 = L3(t, 2u);
    // the raster's side of S (SetupTriangle's det), which K_WFLAG's margins
    // make the status's: checked for the members with contour edges
    dvec3 av = Sub(B0, gS), bv = Sub(B1, gS), cv = Sub(B2, gS);
    dvec3 nT = Cross(Sub(bv, av), Sub(cv, av));
    precise double det = Dot(nT, av);
    double sg = det > 0.0 ? 1.0LF : -1.0LF;
    if (!(det != 0.0) || (st == 1u) != (sg < 0.0))
    {
      return false;
    }
    dvec3 Bm[3] = dvec3[3](B0, B1, B2);
    for (int m = 0; m < 3; ++m)
    {
      if (((edges >> uint(m)) & 1u) != 0u && !EdgeSteps(Bm[m], Bm[(m + 1) % 3], sg))
      {
        return false;
      }
    }
  }
  // the counts along the rows (a negative count: a contour that does not close)
  uint counted[32];
  for (int j = 0; j < uK; ++j)
  {
    int run = 0;
    uint bits = 0u;
    for (int q = 0; q < uK; ++q)
    {
      run += delta[j * (uK + 1) + q];
      if (run < 0)
      {
        return false;
      }
      bits |= run > 0 ? 1u << uint(q) : 0u;
    }
    counted[j] = bits;
  }
  for (int j = 0; j < uK; ++j)
  {
    masks[32u * i + uint(j)] = counted[j];
  }
  return true;
}
void main()
{
  uint gi = GID();
  if (gi >= uN)
  {
    return;
  }
  uint i = pixOrder[gi];
  uint c = pixCell[i];
  // the members with contour edges come first in the cell's list (K_WFLAG)
  uint k0 = c * uCellKeys;
  uint a0 = cellBegin[k0], a1 = cellBegin[k0 + uBuckets];
  wind[i] = 0u;
  if (cellBegin[k0 + 3u * uBuckets] - a0 < uMinList)
  {
    return;
  }
  if (a1 - a0 > ListBudget())
  {
    atomicAdd(red[63], 1u); // declined: too many contour slots for the loop budget
    return;
  }
  PixelFrame(i);
  if (Count(i, a0, a1))
  {
    wind[i] = 1u;
    atomicAdd(red[62], 1u);
  }
  else
  {
    atomicAdd(red[63], 1u);
  }
}
#endif
