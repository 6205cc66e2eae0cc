//VTK::System::Dec
// PVSM §5.2 step 3: the kernel-shape buffer. Per pixel: the blocker search on
// the conservative low-resolution map (z_avg, fully-lit detection), the
// light filter s_alpha through z_avg (§4 eq. 1), the pixel footprint warped
// through the receiver's tangent plane into shadow-map space (§4.2, Fig. 5),
// their convolution as Gaussians turned back into a semi-axis-aligned
// parallelogram (§4.2, appendix with its typo fixed), and the predicted texel
// sizes (§5.1 eq. 4-5). Mirrors ss::ConvolveKernels, ss::PredictTexelSize,
// ss::PerceptualRho (Rendering/Core/ssPVSM.h), where they are unit-tested.
uniform mat4 clipToRel;   // camera clip space -> world relative to the frame origin
uniform vec2 screenSize;
uniform vec4 rhoCoeffs;   // the cubic P of the chosen metric (§5.1)
uniform float rhoEnd;     // log2 n is clamped to [0, rhoEnd]
uniform float quality;    // scale on rho
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
//SS::Common

// Outputs (RGBA32F each):
//  0: u_h.x, u_h.y, v_h.y, state (-1 background, 0 done: V = out1.w, 1 filter)
//  1: X (shadow-map position), view index, V factor (done) or the tangent-plane fraction (filter)
//  2: texel0, texel1 (predicted texel sizes), z_avg, 0

float rho(float n)
{
  float x = (n > 0.0) ? clamp(log2(n), 0.0, rhoEnd) : 0.0;
  return rhoCoeffs.x + x * (rhoCoeffs.y + x * (rhoCoeffs.z + x * rhoCoeffs.w));
}

// Shadow-map position of a point (relative world coordinates) in view i.
vec2 toMap(int i, vec3 q)
{
  vec3 d = q - lightCenter;
  vec3 p = vec3(dot(d, viewU[i]), dot(d, viewV[i]), dot(d, viewN[i]));
  return (orthographic != 0) ? p.xy : p.xy / max(p.z, 1e-30);
}

// Where the camera ray through the point at NDC position ndc meets the plane
// (p0, n); false when it misses (grazing or behind).
bool rayPlane(vec2 ndc, vec3 p0, vec3 n, out vec3 hit)
{
  vec4 a = clipToRel * vec4(ndc, -1.0, 1.0);
  vec4 b = clipToRel * vec4(ndc, 1.0, 1.0);
  vec3 o = a.xyz / a.w;
  vec3 dir = b.xyz / b.w - o;
  float den = dot(n, dir);
  if (abs(den) <= 1e-6 * length(dir) * length(n))
  {
    return false;
  }
  float t = dot(n, p0 - o) / den;
  hit = o + t * dir;
  return t > 0.0;
}

void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(gPosition, 0))));
  vec4 g = texelFetch(gPosition, pix, 0);
  if (g.w <= 0.0)
  {
    gl_FragData[0] = vec4(0.0, 0.0, 0.0, -1.0);
    gl_FragData[1] = vec4(0.0, 0.0, -1.0, 1.0);
    gl_FragData[2] = vec4(0.0);
    return;
  }
  vec3 nrm = texelFetch(gNormal, pix, 0).xyz;
  vec3 ng = receiverNormal(pix, nrm); // the receiver's facet (ssShadowCommon)
  vec3 d = g.xyz - lightCenter;
  vec3 dLookup = d; // the normal-offset lookup, in the low-resolution map's texels
  View w = selectReceiverView(dLookup, ng);
  if (w.index < 0)
  {
    gl_FragData[0] = vec4(0.0);
    gl_FragData[1] = vec4(0.0, 0.0, -1.0, outsideViewsVisibility(d));
    gl_FragData[2] = vec4(0.0);
    return;
  }
  float tangent = lightAboveSurface(normalize(nrm), ng, d);
  vec2 X = project(w.p);
  float bias = w.texelWorld * constantBias;
  float zAvg = blockerSearch(w, bias);
  if (zAvg < 0.0 || tangent <= 0.0)
  {
    // fully lit (no blocker in the conservative map) or facing away: skipped
    // from here on (§5.2 "Fully-lit pixel optimization")
    gl_FragData[0] = vec4(0.0);
    gl_FragData[1] = vec4(X, float(w.index), tangent);
    gl_FragData[2] = vec4(0.0);
    return;
  }
  // Fig. 5: the pixel's axes through the receiver's tangent plane. Half a
  // pixel each way; a ray that misses the plane (grazing) falls back to the
  // other direction's step, then to a tenth of the view.
  vec2 ndc = 2.0 * (vec2(pix) + 0.5) / screenSize - 1.0;
  vec3 n = (dot(ng, ng) > 0.5) ? ng : normalize(nrm); // the footprint on the receiver's facet
  vec3 hx, hy;
  vec2 e = viewExtent[w.index].zw - viewExtent[w.index].xy;
  vec2 uPhi = vec2(0.1 * e.x, 0.0);
  vec2 vPhi = vec2(0.0, 0.1 * e.y);
  bool okx = rayPlane(ndc + vec2(1.0 / screenSize.x, 0.0), g.xyz, n, hx);
  bool oky = rayPlane(ndc + vec2(0.0, 1.0 / screenSize.y), g.xyz, n, hy);
  if (okx)
  {
    uPhi = toMap(w.index, hx) - X;
  }
  if (oky)
  {
    vPhi = toMap(w.index, hy) - X;
  }
  if (okx && !oky)
  {
    vPhi = vec2(-uPhi.y, uPhi.x);
  }
  if (oky && !okx)
  {
    uPhi = vec2(vPhi.y, -vPhi.x);
  }
  uPhi = clamp(uPhi, -0.1 * e, 0.1 * e);
  vPhi = clamp(vPhi, -0.1 * e, 0.1 * e);
  // §4 eq. 1: the light filter s_alpha through blockers at z_avg (half axes)
  vec2 k = lightFilterHalf(w.p.z, zAvg);
  // No kernel is wider than the view: k grows without bound as z_avg -> 0,
  // and its square overflowed to inf, a kernel no tile saw, resolved as lit.
  k = min(k, e);
  // §4.2 / appendix: V_h = M_phi' M_phi'^T + M_s M_s^T = L L^T
  float m00 = uPhi.x * uPhi.x + vPhi.x * vPhi.x + k.x * k.x;
  float m10 = uPhi.x * uPhi.y + vPhi.x * vPhi.y;
  float m11 = uPhi.y * uPhi.y + vPhi.y * vPhi.y + k.y * k.y;
  vec2 uh;
  uh.x = sqrt(max(m00, 0.0));
  uh.y = (uh.x > 0.0) ? m10 / uh.x : 0.0;
  float vhy = sqrt(max(m11 - uh.y * uh.y, 0.0)); // the appendix's u2 is u_out
  // eq. 4-5: kernel size on screen along e0, e1 (pixels) and the texel size
  // that gives it rho(n) texels
  float det = uPhi.x * vPhi.y - vPhi.x * uPhi.y;
  float n0 = 1.0, n1 = 1.0;
  if (abs(det) > 1e-9 * length(uPhi) * length(vPhi))
  {
    n0 = abs(uh.x) * length(vec2(vPhi.y, uPhi.y)) / abs(det);
    n1 = vhy * length(vec2(vPhi.x, uPhi.x)) / abs(det);
  }
  float t0 = 2.0 * uh.x / (quality * rho(n0));
  float t1 = 2.0 * vhy / (quality * rho(n1));
  // Never coarser than the low-resolution map: below it the tiles would lose
  // geometry the blocker search saw (foliage lighter in coarse tiles, seams
  // where tiles of different resolutions meet).
  vec2 lowTexel = e / mapSize;
  t0 = min(t0, lowTexel.x / quality);
  t1 = min(t1, lowTexel.y / quality);
  gl_FragData[0] = vec4(uh, vhy, 1.0);
  gl_FragData[1] = vec4(X, float(w.index), tangent);
  gl_FragData[2] = vec4(t0, t1, zAvg, 0.0);
}
