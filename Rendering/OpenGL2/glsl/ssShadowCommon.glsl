// Shared by the visibility and PVSM shaders (pasted where a shader says
// //SS::Common): the light's views, shadow-map fetches, the receiver plane,
// the light above the tangent plane, view selection and the blocker search.
// The math mirrors Rendering/Core (ssPCSS.h, ssCoverage.h), where it is unit-tested.
uniform sampler2D gPosition; // xyz: world position - frame origin, w: prop id (0 = background)
uniform sampler2D gNormal;   // xyz: world (shading) normal
uniform sampler2D gGeomNormal; // xyz: world normal of the drawn triangle, w: 1 where valid
uniform sampler2DArray shadowMaps; // one layer per view, linear light-space depth (RG);
                                  // mip level l holds (min, max) of the level below
uniform int firstLayer;
uniform int numViews;
uniform vec3 viewU[6];
uniform vec3 viewV[6];
uniform vec3 viewN[6];
uniform vec4 viewExtent[6];
uniform vec3 lightCenter;  // relative to the frame origin (orthographic: a point behind the scene)
uniform int orthographic;
uniform int oneSided;      // rect lights light only the half-space in front of them
uniform vec2 lightHalfSize; // rect: half width/height (world); directional: tan(angle/2) twice
uniform vec3 lightU; // rect light edges (unit), relative frame
uniform vec3 lightV;
uniform float mapSize;
uniform int numLevels;
uniform float searchDepth;  // nearest caster depth: PCSS blocker-search plane
uniform int searchSamples;
uniform float constantBias;
uniform float normalOffset; // texels (ss::NormalOffsetDistance)

struct View
{
  int index;
  vec3 p;   // light-space position (x, y, z)
  vec3 n;   // light-space normal
  vec2 T;   // continuous texel coordinates
  float texelWorld; // world size of one texel at the receiver
  vec2 texelPerUnit; // texels per projected unit
};

vec2 project(vec3 p)
{
  return (orthographic != 0) ? p.xy : p.xy / p.z;
}

float fetchDepth(int layer, ivec2 t)
{
  ivec2 s = ivec2(int(mapSize));
  if (t.x < 0 || t.y < 0 || t.x >= s.x || t.y >= s.y)
  {
    return 3.0e38; // outside the map: nothing there, lit
  }
  return texelFetch(shadowMaps, ivec3(t, layer), 0).r;
}

float fetchMinDepth(int layer, ivec2 t, int level)
{
  int s = max(1, int(mapSize) >> level);
  if (t.x < 0 || t.y < 0 || t.x >= s || t.y >= s)
  {
    return 3.0e38;
  }
  return texelFetch(shadowMaps, ivec3(t, layer), level).r;
}

vec2 fetchMinMaxDepth(int layer, ivec2 t, int level)
{
  int s = max(1, int(mapSize) >> level);
  if (t.x < 0 || t.y < 0 || t.x >= s || t.y >= s)
  {
    return vec2(3.0e38);
  }
  return texelFetch(shadowMaps, ivec3(t, layer), level).rg;
}

// Ssee ss::ReceiverPlaneDepth: depth of the receiver's tangent plane along
// the projection ray through unit-plane position X, clamped.
float planeDepth(View w, vec2 X, float maxDelta)
{
  float z;
  if (orthographic != 0)
  {
    z = (abs(w.n.z) > 1e-6) ? w.p.z - (w.n.x * (X.x - w.p.x) + w.n.y * (X.y - w.p.y)) / w.n.z
                            : w.p.z;
  }
  else
  {
    float den = dot(w.n, vec3(X, 1.0));
    z = (abs(den) > 1e-12) ? dot(w.n, w.p) / den : w.p.z;
  }
  if (!(z == z))
  {
    z = w.p.z;
  }
  return clamp(z, w.p.z - maxDelta, w.p.z + maxDelta);
}

vec2 texelToProjected(View w, vec2 T)
{
  vec4 e = viewExtent[w.index];
  return e.xy + T / w.texelPerUnit;
}

// (min, max) of the receiver's tangent plane over the quad [a, a + s]^2 (texel
// units): the plane's depth along the rays is bounded by the quad's corners.
vec2 planeRange(View w, vec2 a, float s, float maxDelta)
{
  float z00 = planeDepth(w, texelToProjected(w, a), maxDelta);
  float z10 = planeDepth(w, texelToProjected(w, a + vec2(s, 0.0)), maxDelta);
  float z01 = planeDepth(w, texelToProjected(w, a + vec2(0.0, s)), maxDelta);
  float z11 = planeDepth(w, texelToProjected(w, a + vec2(s)), maxDelta);
  return vec2(min(min(z00, z10), min(z01, z11)), max(max(z00, z10), max(z01, z11)));
}

// [lo, hi] of t where alpha + beta t > 0 (`closed`: >= 0 where beta is 0)
void clipInterval(float alpha, float beta, bool closed, inout float lo, inout float hi)
{
  if (beta > 0.0)
  {
    lo = max(lo, -alpha / beta);
  }
  else if (beta < 0.0)
  {
    hi = min(hi, -alpha / beta);
  }
  else if (!(alpha > 0.0 || (closed && alpha == 0.0)))
  {
    hi = lo - 1.0;
  }
}

float crossArea(vec2 p, vec2 q)
{
  return p.x * q.y - p.y * q.x;
}

// ss::SquareFractionAbovePlanes in float (its comments; unit-tested there
// against the clipped polygon): the fraction of [-1,1]^2 where both
// f.x + f.y s + f.z t > 0, by the boundary integral. Registers only: the
// polygon clip it replaced kept its points in local arrays, which llvmpipe
// reads and writes lane by lane.
float squareAbovePlanes(vec3 f1In, vec3 f2In)
{
  float m1 = max(max(abs(f1In.x), abs(f1In.y)), abs(f1In.z));
  float m2 = max(max(abs(f2In.x), abs(f2In.y)), abs(f2In.z));
  vec3 f[2];
  f[0] = (m1 > 0.0) ? f1In / m1 : f1In;
  f[1] = (m2 > 0.0) ? f2In / m2 : f2In;
  float twice = 0.0;
  for (int e = 0; e < 4; ++e)
  {
    // the square's corners counter-clockwise: (-1,-1), (1,-1), (1,1), (-1,1)
    vec2 A = vec2((e == 1 || e == 2) ? 1.0 : -1.0, (e >= 2) ? 1.0 : -1.0);
    vec2 B = vec2((e == 0 || e == 1) ? 1.0 : -1.0, (e == 1 || e == 2) ? 1.0 : -1.0);
    float lo = 0.0, hi = 1.0;
    for (int k = 0; k < 2; ++k)
    {
      float vA = f[k].x + f[k].y * A.x + f[k].z * A.y;
      float vB = f[k].x + f[k].y * B.x + f[k].z * B.y;
      clipInterval(vA, vB - vA, false, lo, hi);
    }
    twice += (lo < hi) ? crossArea(A + (B - A) * lo, A + (B - A) * hi) : 0.0;
  }
  vec2 g[2];
  g[0] = f[0].yz;
  g[1] = f[1].yz;
  vec2 gg = vec2(dot(g[0], g[0]), dot(g[1], g[1]));
  vec2 len = sqrt(gg);
  float kappa = crossArea(g[0], g[1]);
  bool crossing = abs(kappa) > 1e-6 * len.x * len.y;
  vec2 X = crossing ? vec2(f[1].x * g[0].y - f[0].x * g[1].y, f[0].x * g[1].x - f[1].x * g[0].x) / kappa : vec2(0.0);
  bool sameWay = dot(g[0], g[1]) > 0.0;
  vec2 offset = vec2((len.x > 0.0) ? -f[0].x / len.x : 0.0, (len.y > 0.0) ? -f[1].x / len.y : 0.0);
  for (int k = 0; k < 2; ++k)
  {
    int o = 1 - k;
    if (!(gg[k] > 0.0))
    {
      continue;
    }
    vec2 p0 = g[k] * (-f[k].x / gg[k]);
    vec2 dir = vec2(g[k].y, -g[k].x);
    float lo = -3.0e38, hi = 3.0e38;
    clipInterval(1.0 - p0.x, -dir.x, true, lo, hi);
    clipInterval(1.0 + p0.x, dir.x, true, lo, hi);
    clipInterval(1.0 - p0.y, -dir.y, true, lo, hi);
    clipInterval(1.0 + p0.y, dir.y, true, lo, hi);
    if (crossing)
    {
      float tX = dot(X - p0, dir) / gg[k];
      if (dot(g[o], dir) > 0.0)
      {
        lo = max(lo, tX);
      }
      else
      {
        hi = min(hi, tX);
      }
    }
    else if (!(gg[o] > 0.0))
    {
      clipInterval(f[o].x, 0.0, false, lo, hi);
    }
    else
    {
      bool keep = sameWay ? ((k == 0) ? offset[k] >= offset[o] : offset[k] > offset[o]) : (offset.x < -offset.y);
      hi = keep ? hi : lo - 1.0;
    }
    twice += (lo < hi) ? crossArea(p0 + dir * lo, p0 + dir * hi) : 0.0;
  }
  float fraction = 0.125 * twice;
  return (fraction == fraction) ? clamp(fraction, 0.0, 1.0) : 0.0;
}

// Fraction of the light above both the tangent plane of the shading normal
// `ns` and the plane of the receiver's own triangle `ng`: light points below
// either cannot be seen from the surface (below the triangle's plane the
// triangle or, on a closed mesh, the mesh behind it hides them; the
// reference and GEARS clip by the shading normal's plane). This is the
// shadow-terminator rule for coarse meshes with interpolated normals (issue
// 17; Chiang et al. 2019 "Taming the shadow terminator" make the same
// observation): the lit/unlit decision at a facet the light grazes comes from
// the facet, not from a shadow-map texel the facet shares with its
// neighbours. Rect light: the part of the square [-1,1]^2 (the light in units
// of its half sizes, so that a 1e30 light's area stays finite in float)
// above both planes (squareAbovePlanes); directional light with a size: the
// same for its square of directions. Point lights: the light centre's side
// of both planes. Same as ss::LightFractionAboveSurface.
float lightAboveSurface(vec3 ns, vec3 ng, vec3 d)
{
  // (written !(x > 0.5): normalize(0) is NaN, and a NaN normal is none)
  if (!(dot(ns, ns) > 0.5))
  {
    ns = ng; // no shading normal (unlit prop): the triangle's plane alone
  }
  if (!(dot(ng, ng) > 0.5))
  {
    ng = ns;
  }
  if (!(dot(ns, ns) > 0.5))
  {
    return 1.0; // no normal at all: no clipping
  }
  // towards the light's centre; a directional light's square of directions
  // -n + s h u + t h v (h = tan(angle / 2), (s, t) in [-1, 1]^2, as the
  // reference and GEARS sample it) is clipped as a rect light is (before,
  // its centre's side alone: under a light 2.8 rad wide, or a far one of
  // 1e12, the ground kept the half of the light below its plane, V 0.97
  // where 0.45 is right)
  vec3 toCentre = (orthographic != 0) ? -viewN[0] : -d;
  bool sized = (orthographic != 0 || oneSided != 0) && lightHalfSize.x > 0.0 && lightHalfSize.y > 0.0;
  if (!sized)
  {
    return (dot(ns, toCentre) > 0.0 && dot(ng, toCentre) > 0.0) ? 1.0 : 0.0;
  }
  vec3 f1 = vec3(dot(ns, toCentre), lightHalfSize.x * dot(ns, lightU), lightHalfSize.y * dot(ns, lightV));
  vec3 f2 = vec3(dot(ng, toCentre), lightHalfSize.x * dot(ng, lightU), lightHalfSize.y * dot(ng, lightV));
  return squareAbovePlanes(f1, f2);
}

// 1 when the light's centre is above both planes (lightAboveSurface), else
// 0: the terminator of the methods that shadow from the centre (hard, PCF,
// each sample of the hard average), as GEARS at one sample.
float centreAboveSurface(vec3 ns, vec3 ng, vec3 d)
{
  ns = (dot(ns, ns) > 0.5) ? ns : ng;
  ng = (dot(ng, ng) > 0.5) ? ng : ns;
  if (!(dot(ns, ns) > 0.5))
  {
    return 1.0; // no normal at all
  }
  vec3 toCentre = (orthographic != 0) ? -viewN[0] : -d;
  return (dot(ns, toCentre) > 0.0 && dot(ng, toCentre) > 0.0) ? 1.0 : 0.0;
}

// Fraction of the light above the tangent plane of `nrm` alone (receivers
// without a triangle of their own: translucent volumes' samples). Same as
// ss::LightFractionAboveTangentPlane.
float lightAboveTangent(vec3 nrm, vec3 d)
{
  return lightAboveSurface(nrm, nrm, d);
}

// The view of the light that holds the light-space direction d (from the
// light centre to the point); index -1 when none does.
View selectView(vec3 d, vec3 nrm)
{
  View w;
  w.index = -1;
  for (int i = 0; i < numViews; ++i)
  {
    vec3 p = vec3(dot(d, viewU[i]), dot(d, viewV[i]), dot(d, viewN[i]));
    if (orthographic == 0 && p.z <= 0.0)
    {
      continue;
    }
    vec2 X = project(p);
    vec4 e = viewExtent[i];
    if (X.x >= e.x && X.x <= e.z && X.y >= e.y && X.y <= e.w)
    {
      w.index = i;
      w.p = p;
      w.n = vec3(dot(nrm, viewU[i]), dot(nrm, viewV[i]), dot(nrm, viewN[i]));
      w.texelPerUnit = vec2(mapSize) / (e.zw - e.xy);
      w.T = (X - e.xy) * w.texelPerUnit;
      float unitTexel = (e.z - e.x) / mapSize;
      w.texelWorld = (orthographic != 0) ? unitTexel : unitTexel * p.z;
      break;
    }
  }
  return w;
}

// The normal of the receiver's plane: the drawn triangle's own (geometric)
// normal from the G-buffer, the shading normal where there is none. A
// faceted surface with interpolated normals is its facets: the smooth
// normal's tangent plane cuts through the receiver's own facet (half of it
// above the plane), which then shadows the receiver: cross-hatched bands on
// a lit isosurface, speckles along a coarse sphere's terminator (issue 17).
// The receiver-plane depth test (planeDepth) and the slope-scaled bias take
// this plane; the facet is then exactly at the plane's depth, and on a
// convex piece its neighbours lie behind it.
vec3 receiverNormal(ivec2 pix, vec3 shading)
{
  vec4 gn = texelFetch(gGeomNormal, pix, 0);
  return (gn.w > 0.5) ? gn.xyz : ((dot(shading, shading) > 0.5) ? normalize(shading) : vec3(0.0));
}

// Normal-offset lookup (Holbert 2011; Filament's computeLightSpacePosition,
// shaders/src/common_shadowing.fs): the point is moved along its geometric
// normal `ng` by normalOffset texels of its view's world texel size at the
// receiver times sin(theta) between `ng` and the light
// (ss::NormalOffsetDistance), and its view is selected again. The lookup
// then happens where the surface is clear of the texels its own facet and
// its neighbours rasterised into; at normal incidence nothing moves, so
// contact shadows keep their place.
View selectReceiverView(inout vec3 d, vec3 ng)
{
  View w = selectView(d, ng);
  if (w.index < 0 || normalOffset <= 0.0 || dot(ng, ng) < 0.5)
  {
    return w;
  }
  vec3 toLight = (orthographic != 0) ? -viewN[w.index] : normalize(-d);
  float c = clamp(dot(ng, toLight), 0.0, 1.0);
  vec3 d2 = d + ng * (normalOffset * w.texelWorld * sqrt(1.0 - c * c));
  View w2 = selectView(d2, ng);
  if (w2.index >= 0)
  {
    d = d2;
    return w2;
  }
  return w;
}

// V of a point no view holds: behind a one-sided light no light arrives;
// outside every view (beyond the widest angle a view covers) it is unshadowed.
float outsideViewsVisibility(vec3 d)
{
  return ((oneSided != 0) && (dot(d, viewN[0]) <= 0.0)) ? 0.0 : 1.0;
}

// PCSS step 1 (Fernando 2005), the blocker search: the overlap-weighted mean
// depth of the blockers in the light's footprint on the plane of the nearest
// caster, from the min-depth pyramid; -1 when there is none (fully lit; with
// a conservatively rasterised map this is exact, PVSM §5.2).
// §4 eq. 1: half axes of the light's projection through blockers at depth
// zb, seen from a receiver at depth zr (unit-plane units; orthographic:
// world units). Unclamped; ss::LightFilterHalfAxes is this with the view's
// extent as a cap.
vec2 lightFilterHalf(float zr, float zb)
{
  float dz = max(zr - zb, 0.0);
  return (orthographic != 0) ? lightHalfSize * dz : lightHalfSize * dz / max(zr * zb, 1e-30);
}

float blockerSearch(View w, float bias)
{
  // PCSS step 1: blocker search over the light's footprint on the plane of
  // the nearest caster (Fernando 2005; PVSM §4 eq. 1 scale).
  vec2 searchHalf = lightFilterHalf(w.p.z, min(searchDepth, w.p.z));
  vec2 searchTex = min(searchHalf * w.texelPerUnit, vec2(mapSize * 0.25));
  searchTex = max(searchTex, vec2(1.0));
  float maxDelta = max(searchTex.x, searchTex.y) * w.texelWorld * 10.0;
  // The search looks at every cell of the min-depth level whose cells are
  // about (2 * search / samples) texels wide, so no blocker between two
  // samples is missed (a missed blocker makes a lit streak). Each cell is
  // weighted by its overlap with the search box, so z_avg is continuous.
  float cellsWide = 2.0 * max(searchTex.x, searchTex.y) / float(searchSamples);
  int level = clamp(int(ceil(log2(max(cellsWide, 1.0)))), 0, numLevels - 1);
  float cell = exp2(float(level));
  vec2 s0 = w.T - searchTex;
  vec2 s1 = w.T + searchTex;
  ivec2 c0 = ivec2(floor(s0 / cell));
  ivec2 c1 = ivec2(floor(s1 / cell));
  float sum = 0.0;
  float count = 0.0;
  for (int cy = c0.y; cy <= c1.y; ++cy)
  {
    float oy = max(0.0, min((float(cy) + 1.0) * cell, s1.y) - max(float(cy) * cell, s0.y));
    for (int cx = c0.x; cx <= c1.x; ++cx)
    {
      float ox = max(0.0, min((float(cx) + 1.0) * cell, s1.x) - max(float(cx) * cell, s0.x));
      float dz = fetchMinDepth(firstLayer + w.index, ivec2(cx, cy), level);
      if (ox * oy <= 0.0 || dz > 1.0e38)
      {
        continue;
      }
      // the receiver's nearest depth over the cell: its plane at the corners
      float zr = planeRange(w, vec2(cx, cy) * cell, cell, maxDelta).x;
      if (dz < zr - bias)
      {
        sum += dz * ox * oy;
        count += ox * oy;
      }
    }
  }
  return (count == 0.0) ? -1.0 : sum / count;
}

