// GEARS GL, step 4 (after ssGearsCSCommon.glsl and ssGearsCSAssign.glsl):
// the per-pixel bitmasks and V.

#ifdef K_PIXSORT
// The face's pixels in the order of their cells (a counting sort; the order
// within a cell is whatever the atomics give, and changes no result): the
// bitmask kernel's neighbouring invocations, which a CPU driver such as
// llvmpipe runs together in SIMD lanes, then read the same list, so they
// load the same triangle at each step and take the same branches more often.
void main()
{
  uint i = GID();
  if (i < uN && pixFace[i] == uFace)
  {
    uint c = pixCell[i];
    pixOrder[pixStart[c] + atomicAdd(cursor[c], 1u)] = i;
  }
}
#endif

#ifdef K_TOLIGHT
#ifdef WINDING
void PlaneOf(uint t, dvec3 B0, dvec3 B1, dvec3 B2); // (glsl/ssGearsCSWinding.glsl)
#endif
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
      vec3 F = SafeFloat(B);
      triLF[9 * t + 3 * m] = F.x;
      triLF[9 * t + 3 * m + 1] = F.y;
      triLF[9 * t + 3 * m + 2] = F.z;
    }
#ifdef WINDING
    dvec3 B0 = dvec3(triL[9 * t], triL[9 * t + 1], triL[9 * t + 2]);
    dvec3 B1 = dvec3(triL[9 * t + 3], triL[9 * t + 4], triL[9 * t + 5]);
    dvec3 B2 = dvec3(triL[9 * t + 6], triL[9 * t + 7], triL[9 * t + 8]);
    PlaneOf(t, B0, B1, B2);
#endif
  }
}
#endif

#if defined(K_RASTER) || defined(K_WINDING)
// Step 4 [§4.2]: per pixel sample the k x k bitmask of hidden light samples
// from its cell's triangles, in the light's frame (origin L_c, axes u v n).
// The arithmetic repeats Rendering/Core's exact raster (ssGearsRaster.cxx:
// SetupTriangle, RasterSetup, RasterizeTriangle, RasterizeNearTriangle; the
// closed-mesh rule and the start rule's test of ssGearsKernels.h SetupBatch)
// operation for operation, with `precise`, so the bits are the CPU's.
uniform int uK, uDir, uCountNecessary, uHand;
uniform int uPre; // the triangles' light-frame vertices are in triL (K_TOLIGHT)
uniform uint uFullRow;
uniform double uW, uH, uInvK, uXlo, uXhi, uYlo, uYhi;

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
  precise double h = 0.5LF * uInvK - 0.5LF;
  precise double A = (constant + Dot(e, gD0)) + h * (du + dv);
  precise double B = du * uInvK;
  precise double C = dv * uInvK;
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

uint rows[32];
uint tmpRows[32];
uint coverRows[32];
uint belowRows[32];
int gFull; // rows of `rows` that are full (umbra when == k)
void OrRow(int j, uint bits)
{
  bool was = rows[j] == uFullRow;
  rows[j] |= bits;
  gFull += (!was && rows[j] == uFullRow) ? 1 : 0;
}

// the triangle's constraints: edge[3] (+ its plane) as TriangleSetup
Affine gF[4];
bool gHasCross;
double gP[4], gQ4[4];
bool gSteep[4];

// three edge planes through S and, if `cross`, the triangle's plane [§4.2]
bool SetupTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2, bool cross)
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
  gHasCross = cross && uDir == 0;
  if (gHasCross)
  {
    precise dvec3 en = sg * nT;
    precise double cn = sg * -det;
    gF[3] = MakeAffine(en, cn);
  }
  return true;
}

// RowBound of ssGearsRaster.cxx: the row's root, then the signs of the
// constraint at the samples next to it
double RowBound(int m, double ej, double jd, bool strict)
{
  double B = gF[m].B;
  precise double xr = gSteep[m] ? -ej / B : gP[m] + gQ4[m] * jd;
  double x = xr < -2.0LF ? -2.0LF : (xr > double(uK) + 1.0LF ? double(uK) + 1.0LF : xr);
  if (B > 0.0)
  {
    double c = ceil(x);
    precise double em = ej + B * (c - 1.0LF);
    precise double e0 = ej + B * c;
    bool okm = strict ? em > 0.0 : em >= 0.0;
    bool ok0 = strict ? e0 > 0.0 : e0 >= 0.0;
    return okm ? c - 1.0LF : (ok0 ? c : c + 1.0LF);
  }
  double c = floor(x);
  precise double ep = ej + B * (c + 1.0LF);
  precise double e0 = ej + B * c;
  bool okp = strict ? ep > 0.0 : ep >= 0.0;
  bool ok0 = strict ? e0 > 0.0 : e0 >= 0.0;
  return okp ? c + 1.0LF : (ok0 ? c : c - 1.0LF);
}
void Constraint(int m, double jd, inout double lo, inout double hi, inout bool ok)
{
  bool strict = m == 3;
  precise double ej = gF[m].A + gF[m].C * jd;
  if (gF[m].B > 0.0)
  {
    lo = max(lo, RowBound(m, ej, jd, strict));
  }
  else if (gF[m].B < 0.0)
  {
    hi = min(hi, RowBound(m, ej, jd, strict));
  }
  else
  {
    ok = ok && (strict ? ej > 0.0 : ej >= 0.0);
  }
}

// RasterSetup: rows [j0, j1] of the samples every constraint admits, into
// rows (0), tmpRows (1) or coverRows (2); whether any bit was set
bool RasterSetup(int j0, int j1, int target)
{
  int nf = gHasCross ? 4 : 3;
  for (int m = 0; m < nf; ++m)
  {
    precise double B = gF[m].B;
    precise double p = B != 0.0 ? -gF[m].A / B : 0.0LF;
    precise double q = B != 0.0 ? -gF[m].C / B : 0.0LF;
    gP[m] = p;
    gQ4[m] = q;
    gSteep[m] = !(abs(p) <= 1e6LF && abs(q) <= 1e6LF);
  }
  bool any = false;
  for (int j = j0; j <= j1; ++j)
  {
    double jd = double(j);
    double lo = 0.0LF, hi = double(uK - 1);
    bool ok = true;
    // the constraints written out (no loop: llvmpipe's loop budget)
    Constraint(0, jd, lo, hi, ok);
    Constraint(1, jd, lo, hi, ok);
    Constraint(2, jd, lo, hi, ok);
    if (nf == 4)
    {
      Constraint(3, jd, lo, hi, ok);
    }
    if (ok && lo <= hi)
    {
      uint bits = RowBits(int(lo), int(hi));
      if (target == 0)
      {
        OrRow(j, bits);
      }
      else if (target == 1)
      {
        tmpRows[j] |= bits;
      }
      else
      {
        coverRows[j] |= bits;
      }
      any = true;
    }
  }
  return any;
}

// RasterizeTriangle: the edge planes, and the triangle's plane unless all
// three vertices lie strictly between S and the light; rows j0..j1 (the rows
// of the samples the triangle may hide: no other row gets a bit)
bool RasterizeTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2, bool toTmp, int j0, int j1)
{
  bool projected = uK > 1 && uW > 0.0 && uH > 0.0;
  dvec3 B[3] = dvec3[3](B0, B1, B2);
  for (int m = 0; m < 3; ++m)
  {
    precise double den = S.z - B[m].z;
    projected = projected && den > 0.0 && (uDir != 0 || B[m].z > 0.0);
  }
  return SetupTriangle(S, B0, B1, B2, !projected) && RasterSetup(j0, j1, toTmp ? 1 : 0);
}

// RasterizeNearTriangle: the covered samples not already hidden, each kept
// only if its Moeller-Trumbore hit lies at least eps from S (the reference's
// start rule)
dvec3 gE1, gE2, gTv, gQ;
double gEps; // the pixel's start offset (smp)
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
  precise double t = Dot(gE2, gQ) / det;
  precise double tl = t * sqrt(Dot(d, d));
  return tl >= gEps;
}
// the samples of a row are written out, not looped over: llvmpipe ends any
// invocation after 65535 loop iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS)
#define NEAR1(I) if (((todo >> uint(I)) & 1u) != 0u && NearSample(I, sv)) { rb |= 1u << uint(I); }
#define NEAR4(I) NEAR1(I) NEAR1((I) + 1) NEAR1((I) + 2) NEAR1((I) + 3)
#define NEAR16(I) NEAR4(I) NEAR4((I) + 4) NEAR4((I) + 8) NEAR4((I) + 12)
bool RasterizeNearTriangle(dvec3 S, dvec3 B0, dvec3 B1, dvec3 B2, bool toTmp)
{
  for (int j = 0; j < 32; ++j)
  {
    coverRows[j] = 0u;
  }
  if (!SetupTriangle(S, B0, B1, B2, true) || !RasterSetup(0, uK - 1, 2))
  {
    return false;
  }
  gE1 = Sub(B1, B0);
  gE2 = Sub(B2, B0);
  gTv = Sub(S, B0);
  gQ = Cross(gTv, gE1);
  bool any = false;
  for (int j = 0; j < uK; ++j)
  {
    uint todo = coverRows[j] & ~(toTmp ? belowRows[j] : rows[j]);
    if (todo == 0u)
    {
      continue;
    }
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


// The float pre-test: which of the double rejection tests of main() (each
// vertex beyond the pixel, behind the light, outside one side of the
// pyramid from S to the samples, below the tangent plane) a vertex surely
// passes, from the light-frame coordinates rounded to float (K_TOLIGHT). Each
// float quantity errs by less than 1e-6 of the magnitude bound its margin
// scales (products of the coordinates' absolute values: the rounding of the
// inputs and of the float operations), and the margins, 1e-5 of those
// bounds, are 1e4 times the double tests' own (1e-9 relative). So a test the
// float passes for all three vertices, the double passes too: the triangle
// would be rejected there, and it sets no bit either way.
vec3 fS, fN;    // S and the tangent plane's normal in float
float fNl1;     // |fN|_1 (0: no horizon test)
float fXlo, fXhi, fYlo, fYhi;
float fXm, fYm; // max(|fXlo|, |fXhi|), the same in y
uint FloatOut(vec3 P)
{
  bool dirL = uDir != 0;
  float den = fS.z - P.z;
  float ad = abs(fS.z) + abs(P.z);
  float fx = dirL ? 1.0 : fS.z, gx = dirL ? 0.0 : fS.x, gy = dirL ? 0.0 : fS.y;
  float ux = (gx - fXlo) * den + (P.x - fS.x) * fx;
  float vx = (gx - fXhi) * den + (P.x - fS.x) * fx;
  float uy = (gy - fYlo) * den + (P.y - fS.y) * fx;
  float vy = (gy - fYhi) * den + (P.y - fS.y) * fx;
  // (each margin with an absolute floor of 1e-30, far above what underflow
  // in the float products can change)
  float mx = 1e-5 * (dirL ? fXm * ad + abs(P.x) + abs(fS.x) : (abs(fS.x) + fXm + abs(P.x)) * ad) + 1e-30;
  float my = 1e-5 * (dirL ? fYm * ad + abs(P.y) + abs(fS.y) : (abs(fS.y) + fYm + abs(P.y)) * ad) + 1e-30;
  // the directional side tests count only where all three vertices are
  // surely in front of S (the double's `valid`)
  bool sides = !dirL || den > 1e-5 * ad + 1e-30;
  vec3 rel = P - fS;
  float l1 = abs(P.x) + abs(P.y) + abs(P.z) + abs(fS.x) + abs(fS.y) + abs(fS.z);
  uint o = 0u;
  o |= P.z - fS.z > 1e-5 * ad + 1e-30 ? 1u : 0u; // beyond the pixel
  o |= (!dirL && P.z < 0.0) ? 2u : 0u;            // behind the light
  o |= (sides && ux < -mx) ? 4u : 0u;
  o |= (sides && vx > mx) ? 8u : 0u;
  o |= (sides && uy < -my) ? 16u : 0u;
  o |= (sides && vy > my) ? 32u : 0u;
  o |= (fNl1 > 0.0 && dot(rel, fN) < -(1e-5 * l1 * fNl1 + 1e-30)) ? 64u : 0u; // below the tangent plane
  return o;
}

// rows r0..r1 all hold the bits cm (written out: llvmpipe's loop budget)
#define COV1(J) covered = covered && ((J) < r0 || (J) > r1 || (rows[J] & cm) == cm);
#define COV4(J) COV1(J) COV1((J) + 1) COV1((J) + 2) COV1((J) + 3)
#define COV16(J) COV4(J) COV4((J) + 4) COV4((J) + 8) COV4((J) + 12)

// the pixel's state for Visit
dvec3 gS, gHN;       // S and the tangent plane's normal in the light's frame
double gHlen;        // |gHN| (0: no horizon test)
double gSx, gSy, gSd;
bool gDirLight;
uint gNecessary;     // Table 9: pairs hiding a sample above the horizon

// Whether the float pre-test keeps the triangle (the double tests of Visit
// would surely reject it otherwise).
bool FloatKeeps(uint tri)
{
  return uPre == 0 ||
    (FloatOut(vec3(triLF[9 * tri], triLF[9 * tri + 1], triLF[9 * tri + 2])) &
      FloatOut(vec3(triLF[9 * tri + 3], triLF[9 * tri + 4], triLF[9 * tri + 5])) &
      FloatOut(vec3(triLF[9 * tri + 6], triLF[9 * tri + 7], triLF[9 * tri + 8]))) == 0u;
}
// One triangle of the pixel's list [§4.2], in the second phase: whether it
// passes every rejection and is not covered already (then gInfo holds what
// DrawSurvivor needs).
uint gInfo; // what Visit found, for DrawSurvivor
bool Visit(uint tri)
{
  dvec3 Bv[3];
  for (int m = 0; m < 3; ++m)
  {
    Bv[m] = uPre != 0 ? dvec3(triL[9 * tri + 3 * m], triL[9 * tri + 3 * m + 1], triL[9 * tri + 3 * m + 2])
                      : ToLight(dvec3(triV[9 * tri + 3 * m], triV[9 * tri + 3 * m + 1], triV[9 * tri + 3 * m + 2]));
  }
  // the closed-mesh rule, exactly as the CPU's SetupBatch: a face gS is
  // not behind is never the last crossing
  dvec3 pn = Cross(Sub(Bv[1], Bv[0]), Sub(Bv[2], Bv[0]));
  precise double sigma = Dot(Sub(gS, Bv[0]), pn);
  int cs = closedFlag[tri];
  int csl = cs == 2 ? 0 : cs * uHand;
  if (csl != 0 && double(csl) * sigma >= 0.0)
  {
    return false;
  }
  precise double pl = sqrt(Dot(pn, pn));
  precise double lim = gEps * pl;
  bool near = pl > 0.0 && abs(sigma) < lim;
  if (near)
  {
    // gS and every light sample on one side of the plane: no crossing
    double cmin, cmax;
    LightCornerRange(pn, Bv[0], uW, uH, gDirLight, cmin, cmax);
    if ((sigma > 0.0 && cmin >= 0.0) || (sigma < 0.0 && cmax <= 0.0))
    {
      return false;
    }
  }
  // cheap rejection: wholly beyond the pixel, behind the light, or
  // projected beyond one side of the samples (it would set no bit). The
  // side tests are linear in the vertex (a side plane of the pyramid from
  // gS to the samples), so they hold for a triangle that straddles gS's depth
  // or the light's plane too; there, with a relative margin (t0 - t3), as
  // the CPU's rejection kernel does in float (gears.md, eleventh round)
  int out0 = 0, out1 = 0, out2 = 0, out3 = 0, valid = 0, beyondPixel = 0, behindLight = 0;
  int t0 = 0, t1 = 0, t2 = 0, t3 = 0, belowPlane = 0;
  // the projection in sample-index units (where all three are valid): a
  // triangle between two sample rows or columns sets no bit either (as the
  // CPU's rejection kernel)
  double iu0 = 1e300LF, iu1 = -1e300LF, iv0 = 1e300LF, iv1 = -1e300LF;
  for (int m = 0; m < 3; ++m)
  {
    double bx = Bv[m].x, by = Bv[m].y, bd = Bv[m].z;
    precise double den = gSd - bd;
    beyondPixel += !(den > 0.0) ? 1 : 0;
    behindLight += (!gDirLight && !(bd > 0.0)) ? 1 : 0;
    valid += (den > 0.0 && (gDirLight || bd > 0.0)) ? 1 : 0;
    double fx = gDirLight ? 1.0LF : gSd, gx = gDirLight ? 0.0LF : gSx;
    precise double ux = (gx - uXlo) * den + (bx - gSx) * fx;
    precise double vx = (gx - uXhi) * den + (bx - gSx) * fx;
    precise double uy = ((gDirLight ? 0.0LF : gSy) - uYlo) * den + (by - gSy) * fx;
    precise double vy = ((gDirLight ? 0.0LF : gSy) - uYhi) * den + (by - gSy) * fx;
    out0 += ux < 0.0 ? 1 : 0;
    out1 += vx > 0.0 ? 1 : 0;
    out2 += uy < 0.0 ? 1 : 0;
    out3 += vy > 0.0 ? 1 : 0;
    precise double ex = 1e-9 * abs((bx - gSx) * fx), ey = 1e-9 * abs((by - gSy) * fx);
    if (den > 0.0)
    {
      precise double pu = (gx + (bx - gSx) * fx / den) * (double(uK) / uW) + (0.5LF * double(uK) - 0.5LF);
      precise double pv = ((gDirLight ? 0.0LF : gSy) + (by - gSy) * fx / den) * (double(uK) / uH) +
        (0.5LF * double(uK) - 0.5LF);
      iu0 = min(iu0, pu);
      iu1 = max(iu1, pu);
      iv0 = min(iv0, pv);
      iv1 = max(iv1, pv);
    }
    // below the pixel's tangent plane (its samples start hidden)
    precise dvec3 rel = Sub(Bv[m], gS);
    belowPlane += Dot(rel, gHN) < -1e-9 * sqrt(Dot(rel, rel)) * gHlen ? 1 : 0;
    t0 += ux < -(ex + 1e-9 * abs((gx - uXlo) * den)) ? 1 : 0;
    t1 += vx > ex + 1e-9 * abs((gx - uXhi) * den) ? 1 : 0;
    t2 += uy < -(ey + 1e-9 * abs(((gDirLight ? 0.0LF : gSy) - uYlo) * den)) ? 1 : 0;
    t3 += vy > ey + 1e-9 * abs(((gDirLight ? 0.0LF : gSy) - uYhi) * den) ? 1 : 0;
  }
  double tu = 1e-9 * (max(abs(iu0), abs(iu1)) + double(uK)) + 1e-6;
  double tv = 1e-9 * (max(abs(iv0), abs(iv1)) + double(uK)) + 1e-6;
  bool gap = valid == 3 && (ceil(iu0 - tu) > floor(iu1 + tu) || ceil(iv0 - tv) > floor(iv1 + tv));
  if (beyondPixel == 3 || behindLight == 3 || (valid == 3 && (out0 == 3 || out1 == 3 || out2 == 3 || out3 == 3)) ||
    (!gDirLight && (t0 == 3 || t1 == 3 || t2 == 3 || t3 == 3)) || gap || (gHlen > 0.0 && belowPlane == 3))
  {
    return false;
  }
  // The triangle's box of samples (the gap test's, wider margins) where its
  // projection is finite: the samples it may hide. The raster takes only
  // its rows, and a triangle whose box holds only hidden samples is not
  // drawn (the covered skip of the CPU's DrawPixel; not while counting
  // Table 9, which draws every pair).
  // (each bound tested apart: min and max are undefined for NaN; the
  // margins are the CPU's DrawPixel's, wider than the gap test's)
  int r0 = 0, r1 = uK - 1;
  gInfo = near ? 1u : 0u;
  if (valid == 3 && uW > 0.0 && uH > 0.0 && abs(iu0) < 1e9LF && abs(iu1) < 1e9LF && abs(iv0) < 1e9LF &&
    abs(iv1) < 1e9LF)
  {
    double bu = 1e-4 * (abs(iu0) + abs(iu1) + double(uK)) + 1e-3;
    double bv = 1e-4 * (abs(iv0) + abs(iv1) + double(uK)) + 1e-3;
    int c0 = int(max(0.0LF, ceil(iu0 - bu))), c1 = int(min(double(uK - 1), floor(iu1 + bu)));
    r0 = int(max(0.0LF, ceil(iv0 - bv)));
    r1 = int(min(double(uK - 1), floor(iv1 + bv)));
    if (r0 > r1)
    {
      // no row of samples: nothing to draw, near S or not (all three
      // vertices lie between S and the light, so every bit it could set is
      // inside the box; the CPU's rejection kernel drops it too)
      gInfo = 1u << 22;
    }
    else if (c0 <= c1 && uCountNecessary == 0)
    {
      uint cm = RowBits(c0, c1);
      bool covered = true;
      COV16(0)
      COV16(16)
      if (covered)
      {
        return false;
      }
      gInfo |= 2u | (uint(c0) << 12) | (uint(c1) << 17);
    }
  }
  gInfo |= (gInfo & (1u << 22)) != 0u ? 0u : (uint(r0) << 2) | (uint(r1) << 7);
  return true; // it may set bits: drawn in the third phase
}

// The third phase: a triangle Visit kept, with what it found (gInfo: bit 0
// near S, bit 1 a box of samples, bit 22 no sample row; rows r0..r1 in bits
// 2-6 and 7-11, columns c0..c1 in 12-16 and 17-21, all within 0..k-1). Skipped when its box
// holds only hidden samples by now (the covered skip of the CPU's DrawPixel:
// the rows have gained bits since Visit looked), else drawn exactly.
void DrawSurvivor(uint tri, uint info)
{
  if ((info & (1u << 22)) != 0u)
  {
    return;
  }
  int r0 = int((info >> 2) & 31u), r1 = int((info >> 7) & 31u);
  if ((info & 2u) != 0u)
  {
    uint cm = RowBits(int((info >> 12) & 31u), int((info >> 17) & 31u));
    bool covered = true;
    COV16(0)
    COV16(16)
    if (covered)
    {
      return;
    }
  }
  dvec3 Bv[3];
  for (int m = 0; m < 3; ++m)
  {
    Bv[m] = uPre != 0 ? dvec3(triL[9 * tri + 3 * m], triL[9 * tri + 3 * m + 1], triL[9 * tri + 3 * m + 2])
                      : ToLight(dvec3(triV[9 * tri + 3 * m], triV[9 * tri + 3 * m + 1], triV[9 * tri + 3 * m + 2]));
  }
  // opaque casters only (translucent scenes run on the CPU backend)
  bool toTmp = uCountNecessary != 0;
  if (toTmp)
  {
    for (int j = 0; j < 32; ++j)
    {
      tmpRows[j] = 0u;
    }
  }
  bool hit = (info & 1u) != 0u ? RasterizeNearTriangle(gS, Bv[0], Bv[1], Bv[2], toTmp)
                               : RasterizeTriangle(gS, Bv[0], Bv[1], Bv[2], toTmp, r0, r1);
  if (hit && toTmp)
  {
    // gNecessary: it hides a sample above the horizon
    bool above = false;
    for (int j = 0; j < uK; ++j)
    {
      above = above || (tmpRows[j] & ~belowRows[j]) != 0u;
      OrRow(j, tmpRows[j]);
    }
    gNecessary += above ? 1u : 0u;
  }
}

// Pixel i's start in the light's frame, and the sample space and state seen
// from it (K_RASTER, K_WINDING)
dvec3 PixelFrame(uint i)
{
  dvec3 S = ToLight(Start(i));
  gD0 = uDir != 0 ? dvec3(0.0, 0.0, -1.0) : -S;
  gDu = dvec3(uW, 0.0, 0.0);
  gDv = dvec3(0.0, uH, 0.0);
  gDirLight = uDir != 0;
  gS = S;
  gSx = S.x;
  gSy = S.y;
  gSd = S.z;
  return S;
}
#endif

#ifdef K_RASTER
// Chunk uChunk of the pixel's cell list (uChunkSize triangles): the rows
// persist in masks[] between chunks and K_FINISH turns them into V. With the
// winding count (K_WINDING, glsl/ssGearsCSWinding.glsl), masks[] starts with
// its rows where it solved the pixel, and there only the rest of the list
// is drawn.
uniform uint uChunk, uChunkSize;
// Cell c's list: the sort keys c uCellKeys .. (c + 1) uCellKeys - 1 (K_PASS2),
// uBuckets depth buckets per class. With the winding count (uCellKeys =
// 4 uBuckets) the classes of K_WFLAG: the members with contour edges, the
// rest, the other members, and those never drawn in the cell (skipped).
uniform uint uBuckets, uCellKeys;
#ifdef WINDING
uniform int uWinding; // K_WINDING's rows and wind[] are there
#endif
void main()
{
  uint gi = GID();
  if (gi >= uN)
  {
    return;
  }
  uint i = pixOrder[gi]; // (the face's pixels, cell by cell: K_PIXSORT)
  uint c = pixCell[i];
  uint k0 = c * uCellKeys;
  uint first = cellBegin[k0], last = cellBegin[k0 + min(uCellKeys, 3u * uBuckets)];
#ifdef WINDING
  if (uWinding != 0 && wind[i] != 0u)
  {
    // the count solved the members: the rest alone
    first = cellBegin[k0 + uBuckets];
    last = cellBegin[k0 + 2u * uBuckets];
  }
#endif
  uint a0 = first + uChunk * uChunkSize;
  uint end = min(last, a0 + uChunkSize);
  if (uChunk > 0u && a0 >= end)
  {
    return; // this cell's list ended in an earlier chunk
  }
  if (uChunk > 0u && uCountNecessary == 0)
  {
    // an umbra pixel stays one: no set-up for it
    int full = 0;
    for (int j = 0; j < uK; ++j)
    {
      full += masks[32u * i + uint(j)] == uFullRow ? 1 : 0;
    }
    if (full == uK)
    {
      return;
    }
  }
  dvec3 S = PixelFrame(i);
  // light samples below the tangent plane are not seen (reference rule)
  for (int j = 0; j < 32; ++j)
  {
    belowRows[j] = 0u;
  }
  dvec3 Nw = dvec3(smp[7 * i + 3], smp[7 * i + 4], smp[7 * i + 5]);
  gEps = smp[7 * i + 6];
  dvec3 hN = dvec3(0.0); // the tangent plane's normal in the light's frame (0: none)
  if (Nw != dvec3(0.0))
  {
    dvec3 N = dvec3(Dot(Nw, uU), Dot(Nw, uV), Dot(Nw, uNrm));
    hN = N;
    Affine below = MakeAffine(-N, 0.0LF);
    // (only the first chunk starts its rows from them, and Table 9's count
    // reads them)
    for (int j = 0; j < ((uChunk == 0u || uCountNecessary != 0) ? uK : 0); ++j)
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
        belowRows[j] |= RowBits(il, ih);
      }
    }
  }
  for (int j = 0; j < 32; ++j)
  {
    // (before the first chunk masks[] holds the winding count's rows or 0)
    rows[j] = uChunk == 0u ? (belowRows[j] | masks[32u * i + uint(j)]) : masks[32u * i + uint(j)];
  }

  gFull = 0;
  for (int j = 0; j < uK; ++j)
  {
    gFull += rows[j] == uFullRow ? 1 : 0;
  }
  gNecessary = 0u;
  gHN = hN;
  gHlen = sqrt(Dot(hN, hN)); // (0: no horizon test)
  double hlen = gHlen;
  fS = SafeFloat(S);
  fN = vec3(hN); // (a unit vector)
  fNl1 = hlen > 0.0 ? abs(fN.x) + abs(fN.y) + abs(fN.z) : 0.0;
  fXlo = SafeFloat(uXlo); // (NaN beyond the float range: no side test then)
  fXhi = SafeFloat(uXhi);
  fYlo = SafeFloat(uYlo);
  fYhi = SafeFloat(uYhi);
  fXm = max(abs(fXlo), abs(fXhi));
  fYm = max(abs(fYlo), abs(fYhi));
  // The chunk in parts of 128: first every triangle's float pre-test, then
  // the double rejections of those it keeps, then the survivors drawn in
  // list order (each phase compacted). llvmpipe runs neighbouring pixels in
  // lockstep: drawn in one pass with the rejections, a step cost the raster
  // whenever any lane drew; compacted, the lanes draw their survivors side by
  // side. Same triangles in the same order: the same bits.
  for (uint p0 = a0; p0 < end; p0 += 128u)
  {
    if (gFull == uK && uCountNecessary == 0)
    {
      break; // umbra: no further triangle changes V
    }
    uint p1 = min(end, p0 + 128u);
    uint kept[4] = uint[4](0u, 0u, 0u, 0u), need[4] = uint[4](0u, 0u, 0u, 0u);
    uint info[128];
    for (uint a = p0; a < p1; ++a)
    {
      if (FloatKeeps(sorted[a]))
      {
        kept[(a - p0) >> 5] |= 1u << ((a - p0) & 31u);
      }
    }
    for (uint w = 0u; w < 4u; ++w)
    {
      uint bits = kept[w];
      while (bits != 0u)
      {
        int b = findLSB(bits);
        bits &= bits - 1u;
        if (Visit(sorted[p0 + 32u * w + uint(b)]))
        {
          need[w] |= 1u << uint(b);
          info[32u * w + uint(b)] = gInfo;
        }
      }
    }
    for (uint w = 0u; w < 4u; ++w)
    {
      uint bits = need[w];
      while (bits != 0u && !(gFull == uK && uCountNecessary == 0))
      {
        int b = findLSB(bits);
        bits &= bits - 1u;
        DrawSurvivor(sorted[p0 + 32u * w + uint(b)], info[32u * w + uint(b)]);
      }
    }
  }
  for (int j = 0; j < uK; ++j)
  {
    masks[32u * i + uint(j)] = rows[j];
  }
  if (uCountNecessary != 0)
  {
    nec[i] += gNecessary;
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
