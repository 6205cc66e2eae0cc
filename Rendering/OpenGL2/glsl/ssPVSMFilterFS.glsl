//VTK::System::Dec
// PVSM §5.2 step 8: the pixels whose kernel reaches the current tile filter
// it with the §4.1 coverage integral along their kernel h (vertical panels one
// texel wide, each approximated by a box, §4.2) and add (V·A, A) for this
// tile to the accumulation buffer (additive blending): the V·A / A merge of
// kernels overlapping several tiles. Mirrors ss::FilterKernelInTile
// (Rendering/Core/ssPVSM.h), where it is unit-tested.
uniform sampler2D kernel0;
uniform sampler2D kernel1;
uniform sampler2DArray tileMap; // layer 0: the tile's depth (RG), mips (min, max)
uniform vec4 tileRect;          // shadow-map extent of the tile
uniform vec2 tileRes;           // texels of the tile
uniform int tileLevels;
uniform int view;
uniform int maxQuads;
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

// The map hooks of ssQuadLit.glsl: the current tile (children's centre
// texels are kept inside the tile's resolution).
float mapTexelLit(View w, ivec2 t, float bias, float maxDelta)
{
  t = min(t, ivec2(tileRes) - 1);
  return (tolerantDepth(w, tileX(vec2(t) + 0.5), maxDelta) - bias <= tileDepth(t)) ? 1.0 : 0.0;
}

vec2 mapMinMax(View w, ivec2 q, int level)
{
  return texelFetch(tileMap, ivec3(q, 0), level).rg;
}

vec2 mapPlaneRange(View w, vec2 a, float s, float maxDelta)
{
  float z00 = tolerantDepth(w, tileX(a), maxDelta);
  float z10 = tolerantDepth(w, tileX(a + vec2(s, 0.0)), maxDelta);
  float z01 = tolerantDepth(w, tileX(a + vec2(0.0, s)), maxDelta);
  float z11 = tolerantDepth(w, tileX(a + vec2(s)), maxDelta);
  return vec2(min(min(z00, z10), min(z01, z11)), max(max(z00, z10), max(z01, z11)));
}

//SS::QuadLit

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
  vec3 nrm = texelFetch(gNormal, pix, 0).xyz;
  vec3 d = g.xyz - lightCenter;
  View w;
  w.index = view;
  w.p = vec3(dot(d, viewU[view]), dot(d, viewV[view]), dot(d, viewN[view]));
  w.n = vec3(dot(nrm, viewU[view]), dot(nrm, viewV[view]), dot(nrm, viewN[view]));
  tilePerUnit = tileRes / (tileRect.zw - tileRect.xy);
  float unitWorld = (orthographic != 0) ? 1.0 : w.p.z;
  unitWorldG = unitWorld;
  kernelCentre = c;
  float texelWorld = max(1.0 / tilePerUnit.x, 1.0 / tilePerUnit.y) * unitWorld;
  float bias = texelWorld * constantBias;
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
  float lit = 0.0;
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
      lit += o * quadLit(w, level, ivec2(qx, qy), bias, maxDelta);
    }
  }
  // shadow-map units, so tiles of different resolutions merge
  float toUnits = 1.0 / (tilePerUnit.x * tilePerUnit.y);
  gl_FragData[0] = vec4(lit * toUnits, area * toUnits, 0.0, 0.0);
}
