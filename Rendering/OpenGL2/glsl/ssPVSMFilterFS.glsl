//VTK::System::Dec
// PVSM §5.2 step 8: the pixels whose kernel reaches the current tile filter
// it with the §4.1 coverage integral along their kernel h (vertical panels one
// texel wide, each approximated by a box, §4.2) and add (V·A, A, back-
// projection) for this tile to the accumulation buffer (additive blending):
// the V·A / A merge of kernels overlapping several tiles, plus the per-texel
// reach below. Mirrors ss::FilterKernelInTile with ss::ReachParams
// (Rendering/Core/ssPVSM.h), where it is unit-tested.
uniform sampler2D kernel0;
uniform sampler2D kernel1;
uniform sampler2D kernel2;
uniform sampler2DArray tileMap; // layer 0: the tile's depth (RG), mips (min, max)
uniform vec4 tileRect;          // shadow-map extent of the tile
uniform vec2 tileRes;           // texels of the tile
uniform int tileLevels;
uniform int view;
uniform int maxQuads;
uniform float nearFraction; // ss::ReachParams::nearFraction
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
//SS::Common

vec2 tilePerUnit;
vec2 kernelCentre;  // shadow-map units
float unitWorldG;   // world units per shadow-map unit at the receiver

float tileDepth(ivec2 t)
{
  if (t.x < 0 || t.y < 0 || float(t.x) >= tileRes.x || float(t.y) >= tileRes.y)
  {
    return 3.0e38;
  }
  return texelFetch(tileMap, ivec3(t, 0), 0).r;
}

vec2 tileX(vec2 T)
{
  return tileRect.xy + T / tilePerUnit;
}

// The receiver's depth at X for the shadow test: its tangent plane, lowered
// by 0.05 of the lateral distance from the kernel centre (a 3 degree cone).
// A faceted surface deviates from the smooth normal's plane in proportion to
// that distance; without the cone its own facets hid the light from it
// (acne on a lit isosurface, growing with the tile resolution).
float tolerantDepth(View w, vec2 X, float maxDelta)
{
  return planeDepth(w, X, maxDelta) - 0.05 * length(X - kernelCentre) * unitWorldG;
}

// Per-texel reach and back-projection (beyond the paper; pvsm.md "Streaks on
// a concave wall"; ss::ReachParams). A blocked texel of depth z_b can hide
// light from the receiver only within its reach: the light filter of §4
// eq. 1 at z_b instead of z_avg, convolved with the pixel footprint as in
// §4.2. Two estimates of the hidden fraction are accumulated; the resolve
// keeps the larger:
//  - PCSS over the kernel, where a blocked texel counts whole if it is at
//    least nearFraction of z_avg's height above the receiver (the blockers
//    the kernel is sized by) and otherwise only within its reach;
//  - back-projection (Guennebaud et al. 2006): each blocked texel within its
//    reach adds its area over the reach's area (exact for a blocker plane at
//    any depth, where PCSS is exact only at z_avg).
// A curved receiver's own facets rise a little above its tangent plane but
// lie beyond their tiny reach, so neither counts them; plain PCSS counted
// them across the whole kernel (facet streaks on a lit concave wall).
mat2 footprint;   // the pixel footprint's covariance (shadow-map units^2)
float receiverZ;  // the receiver's light-space depth
float zAvg;       // the blocker average the kernel was sized with
vec2 viewSpan;    // the view's extent (shadow-map units)
float occ;        // blocked area counted by the PCSS estimate (tile texels^2)
float backProj;   // back-projected hidden fraction of the light

// The reach at depth zb as a semi-axis-aligned parallelogram (rx, slope, rvy)
// around the kernel centre; returns its area (shadow-map units^2).
float reachAt(float zb, out float rx, out float slope, out float rvy)
{
  vec2 r = min(lightFilterHalf(receiverZ, zb), viewSpan);
  float m00 = footprint[0][0] + r.x * r.x;
  float m10 = footprint[0][1];
  float m11 = footprint[1][1] + r.y * r.y;
  rx = sqrt(max(m00, 0.0));
  float ry = (rx > 0.0) ? m10 / rx : 0.0;
  rvy = sqrt(max(m11 - ry * ry, 0.0));
  slope = (rx > 0.0) ? ry / rx : 0.0;
  return 4.0 * rx * rvy;
}

// A blocked block of texels [t0, t1] (tile texels) of depths around zb, the
// lowest zLow, of which o (tile texels^2) lies in the kernel: it counts whole
// for PCSS when zb is high enough; otherwise, and for the back-projection,
// the part within the reach at zLow (its vertical extent at the block's
// centre, as the panels) does: the smallest of the block's reaches, so a
// coarse quad reaching down to the receiver (its own surface next to the
// kernel centre) is not credited with the light its high corner could hide.
// A block only sampled (its centre texel blocked) adds nothing to the
// back-projection: a reach is centred on the kernel centre, so a block
// touching it would claim a quarter of it, however small, for texels that
// may not be blocked at all.
void addBlocked(vec2 t0, vec2 t1, float zb, float zLow, float o, bool sampled)
{
  float rx, slope, rvy;
  float areaMap = reachAt(zLow, rx, slope, rvy);
  bool high = receiverZ - zb >= nearFraction * (receiverZ - zAvg);
  if (high)
  {
    occ += o;
  }
  if (!(areaMap > 0.0))
  {
    return;
  }
  vec2 a = tileX(t0) - kernelCentre;
  vec2 b = tileX(t1) - kernelCentre;
  float x0 = max(a.x, -rx), x1 = min(b.x, rx);
  if (!(x1 > x0))
  {
    return;
  }
  float cy = slope * 0.5 * (x0 + x1);
  float y0 = max(a.y, cy - rvy), y1 = min(b.y, cy + rvy);
  if (!(y1 > y0))
  {
    return;
  }
  float f = (x1 - x0) * (y1 - y0) / ((b.x - a.x) * (b.y - a.y));
  occ += high ? 0.0 : o * f;
  backProj += sampled ? 0.0 : o * f / (tilePerUnit.x * tilePerUnit.y * areaMap);
}

// The depth bias of a test on a quad of s tile texels: s texels (ssQuadLit.glsl:
// a quad samples the map as a map s times coarser would), and never less than
// the pixel footprint (receiverBiasFloor, set in main).
float receiverBiasFloor;
float quadBias(float texelBias, float s)
{
  return max(texelBias * s, receiverBiasFloor);
}

bool texelBlocked(View w, ivec2 t, float bias, float maxDelta, out float zb)
{
  t = min(t, ivec2(tileRes) - 1);
  zb = tileDepth(t);
  return !(tolerantDepth(w, tileX(vec2(t) + 0.5), maxDelta) - bias <= zb);
}

vec2 planeRangeTile(View w, vec2 a, float s, float maxDelta)
{
  float z00 = tolerantDepth(w, tileX(a), maxDelta);
  float z10 = tolerantDepth(w, tileX(a + vec2(s, 0.0)), maxDelta);
  float z01 = tolerantDepth(w, tileX(a + vec2(0.0, s)), maxDelta);
  float z11 = tolerantDepth(w, tileX(a + vec2(s)), maxDelta);
  return vec2(min(min(z00, z10), min(z01, z11)), max(max(z00, z10), max(z01, z11)));
}

// The quad q of 2^level texels, o of it in the kernel: decided as in
// ssQuadLit.glsl (its (min, max) depth, else its four children's, else a
// child's centre texel), each blocked part added with its depth (a decided
// quad: the middle of its range and its max).
void quadBlocked(View w, int level, ivec2 q, float bias, float maxDelta, float o)
{
  // one addBlocked() call site per path: llvmpipe runs every inlined copy
  // for all lanes of a SIMD group, so each copy costs (filtering +50% with
  // four of them on the canopy)
  float zb;
  if (level == 0)
  {
    if (texelBlocked(w, q, quadBias(bias, 1.0), maxDelta, zb))
    {
      addBlocked(vec2(q), vec2(q) + 1.0, zb, zb, o, false);
    }
    return;
  }
  float s = exp2(float(level));
  vec2 z = planeRangeTile(w, vec2(q) * s, s, maxDelta) - quadBias(bias, s);
  vec2 mm = texelFetch(tileMap, ivec3(q, 0), level).rg;
  if (z.y <= mm.x)
  {
    return;
  }
  bool whole = z.x > mm.y; // the whole quad is blocked
  float h = whole ? s : 0.5 * s;
  // the level below as the pyramid built it (ceil(tileRes / 2^(level-1))):
  // a child beyond it lies outside the tile, where the texture holds
  // whatever an earlier tile left (ss::FilterKernelInTile: nothing drawn).
  // o lies in the tile, so the children inside share it.
  ivec2 below = (ivec2(tileRes) + (1 << (level - 1)) - 1) >> (level - 1);
  float share = o / float(((2 * q.x + 1 < below.x) ? 2 : 1) * ((2 * q.y + 1 < below.y) ? 2 : 1));
  for (int c = 0; c < (whole ? 1 : 4); ++c)
  {
    ivec2 child = whole ? q : 2 * q + ivec2(c & 1, c >> 1);
    if (!whole && (child.x >= below.x || child.y >= below.y))
    {
      continue;
    }
    vec2 b = vec2(child) * h;
    vec2 cm = whole ? mm : texelFetch(tileMap, ivec3(child, 0), level - 1).rg;
    vec2 cz = whole ? z : planeRangeTile(w, b, h, maxDelta) - quadBias(bias, h);
    if (cz.y <= cm.x)
    {
      continue;
    }
    bool decided = cz.x > cm.y;
    zb = 0.5 * (cm.x + cm.y);
    if (decided || texelBlocked(w, ivec2(b + 0.5 * h), quadBias(bias, h), maxDelta, zb))
    {
      addBlocked(b, b + h, zb, cm.y, whole ? o : share, !decided);
    }
  }
}

void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(gPosition, 0))));
  vec4 k0 = texelFetch(kernel0, pix, 0);
  vec4 k1 = texelFetch(kernel1, pix, 0);
  if (k0.w != 1.0 || int(k1.z) != view)
  {
    discard;
  }
  // the kernel's bounding box against the tile
  float hw = max(abs(k0.x), 0.0);
  float hh = abs(k0.y) + abs(k0.z);
  vec2 c = k1.xy;
  if (c.x + hw < tileRect.x || c.x - hw > tileRect.z || c.y + hh < tileRect.y || c.y - hh > tileRect.w)
  {
    discard;
  }
  vec4 g = texelFetch(gPosition, pix, 0);
  vec3 nrm = receiverNormal(pix, texelFetch(gNormal, pix, 0).xyz); // the facet's plane
  vec3 d = g.xyz - lightCenter;
  View w;
  w.index = view;
  w.p = vec3(dot(d, viewU[view]), dot(d, viewV[view]), dot(d, viewN[view]));
  w.n = vec3(dot(nrm, viewU[view]), dot(nrm, viewV[view]), dot(nrm, viewN[view]));
  tilePerUnit = tileRes / (tileRect.zw - tileRect.xy);
  if (normalOffset > 0.0 && dot(nrm, nrm) > 0.5)
  {
    // the normal-offset lookup of ssShadowCommon (selectReceiverView) in
    // this tile's texels: the receiver's plane moved along its facet normal
    vec3 toLight = (orthographic != 0) ? -viewN[view] : normalize(-d);
    float cosL = clamp(dot(nrm, toLight), 0.0, 1.0);
    float texelW = max(1.0 / tilePerUnit.x, 1.0 / tilePerUnit.y) * ((orthographic != 0) ? 1.0 : w.p.z);
    d += nrm * (normalOffset * texelW * sqrt(1.0 - cosL * cosL));
    w.p = vec3(dot(d, viewU[view]), dot(d, viewV[view]), dot(d, viewN[view]));
  }
  float unitWorld = (orthographic != 0) ? 1.0 : w.p.z;
  unitWorldG = unitWorld;
  kernelCentre = c;
  receiverZ = w.p.z;
  viewSpan = viewExtent[view].zw - viewExtent[view].xy;
  occ = 0.0;
  backProj = 0.0;
  {
    // the footprint: the kernel's covariance minus the light filter at z_avg
    // (the same k as the kernel pass)
    zAvg = texelFetch(kernel2, pix, 0).z;
    vec2 k = min(lightFilterHalf(w.p.z, zAvg), viewSpan);
    float m10 = k0.x * k0.y;
    footprint = mat2(max(k0.x * k0.x - k.x * k.x, 0.0), m10, m10,
      max(k0.y * k0.y + k0.z * k0.z - k.y * k.y, 0.0));
  }
  float texelWorld = max(1.0 / tilePerUnit.x, 1.0 / tilePerUnit.y) * unitWorld;
  // The depth bias: constantBias tile texels, but never less than constantBias
  // times the pixel footprint's larger half axis (world, at the receiver).
  // The filter integrates V over the pixel's footprint (§4.2), and within it
  // the receiver's own surface departs from its facet's plane: across a
  // concave crease the neighbouring facet rises above that plane by about
  // its distance from the crease times the crease's slope, and counted as a
  // blocker (it is within every reach, which the footprint widens). A bias of
  // one tile texel shrank as the tiles got finer (views fitted to the visible
  // receivers) and the bunny showed thin dark curves along its creases on lit
  // surfaces (stability.md, real-mesh set: pvsm 169 -> 30 px off silhouettes
  // on the bunny, 264 -> 123 on the wavelet isosurface).
  float bias = texelWorld * constantBias;
  receiverBiasFloor = sqrt(max(footprint[0][0], footprint[1][1])) * unitWorld * constantBias;
  float maxDelta = 10.0 * (max(hw, hh) * unitWorld + texelWorld);
  // the kernel in tile texels
  vec2 T = (c - tileRect.xy) * tilePerUnit;
  float ux = k0.x * tilePerUnit.x;
  float uy = k0.y * tilePerUnit.y;
  float hv = abs(k0.z) * tilePerUnit.y;
  if (ux < 0.0)
  {
    ux = -ux;
    uy = -uy;
  }
  float slope = 0.0;
  if (ux < 1e-3)
  {
    hv += abs(uy);
    ux = 1e-3;
  }
  else
  {
    slope = uy / ux;
  }
  hv = max(hv, 1e-3);
  float extentT = max(2.0 * ux, 2.0 * (hv + abs(uy)));
  int level = 0;
  while (extentT / exp2(float(level)) > float(maxQuads) && level < tileLevels - 1)
  {
    ++level;
  }
  float s = exp2(float(level));
  int qx0 = max(0, int(floor((T.x - ux) / s)));
  int qx1 = min(int((tileRes.x - 1.0) / s), int(floor((T.x + ux) / s)));
  int qyMax = int((tileRes.y - 1.0) / s);
  float area = 0.0;
  for (int qx = qx0; qx <= qx1; ++qx)
  {
    float a = max(max(float(qx) * s, T.x - ux), 0.0);
    float b = min(min(float(qx + 1) * s, T.x + ux), tileRes.x);
    if (!(b > a))
    {
      continue;
    }
    float cy = T.y + slope * (0.5 * (a + b) - T.x);
    float y0 = max(cy - hv, 0.0);
    float y1 = min(cy + hv, tileRes.y);
    if (!(y1 > y0))
    {
      continue;
    }
    int qy0 = max(0, int(floor(y0 / s)));
    int qy1 = min(qyMax, int(floor(y1 / s)));
    for (int qy = qy0; qy <= qy1; ++qy)
    {
      float oy = min(float(qy + 1) * s, y1) - max(float(qy) * s, y0);
      if (oy <= 0.0)
      {
        continue;
      }
      float o = (b - a) * oy;
      area += o;
      quadBlocked(w, level, ivec2(qx, qy), bias, maxDelta, o);
    }
  }
  // shadow-map units, so tiles of different resolutions merge
  float toUnits = 1.0 / (tilePerUnit.x * tilePerUnit.y);
  gl_FragData[0] = vec4((area - occ) * toUnits, area * toUnits, backProj, 0.0);
}
