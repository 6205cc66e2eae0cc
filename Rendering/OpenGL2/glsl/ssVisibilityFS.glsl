//VTK::System::Dec
// Visibility V(x,y) of one light for every G-buffer pixel: hard, PCF or PCSS.
uniform int method;         // 1 hard, 2 pcf, 3 pcss
uniform int maxQuads;
uniform float pcfRadius;
uniform float slopeBias;
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
//SS::Common

// The map hooks of ssQuadLit.glsl: the light's layer of the shadow-map array.
float mapTexelLit(View w, ivec2 t, float bias, float maxDelta)
{
  float d = fetchDepth(firstLayer + w.index, t);
  return (planeDepth(w, texelToProjected(w, vec2(t) + 0.5), maxDelta) - bias <= d) ? 1.0 : 0.0;
}

vec2 mapMinMax(View w, ivec2 q, int level)
{
  return fetchMinMaxDepth(firstLayer + w.index, q, level);
}

vec2 mapPlaneRange(View w, vec2 a, float s, float maxDelta)
{
  return planeRange(w, a, s, maxDelta);
}

//SS::QuadLit

// PVSM §4.1 eq. 2 with texel quads of 2^level texels: each quad contributes
// its overlap with the kernel box times its lit fraction, over the box area.
float coverageFilter(View w, vec2 k0, vec2 k1, float bias, float maxDelta)
{
  vec2 size = k1 - k0;
  if (size.x * size.y <= 0.0)
  {
    return quadLit(w, 0, ivec2(floor(0.5 * (k0 + k1))), bias, maxDelta);
  }
  // Texels outside the map hold nothing (fetchDepth: lit), so the kernel is
  // clipped to the map and its outside counted lit: V = 1 - blocked / area,
  // divided one axis at a time. A huge light's kernel (1e32 texels for a
  // light of size 1e30) overflowed the area and the quad indices in float
  // and int and gave V = 0 everywhere (issue 17).
  vec2 m0 = max(k0, vec2(0.0));
  vec2 m1 = min(k1, vec2(mapSize));
  if (m1.x <= m0.x || m1.y <= m0.y)
  {
    return 1.0;
  }
  float inside = (m1.x - m0.x) * (m1.y - m0.y);
  k0 = m0;
  k1 = m1;
  float extent = max(k1.x - k0.x, k1.y - k0.y);
  int level = 0;
  while (extent / exp2(float(level)) > float(maxQuads) && level < numLevels - 1)
  {
    ++level;
  }
  float s = exp2(float(level));
  ivec2 q0 = ivec2(floor(k0 / s));
  ivec2 q1 = ivec2(floor(k1 / s));
  float lit = 0.0;
  for (int qy = q0.y; qy <= q1.y; ++qy)
  {
    float a0 = float(qy) * s;
    float oy = max(0.0, min(a0 + s, k1.y) - max(a0, k0.y));
    if (oy <= 0.0)
    {
      continue;
    }
    for (int qx = q0.x; qx <= q1.x; ++qx)
    {
      float b0 = float(qx) * s;
      float ox = max(0.0, min(b0 + s, k1.x) - max(b0, k0.x));
      if (ox <= 0.0)
      {
        continue;
      }
      lit += ox * oy * quadLit(w, level, ivec2(qx, qy), bias, maxDelta);
    }
  }
  return clamp(1.0 - ((inside - lit) / size.x) / size.y, 0.0, 1.0);
}

void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(gPosition, 0))));
  vec4 g = texelFetch(gPosition, pix, 0);
  if (g.w <= 0.0)
  {
    gl_FragData[0] = vec4(-1.0); // background: NaN on download
    return;
  }
  vec3 nrm = texelFetch(gNormal, pix, 0).xyz;
  vec3 ng = receiverNormal(pix, nrm); // the receiver's facet (ssShadowCommon)
  vec3 d = g.xyz - lightCenter;
  vec3 dLookup = d; // moved along ng by the normal offset

  View w = selectReceiverView(dLookup, ng);
  if (w.index < 0)
  {
    gl_FragData[0] = vec4(outsideViewsVisibility(d));
    return;
  }

  // Direction to the light and the slope of the receiver's facet (ss::SlopeScaledBias).
  vec3 toLight = (orthographic != 0) ? -viewN[w.index] : normalize(-dLookup);
  float cosTheta = (dot(ng, ng) > 0.5) ? dot(ng, toLight) : 1.0;
  float tanTheta = (cosTheta > 1e-4) ? min(sqrt(max(0.0, 1.0 - cosTheta * cosTheta)) / cosTheta, 10.0) : 10.0;
  float slopeScaled = w.texelWorld * (constantBias + slopeBias * tanTheta);

  float V = 1.0;
  if (method == 1)
  {
    // hard: one texel, slope-scaled bias
    float dz = fetchDepth(firstLayer + w.index, ivec2(floor(w.T)));
    V = (w.p.z - slopeScaled <= dz) ? 1.0 : 0.0;
  }
  else
  {
    float bias = w.texelWorld * constantBias;
    if (method == 2)
    {
      vec2 r = vec2(pcfRadius);
      V = coverageFilter(w, w.T - r, w.T + r, bias, 8.0 * pcfRadius * w.texelWorld * 10.0);
    }
    else
    {
      float zAvg = blockerSearch(w, bias);
      if (zAvg < 0.0)
      {
        V = 1.0; // fully lit: no blocker in the search region
      }
      else
      {
        // PCSS step 2: penumbra by parallel planes, PVSM §4 eq. 1:
        // alpha = (z_r - z_o) / (z_r z_o) maps the light onto the unit plane.
        vec2 kHalf = lightFilterHalf(w.p.z, zAvg);
        vec2 kTex = kHalf * w.texelPerUnit;
        // PCSS step 3: filter with the texel-as-quad coverage integral (§4.1).
        // Below half a texel the kernel becomes an antialiased hard edge.
        kTex = max(kTex, vec2(0.5));
        float md = max(kTex.x, kTex.y) * w.texelWorld * 10.0;
        V = coverageFilter(w, w.T - kTex, w.T + kTex, bias, md);
      }
    }
  }
  // The shadow terminator: the light above both the shading normal's and
  // the facet's plane (ssShadowCommon, lightAboveSurface). Hard and PCF
  // shadow the light's centre (a hard map): its side of both planes; PCSS
  // the fraction of the light above them.
  V *= (method == 3) ? lightAboveSurface(normalize(nrm), ng, d) : centreAboveSurface(normalize(nrm), ng, d);
  gl_FragData[0] = vec4(V, 0.0, 0.0, 1.0);
}
