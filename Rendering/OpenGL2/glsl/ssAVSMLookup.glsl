// Reading an AVSM (ssAVSMMaps) and VPCSS's filter on it (pasted where a
// shader says //SS::AVSMLookup, after //SS::Common, whose views, receiver
// plane and light footprint it uses). The formulas are Rendering/Core's
// (ssAVSM.cxx Evaluate/EvaluateFront, ssVPCSS.cxx), unit-tested there.
// The including shader defines vec4 avsmFetch(ivec3 texelAndLayer, int level)
// (the AVSM array's texel).
uniform float slopeBias;
uniform int avsmNodes;        // N: a multiple of 4, at most 16
uniform int avsmColored;      // 1: three transmittance channels
uniform int avsmLevels;       // levels of the mean-function pyramid (1: none)
uniform int avsmFirstLayer;   // the light's first layer
uniform int avsmLayersPerView;
uniform int avsmFilterQuads;  // VPCSS: texel quads per axis of the filter, at most

// Which lookups the including shader holds, fixed when it is built (it may
// define them first). llvmpipe runs both sides of every branch and the first
// pass of every loop, even for a group of fragments none of which takes it:
// code for a lookup no light uses costs as much as the one in use (measured
// in Documentation/vpcss.md, "Only the code a light uses").
// AVSM_HARD: hard AVSM; AVSM_FILTERED: VPCSS's filter; with both, the
// caller's `hard` picks. AVSM_REFINE 1: a pyramid quad whose function
// changes across it reads its four children (G-buffer pixels), and the
// blocker search exits early by blocks of cells; 0: its mean function
// alone, a mip-mapped lookup (translucent receivers,
// ssTranslucentReceivers: each of their fragments runs the filter, once,
// in the fragment lists' filter pass or in its shading), and the search
// reads its cells without the block test (whose 4 x 4 reads cost more than
// they save, as every loop runs at least once on llvmpipe: 614 against 641
// ms of shading on particles.json when every depth peel ran the filter;
// 278-285 against 271-277 ms in the filter pass; the same V). AVSM_COLORED 0: no light
// of the shader has three channels (avsmColored is 0), so the code of the
// other two is left out. AVSM_NODES > 0: every light of the shader has that
// N (avsmNodes), so the loops over its blocks unroll; 0: N is read.
#ifndef AVSM_HARD
#define AVSM_HARD 1
#endif
#ifndef AVSM_FILTERED
#define AVSM_FILTERED 1
#endif
#ifndef AVSM_REFINE
#define AVSM_REFINE 1
#endif
#ifndef AVSM_COLORED
#define AVSM_COLORED 1
#endif
#ifndef AVSM_NODES
#define AVSM_NODES 0
#endif
#if AVSM_NODES > 0
#define avsmBlocks (AVSM_NODES / 4)
#else
#define avsmBlocks (avsmNodes / 4)
#endif
#if AVSM_COLORED
#define avsmIsColored (avsmColored != 0)
#else
#define avsmIsColored false
#endif

// Texel q of a level of `mapSize` >> level texels a side lies in the map
// (outside: no node, T = 1).
bool avsmInMap(ivec2 q, int level)
{
  int size = max(1, int(mapSize) >> level);
  return q.x >= 0 && q.y >= 0 && q.x < size && q.y < size;
}

// Block b of texel q's nodes: 4 depths (unused: 3e38) and their
// transmittance per channel (t1 = t2 = t0 with one channel). `L`: the
// view's first layer; nb: blocks per texel.
void avsmBlock(int L, int nb, ivec2 q, int level, int b, out vec4 d, out vec4 t0, out vec4 t1, out vec4 t2)
{
  d = avsmFetch(ivec3(q, L + b), level);
  t0 = avsmFetch(ivec3(q, L + nb + b), level);
  t1 = avsmIsColored ? avsmFetch(ivec3(q, L + 2 * nb + b), level) : t0;
  t2 = avsmIsColored ? avsmFetch(ivec3(q, L + 3 * nb + b), level) : t0;
}

// T(z) of texel q of `view` at `level`, at two depths z.x and z.y, read
// block by block into registers. The segment from node k to node k + 1
// holds z where d_k <= z < d_{k+1}: k is the last node at or in front of z
// (ss::AVSMFunction::Evaluate), interpolated as there; in front of the first
// node T = 1. The unused nodes (depth 3e38, the last node's T: storeNodes in
// ssAVSMBuildCS.glsl) make the last node's segment constant, and a texel
// with no node, or outside the map, gives 1. No local array: llvmpipe reads
// an array at an index that differs between the fragments of a group lane
// by lane, and the nodes' compaction and search did that for every texel
// of the filter.
void avsmSegments(vec4 D, vec4 Dn, vec4 T0, vec4 Tn0, vec4 T1, vec4 Tn1, vec4 T2, vec4 Tn2, float z,
  inout vec3 r)
{
  vec4 zz = vec4(z);
  vec4 hit = step(D, zz) * (vec4(1.0) - step(Dn, zz)); // D <= z < Dn
  vec4 s = (zz - D) / (Dn - D);
  vec4 v0 = T0 + (Tn0 - T0) * s;
  vec4 v1 = T1 + (Tn1 - T1) * s;
  vec4 v2 = T2 + (Tn2 - T2) * s;
  r = (hit.x > 0.5) ? vec3(v0.x, v1.x, v2.x) : r;
  r = (hit.y > 0.5) ? vec3(v0.y, v1.y, v2.y) : r;
  r = (hit.z > 0.5) ? vec3(v0.z, v1.z, v2.z) : r;
  r = (hit.w > 0.5) ? vec3(v0.w, v1.w, v2.w) : r;
}

vec3 avsmTexel2(int view, ivec2 q, int level, vec2 z, out vec3 second)
{
  vec3 r0 = vec3(1.0), r1 = vec3(1.0);
  second = r1;
  if (!avsmInMap(q, level))
  {
    return r0;
  }
  int nb = avsmBlocks;
  int L = avsmFirstLayer + view * avsmLayersPerView;
  vec4 d, t0, t1, t2;
  avsmBlock(L, nb, q, level, 0, d, t0, t1, t2);
  for (int b = 0; b < nb; ++b)
  {
    // the next block's first node closes this block's last segment
    vec4 dn = vec4(3.0e38), n0 = t0.wwww, n1 = t1.wwww, n2 = t2.wwww;
    if (b + 1 < nb)
    {
      avsmBlock(L, nb, q, level, b + 1, dn, n0, n1, n2);
    }
    vec4 D1 = vec4(d.yzw, dn.x);
    vec4 T0n = vec4(t0.yzw, n0.x), T1n = vec4(t1.yzw, n1.x), T2n = vec4(t2.yzw, n2.x);
    avsmSegments(d, D1, t0, T0n, t1, T1n, t2, T2n, z.x, r0);
    avsmSegments(d, D1, t0, T0n, t1, T1n, t2, T2n, z.y, r1);
    d = dn;
    t0 = n0;
    t1 = n1;
    t2 = n2;
  }
  second = r1;
  return r0;
}

vec3 avsmTexel(int view, ivec2 q, int level, float z)
{
  vec3 unused;
  return avsmTexel2(view, q, level, vec2(z), unused);
}

// VPCSS eq. 6 (sign corrected: ss::ReplacementBlockerFraction), for four
// opacities at once
vec4 avsmReplacementFraction(vec4 a)
{
  vec4 f = log(vec4(1.0) - 0.5 * a) / log(vec4(1.0) - a);
  f = mix(f, vec4(0.5) - a / 8.0, lessThan(a, vec4(1e-3)));
  f = mix(f, vec4(0.0), greaterThanEqual(a, vec4(1.0)));
  return mix(f, vec4(0.5), not(greaterThan(a, vec4(0.0))));
}

// One channel of one block of nodes i (depths D, transmittance T) with the
// nodes before them (Dp, Tp): node i's drop from Tp to T (at zR: the function
// just in front of zR, on the segment from node i - 1, where node i lies at
// or behind it) with its replacement blocker depth; 0 where the node is
// not in front of zR (`live` 0).
void avsmBlockerChannel(vec4 live, vec4 inside, vec4 s, vec4 Dp, vec4 zE, vec4 Tp, vec4 T, out vec4 delta,
  out vec4 zRB)
{
  vec4 after = mix(T, Tp + (T - Tp) * s, greaterThan(inside, vec4(0.5)));
  delta = Tp - after;
  vec4 ok = live * (vec4(1.0) - step(Tp, vec4(0.0))) * (vec4(1.0) - step(delta, vec4(0.0))); // Tp > 0, delta > 0
  zRB = Dp + (zE - Dp) * avsmReplacementFraction(vec4(1.0) - after / Tp);
  delta = mix(vec4(0.0), delta, greaterThan(ok, vec4(0.5)));
  zRB = mix(vec4(0.0), zRB, greaterThan(ok, vec4(0.5)));
}

// VPCSS eqs. 7-8 (ss::TransmittanceFunctionBlocker) on texel q of `view` at
// `level`: (sum Delta z_RB, sum Delta) of the blockers in front of zR,
// channels summed, in the order of ss::TransmittanceFunctionBlocker (node by
// node, channel by channel). Node i's segment runs from node i - 1 (the first
// node: from itself, a drop) to node i, clipped at zR; the nodes are sorted,
// so those whose segment starts at or behind zR, and the unused ones (3e38),
// add nothing. Block by block in registers, as avsmTexel2.
vec2 avsmBlockerTexel(int view, ivec2 q, int level, float zR)
{
  vec2 acc = vec2(0.0);
  if (!avsmInMap(q, level))
  {
    return acc;
  }
  int nb = avsmBlocks;
  int L = avsmFirstLayer + view * avsmLayersPerView;
  bool colored = avsmIsColored;
  vec4 zz = vec4(zR);
  float lastD = 0.0;
  vec3 lastT = vec3(1.0);
  for (int b = 0; b < nb; ++b)
  {
    vec4 D, t0, t1, t2;
    avsmBlock(L, nb, q, level, b, D, t0, t1, t2);
    lastD = (b == 0) ? D.x : lastD;
    vec4 Dp = vec4(lastD, D.xyz);
    // Dp < zR and a used node
    vec4 live = (vec4(1.0) - step(zz, Dp)) * (vec4(1.0) - step(vec4(1.0e38), D));
    vec4 inside = step(zz, D); // node i at or behind zR: clip its segment there
    vec4 s = (zz - Dp) / (D - Dp);
    vec4 zE = mix(D, zz, greaterThan(inside, vec4(0.5)));
    vec4 d0, z0, d1 = vec4(0.0), z1 = vec4(0.0), d2 = vec4(0.0), z2 = vec4(0.0);
    avsmBlockerChannel(live, inside, s, Dp, zE, vec4(lastT.x, t0.xyz), t0, d0, z0);
    if (colored)
    {
      avsmBlockerChannel(live, inside, s, Dp, zE, vec4(lastT.y, t1.xyz), t1, d1, z1);
      avsmBlockerChannel(live, inside, s, Dp, zE, vec4(lastT.z, t2.xyz), t2, d2, z2);
    }
    for (int j = 0; j < 4; ++j)
    {
      acc += vec2(d0[j] * z0[j], d0[j]);
      if (colored)
      {
        acc += vec2(d1[j] * z1[j], d1[j]);
        acc += vec2(d2[j] * z2[j], d2[j]);
      }
    }
    lastD = D.w;
    lastT = vec3(t0.w, t1.w, t2.w);
  }
  return acc;
}

// The nearest node depth of texel q of `view` at `level` (3e38: no node,
// or outside the map): the first depth of its first layer, one fetch (the
// nodes are stored sorted, unused ones last; storeNodes in ssAVSMBuildCS).
float avsmFirstDepth(int view, ivec2 q, int level)
{
  if (!avsmInMap(q, level))
  {
    return 3.0e38;
  }
  return avsmFetch(ivec3(q, avsmFirstLayer + view * avsmLayersPerView), level).x;
}

// An upper bound of the receiver plane's depth (planeDepth) over the quad
// [a, a + s]^2 (texel units). Along the projection rays the plane's depth
// is dot(n, p) / dot(n, (X, 1)), monotonic along any segment on which the
// denominator keeps its sign, so the corners bound it; where the sign may
// change inside, only planeDepth's clamp bounds it.
float planeUpper(View w, vec2 a, float s, float maxDelta)
{
  if (orthographic == 0)
  {
    vec2 X0 = texelToProjected(w, a), X1 = texelToProjected(w, a + vec2(s));
    vec4 den = vec4(dot(w.n, vec3(X0, 1.0)), dot(w.n, vec3(X1.x, X0.y, 1.0)), dot(w.n, vec3(X0.x, X1.y, 1.0)),
      dot(w.n, vec3(X1, 1.0)));
    if (!(all(greaterThan(den, vec4(1e-12))) || all(lessThan(den, vec4(-1e-12)))))
    {
      return w.p.z + maxDelta;
    }
  }
  return planeRange(w, a, s, maxDelta).y;
}

// VPCSS §4, eq. 13: the blocker depth over the search window (the light's
// footprint on the plane of the nearest caster, as PCSS's blocker search),
// read from the pyramid level whose cells are about 2 * search / samples
// texels wide so that no blocker between samples is missed; each cell
// weighted by its overlap with the window and by its Delta (1 - T at the
// receiver's nearest depth over the cell). -1: nothing in the window has
// transmittance < 1 in front of the receiver (the paper's early exit, §4).
//
// That exit is taken for blocks of cells first: the pyramid level two above
// the search's holds in its first node depth the nearest node of every
// texel under it (the mean function's first breakpoint is its children's
// nearest, and least-area removal never removes the first node: K_PYRAMID
// in ssAVSMBuildCS.glsl), so a block whose first depth lies behind the
// receiver plane's farthest depth over the window holds no blocker in front
// of any of its cells (their Delta is 0). Only the search cells under the
// other blocks are read, in the same order: the sums, and so V, are the
// same as over every cell; with no such block, V = 1 after at most 4 x 4
// fetches instead of up to 9 x 9 functions.
float avsmBlockerSearch(View w, float bias)
{
  vec2 searchHalf = lightFilterHalf(w.p.z, min(searchDepth, w.p.z));
  vec2 searchTex = min(searchHalf * w.texelPerUnit, vec2(mapSize * 0.25));
  searchTex = max(searchTex, vec2(1.0));
  float maxDelta = max(searchTex.x, searchTex.y) * w.texelWorld * 10.0;
  float cellsWide = 2.0 * max(searchTex.x, searchTex.y) / float(searchSamples);
  int level = clamp(int(ceil(log2(max(cellsWide, 1.0)))), 0, avsmLevels - 1);
  float cell = exp2(float(level));
  vec2 s0 = w.T - searchTex;
  vec2 s1 = w.T + searchTex;
  ivec2 c0 = ivec2(floor(s0 / cell));
  ivec2 c1 = ivec2(floor(s1 / cell));
  int up = min(level + 2, avsmLevels - 1) - level;
#if !AVSM_REFINE
  up = 0; // the coarse filter: fewer search cells than the exit's 4 x 4 reads (measured)
#endif
  if (up > 0)
  {
    // the deepest a search cell's receiver depth (zr - bias * cell below)
    // can be: over a square holding every search cell, with a margin for
    // the rounding of the corners' depths
    float side = float(max(c1.x - c0.x, c1.y - c0.y) + 1) * cell;
    float zMax = planeUpper(w, vec2(c0) * cell, side, maxDelta);
    zMax += 1e-4 * abs(zMax) - bias * cell;
    ivec2 b0 = c0 >> up, b1 = c1 >> up;
    ivec2 lo = c1 + 1, hi = c0 - 1; // the search cells under blocks that may block
    for (int by = b0.y; by <= b1.y; ++by)
    {
      for (int bx = b0.x; bx <= b1.x; ++bx)
      {
        if (avsmFirstDepth(w.index, ivec2(bx, by), level + up) < zMax)
        {
          lo = min(lo, ivec2(bx, by) << up);
          hi = max(hi, ((ivec2(bx, by) + 1) << up) - 1);
        }
      }
    }
    c0 = max(c0, lo);
    c1 = min(c1, hi);
  }
  float sum = 0.0, weight = 0.0;
  for (int cy = c0.y; cy <= c1.y; ++cy)
  {
    float oy = max(0.0, min((float(cy) + 1.0) * cell, s1.y) - max(float(cy) * cell, s0.y));
    for (int cx = c0.x; cx <= c1.x; ++cx)
    {
      float ox = max(0.0, min((float(cx) + 1.0) * cell, s1.x) - max(float(cx) * cell, s0.x));
      if (ox * oy <= 0.0)
      {
        continue;
      }
      float zr = planeRange(w, vec2(cx, cy) * cell, cell, maxDelta).x;
      vec2 b = avsmBlockerTexel(w.index, ivec2(cx, cy), level, zr - bias * cell);
      sum += ox * oy * b.x;
      weight += ox * oy * b.y;
    }
  }
  return (weight > 0.0) ? sum / weight : -1.0;
}

// Mean transmittance of quad q of 2^level texels at the receiver: the
// pyramid's mean function at the receiver plane's depth over the quad's
// centre; where that function changes between the plane's nearest and
// farthest depth over the quad, the four children at theirs (as the
// coverage filter of PCSS refines undecided quads, ssQuadLit.glsl).
vec3 avsmQuad(View w, int level, ivec2 q, float bias, float maxDelta)
{
  float s = exp2(float(level));
  if (level == 0)
  {
    float z = planeDepth(w, texelToProjected(w, vec2(q) + 0.5), maxDelta) - bias;
    return avsmTexel(w.index, q, 0, z);
  }
  vec2 zr = planeRange(w, vec2(q) * s, s, maxDelta) - bias * s;
  vec3 far;
  vec3 near = avsmTexel2(w.index, q, level, zr, far);
#if AVSM_REFINE
  bool refine = !all(lessThan(abs(near - far), vec3(1e-3)));
  // the children's loop runs 0 times unless refining: llvmpipe runs a
  // branch's body for every fragment of a group whatever the condition,
  // but a loop only as often as its longest-running fragment needs
  int children = refine ? 4 : 0;
  float h = 0.5 * s;
  vec3 sum = vec3(0.0);
  for (int c = 0; c < children; ++c)
  {
    ivec2 child = 2 * q + ivec2(c & 1, c >> 1);
    float z = planeDepth(w, texelToProjected(w, vec2(child) * h + 0.5 * h), maxDelta) - bias * h;
    sum += avsmTexel(w.index, child, level - 1, z);
  }
  return refine ? 0.25 * sum : 0.5 * (near + far);
#else
  return 0.5 * (near + far);
#endif
}

// The filtered transmittance over the kernel box [k0, k1] (texel units):
// each quad of the chosen level contributes its overlap with the box times
// its mean transmittance (PVSM §4.1 eq. 2's texel-as-quad integral, which
// PCSS uses, with transmittance for the lit fraction): no sample lattice,
// no banding.
vec3 avsmCoverage(View w, vec2 k0, vec2 k1, float bias, float maxDelta)
{
  float area = (k1.x - k0.x) * (k1.y - k0.y);
  if (area <= 0.0)
  {
    return avsmQuad(w, 0, ivec2(floor(0.5 * (k0 + k1))), bias, maxDelta);
  }
  float extent = max(k1.x - k0.x, k1.y - k0.y);
  int level = 0;
  while (extent / exp2(float(level)) > float(avsmFilterQuads) && level < avsmLevels - 1)
  {
    ++level;
  }
  float s = exp2(float(level));
  ivec2 q0 = ivec2(floor(k0 / s));
  ivec2 q1 = ivec2(floor(k1 / s));
  vec3 sum = vec3(0.0);
  for (int qy = q0.y; qy <= q1.y; ++qy)
  {
    float oy = max(0.0, min(float(qy) * s + s, k1.y) - max(float(qy) * s, k0.y));
    if (oy <= 0.0)
    {
      continue;
    }
    for (int qx = q0.x; qx <= q1.x; ++qx)
    {
      float ox = max(0.0, min(float(qx) * s + s, k1.x) - max(float(qx) * s, k0.x));
      if (ox <= 0.0)
      {
        continue;
      }
      sum += ox * oy * avsmQuad(w, level, ivec2(qx, qy), bias, maxDelta);
    }
  }
  return clamp(sum / area, 0.0, 1.0);
}

// Hard AVSM's transmittance of the light at receiver point d (from the
// light's centre) with normal nrm: one texel, at the receiver's depth less
// the slope-scaled bias; RGB.
vec3 avsmHardVisibility(View w, vec3 nrm, vec3 d)
{
  vec3 toLight = (orthographic != 0) ? -viewN[w.index] : normalize(-d);
  float cosTheta = dot(normalize(nrm), toLight);
  float tanTheta = (cosTheta > 1e-4) ? min(sqrt(max(0.0, 1.0 - cosTheta * cosTheta)) / cosTheta, 10.0) : 10.0;
  if (dot(nrm, nrm) < 0.5)
  {
    tanTheta = 0.0; // no normal: no slope
  }
  float slopeScaled = w.texelWorld * (constantBias + slopeBias * tanTheta);
  return avsmTexel(w.index, ivec2(floor(w.T)), 0, w.p.z - slopeScaled);
}

// VPCSS's transmittance of the light at receiver view w: blocker search,
// eq. 14 penumbra, filtered transmittance; RGB.
vec3 avsmFilteredVisibility(View w)
{
  float bias = w.texelWorld * constantBias;
  float zAvg = avsmBlockerSearch(w, bias);
  if (zAvg < 0.0)
  {
    return vec3(1.0); // early exit: no texel of the window blocks anything
  }
  // eq. 14, penumbra by parallel planes: (z_R - z_avg) / z_avg * w_L on the
  // receiver, i.e. the light's half size times (z_R - z_avg) / (z_R z_avg)
  // on the unit plane (PVSM §4 eq. 1, as PCSS)
  vec2 kTex = max(lightFilterHalf(w.p.z, zAvg) * w.texelPerUnit, vec2(0.5));
  float md = max(kTex.x, kTex.y) * w.texelWorld * 10.0;
  return avsmCoverage(w, w.T - kTex, w.T + kTex, bias, md);
}

// Transmittance of the light at receiver point d (from the light's centre)
// with normal nrm: hard AVSM (`hard` != 0) or VPCSS, among the lookups the
// shader holds (AVSM_HARD, AVSM_FILTERED); RGB. The views are the caller's.
vec3 avsmVisibility(View w, vec3 nrm, vec3 d, int hard)
{
#if AVSM_HARD && AVSM_FILTERED
  return (hard != 0) ? avsmHardVisibility(w, nrm, d) : avsmFilteredVisibility(w);
#elif AVSM_HARD
  return avsmHardVisibility(w, nrm, d);
#else
  return avsmFilteredVisibility(w);
#endif
}

// The fraction of the light above the receiver's surface (the terminator,
// ssShadowCommon; ns the shading normal, ng the facet's): hard AVSM's light
// is its centre, VPCSS's all of it. As avsmVisibility, only the code the
// shader's lookups need.
float avsmAboveSurface(vec3 ns, vec3 ng, vec3 d, int hard)
{
#if AVSM_HARD && AVSM_FILTERED
  return (hard != 0) ? centreAboveSurface(ns, ng, d) : lightAboveSurface(ns, ng, d);
#elif AVSM_HARD
  return centreAboveSurface(ns, ng, d);
#else
  return lightAboveSurface(ns, ng, d);
#endif
}
