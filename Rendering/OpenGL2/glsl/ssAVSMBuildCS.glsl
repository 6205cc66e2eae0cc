// The compute kernels that turn the per-texel fragment lists of an AVSM view
// into its nodes (ssAVSMMaps.cxx runs them; one source, one kernel per K_*
// define; the host prepends "#version 430", the kernel's define, AVSM_N and
// AVSM_C). Without pixel synchronisation (llvmpipe has none) the AVSM is
// built in steps that need no ordering between fragments:
//   ssAVSMCasterFS: count the translucent fragments in front of the nearest
//     opaque one per texel (atomics), then store them (atomic cursor)
//   K_SCAN     per row: each texel's list offset in its row, the row's total
//              and longest list (the host cuts the map into bands of rows
//              whose lists fit the fragment buffer)
//   K_SORT     each list sorted in place by depth (heap sort; lists longer
//              than uSortMax stay in arrival order: Salvi's unsorted insertion)
//   K_RESOLVE  the sorted fragments merged by depth with the volume march
//              along the texel's ray, inserted one by one (ssAVSMNodes.glsl),
//              then the opaque step; at most uBudget insertions per dispatch
//              (llvmpipe ends an invocation after 65535 loop iterations), the
//              nodes and the stream positions kept between dispatches
//   K_PYRAMID  level L from level L-1: the mean of 2x2 functions compressed
//              to AVSM_N nodes (ss::MeanAVSM)
// Node storage: per view, AVSM_N/4 RGBA32F layers of depths (unused nodes
// 3e38) and AVSM_C * AVSM_N/4 layers of transmittance (channel-major).

#ifndef WG
#define WG 64
#endif
layout(local_size_x = WG) in;

#define NB (AVSM_N / 4)
#define DONE 0xFFFFFFFFu

uniform int uS;    // map size (texels a side, level 0)
uniform int uY0;   // band: rows [uY0, uY1)
uniform int uY1;
uniform int uLayer0; // first layer of this view in the AVSM array
uniform uint uCapacity; // entries of the fragment buffer

// The fragments of list `idx` that the buffer holds (a row with more than
// it holds was cut when stored).
uint listLength(uint idx, uint base);

uint GID()
{
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(WG);
}

#if AVSM_C == 3
#define FRAG vec4
#else
#define FRAG vec2
#endif

layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer Local { uint local[]; };
layout(std430, binding = 2) buffer Rows { uint rows[]; };        // total[S], longest[S]
layout(std430, binding = 3) buffer RowStart { uint rowStart[]; }; // per row, within the band
layout(std430, binding = 5) buffer State { uvec2 state[]; };      // (fragment, march step) per texel
layout(std430, binding = 6) buffer Frags { FRAG frags[]; };

//SS::AVSMNodes

uint listLength(uint idx, uint base)
{
  return base >= uCapacity ? 0u : min(counts[idx], uCapacity - base);
}

#ifdef K_SCAN
void main()
{
  uint y = GID();
  if (y >= uint(uS))
  {
    return;
  }
  uint sum = 0u, longest = 0u;
  for (uint x = 0u; x < uint(uS); ++x)
  {
    uint c = counts[y * uint(uS) + x];
    local[y * uint(uS) + x] = sum;
    sum += c;
    longest = max(longest, c);
  }
  rows[y] = sum;
  rows[uint(uS) + y] = longest;
}
#endif

#ifdef K_SORT
uniform int uSortMax;

bool fragLess(FRAG a, FRAG b)
{
  // ss::AVSMFragmentBefore: depth, then transmittance
  for (int i = 0; i < AVSM_C + 1; ++i)
  {
    if (a[i] != b[i])
    {
      return a[i] < b[i];
    }
  }
  return false;
}

void siftDown(uint base, uint start, uint end)
{
  uint root = start;
  for (int guard = 0; guard < 32; ++guard)
  {
    uint child = 2u * root + 1u;
    if (child >= end)
    {
      return;
    }
    if (child + 1u < end && fragLess(frags[base + child], frags[base + child + 1u]))
    {
      ++child;
    }
    if (!fragLess(frags[base + root], frags[base + child]))
    {
      return;
    }
    FRAG t = frags[base + root];
    frags[base + root] = frags[base + child];
    frags[base + child] = t;
    root = child;
  }
}

void main()
{
  uint g = GID();
  uint x = g % uint(uS), y = uint(uY0) + g / uint(uS);
  if (y >= uint(uY1))
  {
    return;
  }
  uint idx = y * uint(uS) + x;
  uint base = rowStart[y] + local[idx];
  uint k = listLength(idx, base);
  if (k < 2u || k > uint(uSortMax))
  {
    return;
  }
  for (uint s = k / 2u; s > 0u; --s)
  {
    siftDown(base, s - 1u, k);
  }
  for (uint end = k - 1u; end > 0u; --end)
  {
    FRAG t = frags[base];
    frags[base] = frags[base + end];
    frags[base + end] = t;
    siftDown(base, 0u, end);
  }
}
#endif

#if defined(K_RESOLVE) || defined(K_PYRAMID)
layout(rgba32f, binding = 0) uniform image2DArray uOut;

// Layer `layer` of texel q in the map the kernel reads nodes from: uOut
// (resolve: its own nodes, kept between dispatches) or uIn (pyramid: level
// L-1). Each kernel defines it.
vec4 nodeLayer(ivec2 q, int layer);

// The nodes of texel q (the layout storeNodes writes): the depths below 3e38
// with their transmittance, into d and t; returns how many. The one reader
// of that layout for both kernels (the resolve's nodes between dispatches,
// the pyramid's four children).
int loadNodes(ivec2 q, inout float d[AVSM_N + 2], inout vec3 t[AVSM_N + 2])
{
  int n = 0;
  for (int b = 0; b < NB; ++b)
  {
    vec4 dd = nodeLayer(q, uLayer0 + b);
    vec4 t0 = nodeLayer(q, uLayer0 + NB + b);
#if AVSM_C == 3
    vec4 t1 = nodeLayer(q, uLayer0 + 2 * NB + b);
    vec4 t2 = nodeLayer(q, uLayer0 + 3 * NB + b);
#else
    vec4 t1 = t0, t2 = t0;
#endif
    for (int j = 0; j < 4; ++j)
    {
      if (dd[j] < 1.0e38)
      {
        d[n] = dd[j];
        t[n++] = vec3(t0[j], t1[j], t2[j]);
      }
    }
  }
  return n;
}

void storeNodes(ivec2 q)
{
  vec3 last = nn > 0 ? nt[nn - 1] : vec3(1.0);
  for (int b = 0; b < NB; ++b)
  {
    vec4 d, t0, t1, t2;
    for (int j = 0; j < 4; ++j)
    {
      int i = 4 * b + j;
      bool used = i < nn;
      d[j] = used ? nd[i] : 3.0e38;
      vec3 t = used ? nt[i] : last;
      t0[j] = t.x;
      t1[j] = t.y;
      t2[j] = t.z;
    }
    imageStore(uOut, ivec3(q, uLayer0 + b), d);
    imageStore(uOut, ivec3(q, uLayer0 + NB + b), t0);
#if AVSM_C == 3
    imageStore(uOut, ivec3(q, uLayer0 + 2 * NB + b), t1);
    imageStore(uOut, ivec3(q, uLayer0 + 3 * NB + b), t2);
#endif
  }
}
#endif

#ifdef K_RESOLVE
uniform sampler2DArray uOpaqueMap; // nearest opaque depth per texel (3e38: none), one layer per view
uniform int uView;
uniform int uBudget;   // insertions per dispatch
uniform int uFirst;    // 1: the band's first dispatch (empty functions)
// the view (ssCasterVS's light space) and the volumes marched along its rays
uniform vec3 uViewOrigin;
uniform vec3 uAxisU;
uniform vec3 uAxisV;
uniform vec3 uAxisN;
uniform vec4 uExtent;
uniform int uOrtho;
uniform int uVolumes;
uniform mat4 uRelToIndex[4]; // world relative to the frame origin -> grid index
uniform vec3 uDims[4];
uniform sampler3D uVol0;
uniform sampler3D uVol1;
uniform sampler3D uVol2;
uniform sampler3D uVol3;
uniform float uStep;   // march step (world units)
uniform int uMaxSteps;

vec4 nodeLayer(ivec2 q, int layer)
{
  return imageLoad(uOut, ivec3(q, layer));
}

float sigmaOf(int v, vec3 p)
{
  vec3 idx = (uRelToIndex[v] * vec4(p, 1.0)).xyz;
  vec3 hi = uDims[v] - 1.0;
  if (any(lessThan(idx, vec3(0.0))) || any(greaterThan(idx, hi)))
  {
    return 0.0;
  }
  vec3 tc = (idx + 0.5) / uDims[v];
  if (v == 0)
  {
    return texture(uVol0, tc).r;
  }
  if (v == 1)
  {
    return texture(uVol1, tc).r;
  }
  if (v == 2)
  {
    return texture(uVol2, tc).r;
  }
  return texture(uVol3, tc).r;
}

// ss::VolumeGrid::Clip in index space
bool clipVolume(int v, vec3 p, vec3 d, float tMax, out float t0, out float t1)
{
  vec3 o = (uRelToIndex[v] * vec4(p, 1.0)).xyz;
  vec3 w = (uRelToIndex[v] * vec4(d, 0.0)).xyz;
  vec3 hi = uDims[v] - 1.0;
  t0 = 0.0;
  t1 = tMax;
  for (int a = 0; a < 3; ++a)
  {
    if (abs(w[a]) < 1e-30)
    {
      if (o[a] < 0.0 || o[a] > hi[a])
      {
        return false;
      }
      continue;
    }
    float ta = (0.0 - o[a]) / w[a], tb = (hi[a] - o[a]) / w[a];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  return t1 > t0;
}

void main()
{
  uint g = GID();
  uint x = g % uint(uS), y = uint(uY0) + g / uint(uS);
  if (y >= uint(uY1))
  {
    return;
  }
  uint idx = y * uint(uS) + x;
  uvec2 st = (uFirst != 0) ? uvec2(0u) : state[idx];
  if (st.x == DONE)
  {
    return;
  }
  ivec2 q = ivec2(x, y);
  if (uFirst != 0)
  {
    nn = 0;
  }
  else
  {
    nn = loadNodes(q, nd, nt);
  }
  uint base = rowStart[y] + local[idx];
  uint count = listLength(idx, base);
  float od = texelFetch(uOpaqueMap, ivec3(q, uView), 0).r;

  // the texel's ray (ss::MarchVolumes): from the light through the texel's centre
  vec2 X = uExtent.xy + (vec2(q) + 0.5) / float(uS) * (uExtent.zw - uExtent.xy);
  vec3 o = uViewOrigin, dir = uAxisN;
  float depthPerT = 1.0;
  if (uOrtho != 0)
  {
    o = uViewOrigin + X.x * uAxisU + X.y * uAxisV;
  }
  else
  {
    vec3 l = vec3(X, 1.0);
    depthPerT = 1.0 / length(l);
    dir = (X.x * uAxisU + X.y * uAxisV + uAxisN) * depthPerT;
  }
  float a = 3.0e38, b = -3.0e38;
  float tMax = (od < 1.0e38) ? od / depthPerT : 1.0e30;
  for (int v = 0; v < uVolumes; ++v)
  {
    float t0, t1;
    if (clipVolume(v, o, dir, tMax, t0, t1))
    {
      a = min(a, t0);
      b = max(b, t1);
    }
  }
  uint steps = 0u;
  float dt = 0.0;
  if (b > a)
  {
    steps = uint(clamp(int(ceil((b - a) / max(uStep, 1e-30))), 1, uMaxSteps));
    dt = (b - a) / float(steps);
  }

  // one event per iteration: the next fragment, the next march step (in
  // depth order), then the opaque step; one insertion site keeps the
  // kernel small
  for (int budget = uBudget; budget > 0 && st.x != DONE; --budget)
  {
    float entry = (st.y < steps) ? (a + float(st.y) * dt) * depthPerT : 3.0e38;
    float za = 0.0, zb = 0.0;
    vec3 tau = vec3(1.0);
    if (st.x < count && frags[base + st.x].x <= entry)
    {
      FRAG f = frags[base + st.x];
      za = f.x;
      zb = f.x;
#if AVSM_C == 3
      tau = f.yzw;
#else
      tau = vec3(f.y);
#endif
      ++st.x;
    }
    else if (st.y < steps)
    {
      float t0 = a + float(st.y) * dt, t1 = t0 + dt;
      float sigma = 0.0;
      for (int v = 0; v < uVolumes; ++v)
      {
        sigma += sigmaOf(v, o + dir * (0.5 * (t0 + t1)));
      }
      za = t0 * depthPerT;
      zb = t1 * depthPerT;
      tau = vec3(exp(-sigma * dt)); // 1 where the step is empty: nothing inserted
      ++st.y;
    }
    else
    {
      za = od; // the opaque caster: the step to 0 (none: od = 3e38, tau stays 1)
      zb = od;
      tau = vec3(od < 1.0e38 ? 0.0 : 1.0);
      st.x = DONE;
    }
    nodesInsert(za, zb, tau);
  }
  storeNodes(q);
  state[idx] = st;
}
#endif

#ifdef K_PYRAMID
layout(rgba32f, binding = 1) uniform readonly image2DArray uIn; // level L-1
uniform int uSize;  // texels a side at level L

// the four children's nodes (sized as nd, nt for loadNodes), and the mean's breakpoints
float cd[4][AVSM_N + 2];
vec3 ct[4][AVSM_N + 2];
int cn[4];
float bp[4 * AVSM_N];
float md[8 * AVSM_N];
vec3 mt[8 * AVSM_N];

vec4 nodeLayer(ivec2 q, int layer)
{
  return imageLoad(uIn, ivec3(q, layer));
}

vec3 childEval(int k, float z, bool front)
{
  int i = -1;
  for (int j = 0; j < cn[k]; ++j)
  {
    i = (front ? cd[k][j] < z : cd[k][j] <= z) ? j : i;
  }
  if (i < 0)
  {
    return vec3(1.0);
  }
  if (i == cn[k] - 1)
  {
    return ct[k][i];
  }
  float s = (z - cd[k][i]) / (cd[k][i + 1] - cd[k][i]);
  return ct[k][i] + (ct[k][i + 1] - ct[k][i]) * s;
}

// the mean's nodes compressed as nodesCompress does, on the larger arrays
float meanArea(int i, int n)
{
  float area = 0.0;
  for (int c = 0; c < AVSM_C; ++c)
  {
    area += 0.5 * abs((md[i] - md[i - 1]) * (mt[i + 1][c] - mt[i - 1][c]) -
                      (md[i + 1] - md[i - 1]) * (mt[i][c] - mt[i - 1][c]));
  }
  return area;
}

void main()
{
  uint g = GID();
  if (g >= uint(uSize * uSize))
  {
    return;
  }
  ivec2 q = ivec2(int(g) % uSize, int(g) / uSize);
  int nb = 0;
  bool same = true;
  for (int k = 0; k < 4; ++k)
  {
    cn[k] = loadNodes(2 * q + ivec2(k & 1, k >> 1), cd[k], ct[k]);
    same = same && cn[k] == cn[0];
    for (int j = 0; j < cn[k]; ++j)
    {
      same = same && cd[k][j] == cd[0][j] && ct[k][j] == ct[0][j];
      // insertion of the child's depths into the sorted breakpoints
      float d = cd[k][j];
      int p = nb;
      while (p > 0 && bp[p - 1] > d)
      {
        bp[p] = bp[p - 1];
        --p;
      }
      bp[p] = d;
      ++nb;
    }
  }
  nn = 0;
  if (same)
  {
    // four equal functions (empty, or a region of one caster): their mean is one of them
    for (int j = 0; j < cn[0]; ++j)
    {
      nd[nn] = cd[0][j];
      nt[nn++] = ct[0][j];
    }
    storeNodes(q);
    return;
  }
  int m = 0;
  for (int i = 0; i < nb; ++i)
  {
    if (i > 0 && bp[i] == bp[i - 1])
    {
      continue;
    }
    vec3 front = vec3(0.0), at = vec3(0.0);
    for (int k = 0; k < 4; ++k)
    {
      front += childEval(k, bp[i], true);
      at += childEval(k, bp[i], false);
    }
    front *= 0.25;
    at *= 0.25;
    md[m] = bp[i];
    mt[m++] = front;
    if (at != front)
    {
      md[m] = bp[i];
      mt[m++] = at;
    }
  }
  while (m > AVSM_N)
  {
    int best = 1;
    float bestArea = meanArea(1, m);
    for (int i = 2; i + 1 < m; ++i)
    {
      float ar = meanArea(i, m);
      if (ar < bestArea)
      {
        bestArea = ar;
        best = i;
      }
    }
    for (int i = best; i + 1 < m; ++i)
    {
      md[i] = md[i + 1];
      mt[i] = mt[i + 1];
    }
    --m;
  }
  for (int i = 0; i < m; ++i)
  {
    nd[i] = md[i];
    nt[i] = mt[i];
  }
  nn = m;
  storeNodes(q);
}
#endif
