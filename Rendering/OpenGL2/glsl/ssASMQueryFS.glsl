//VTK::System::Dec
// ASM queries (Fernando et al. 2001, §3, §4.2; Documentation/asm.md): every
// G-buffer pixel is taken to the light's view that holds it, the tree is
// descended from that view's root through the cells that hold children (the
// same walk as ss::ASMTree::FindLeaf), and the leaf's page in the atlas
// answers the shadow test. Output 0: V (1 lit, 0 shadowed, -1 background).
// Output 1: 1 where the pixel straddles a depth discontinuity of its leaf
// (§3.1's benefit counts such pixels): the receiver's own test differs among
// the 3x3 texels around its lookup, or, lit at its texel, it lies behind the
// nearest caster of its texel block (the page's conservative summary: a
// caster thinner than a texel that no texel centre sampled).
uniform sampler2D gPosition; // xyz: world position - frame origin, w: prop id (0 = background)
uniform sampler2D gNormal;
uniform sampler2D gGeomNormal; // the drawn triangle's normal, w: 1 where valid (ssGBuffer)
uniform usampler2D idImage;       // camera view of the caster set: (triangle id + 1, depth)
uniform usampler2DArray atlas;    // node pages: (depth fixed point, triangle id + 1)
uniform sampler2DArray summary;   // per page and block of summaryBlock^2 texels: the nearest caster depth
uniform int summaryBlock;
uniform isampler2D nodeTable;     // per node: (page x, page y, layer, resolution), then C*C children
uniform int nodeWidth;            // texels per node in the table
uniform int nodesPerRow;
uniform int cells;                // C
uniform int numViews;
uniform vec3 viewU[6];
uniform vec3 viewV[6];
uniform vec3 viewN[6];
uniform vec3 viewOrigin[6];       // relative to the frame origin
uniform vec4 viewExtent[6];
uniform int viewRoot[6];
uniform float viewDepthScale[6];
uniform int orthographic;
uniform int faceView[6];          // cube: the view of each face (+a0 -a0 +a1 -a1 +a2 -a2), -1: none
uniform vec3 cubeAxes[3];
uniform vec3 lightCenter;         // relative to the frame origin
uniform vec3 facing;              // a one-sided light's normal, else 0
uniform int useIdTest;
uniform float constantBias;       // texels
uniform float slopeBias;          // texels
uniform vec3 eyeRel;
uniform vec3 viewDir;
uniform float camDepthScale;
in vec2 texCoord;
//VTK::Output::Dec

const float kFixed = 4294967040.0;

ivec2 tableTexel(int node, int k)
{
  return ivec2((node % nodesPerRow) * nodeWidth + k, node / nodesPerRow);
}

int childOf(int node, int cell)
{
  ivec4 t = texelFetch(nodeTable, tableTexel(node, 1 + cell / 4), 0);
  int c = cell % 4;
  return c == 0 ? t.x : (c == 1 ? t.y : (c == 2 ? t.z : t.w));
}

// the view holding light-space direction d (from the light centre), -1 when none
int locate(vec3 d)
{
  if (orthographic != 0)
  {
    return 0;
  }
  if (dot(facing, facing) > 0.0 && dot(d, facing) <= 0.0)
  {
    return -2; // behind a one-sided light: no light arrives
  }
  vec3 c = vec3(dot(d, cubeAxes[0]), dot(d, cubeAxes[1]), dot(d, cubeAxes[2]));
  vec3 a = abs(c);
  int k = (a.x >= a.y && a.x >= a.z) ? 0 : ((a.y >= a.z) ? 1 : 2);
  float ck = k == 0 ? c.x : (k == 1 ? c.y : c.z);
  return faceView[2 * k + (ck < 0.0 ? 1 : 0)];
}

// the shadow test of texel t of a page: lit by the ID test (the texel's
// nearest caster is the pixel's own triangle) or by the depth test (§4.2)
bool litAt(ivec3 page, ivec2 t, float zr, float scale, uint pixelId)
{
  uvec2 s = texelFetch(atlas, ivec3(page.xy + t, page.z), 0).rg;
  if (useIdTest != 0 && pixelId != 0u && s.g == pixelId)
  {
    return true;
  }
  return uint(clamp(zr * scale, 0.0, 1.0) * kFixed) <= s.r;
}

void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(gPosition, 0))));
  vec4 g = texelFetch(gPosition, pix, 0);
  if (g.w <= 0.0)
  {
    gl_FragData[0] = vec4(-1.0);
    gl_FragData[1] = vec4(0.0);
    return;
  }
  vec3 nrm = texelFetch(gNormal, pix, 0).xyz;
  bool hasNormal = dot(nrm, nrm) > 0.5;
  vec3 dc = g.xyz - lightCenter;
  int v = locate(dc);
  if (v < 0)
  {
    // behind a one-sided light, or a direction without receivers' roots
    gl_FragData[0] = vec4(v == -2 ? 0.0 : 1.0);
    gl_FragData[1] = vec4(0.0);
    return;
  }
  vec3 d = g.xyz - viewOrigin[v];
  vec3 p = vec3(dot(d, viewU[v]), dot(d, viewV[v]), dot(d, viewN[v]));
  vec2 X = (orthographic != 0) ? p.xy : p.xy / p.z;
  vec4 e = viewExtent[v];
  if (!(orthographic != 0 || p.z > 0.0) || X.x < e.x || X.x > e.z || X.y < e.y || X.y > e.w)
  {
    gl_FragData[0] = vec4(1.0);
    gl_FragData[1] = vec4(0.0);
    return;
  }
  // the walk down the tree: t is X in the current node's window, in [0, 1)
  vec2 t = clamp((X - e.xy) / (e.zw - e.xy), 0.0, 1.0);
  int node = viewRoot[v];
  float scale = 1.0;
  for (int level = 0; level < 24; ++level)
  {
    ivec2 c = clamp(ivec2(floor(t * float(cells))), ivec2(0), ivec2(cells - 1));
    int child = childOf(node, c.x + cells * c.y);
    if (child < 0)
    {
      break;
    }
    t = t * float(cells) - vec2(c);
    scale *= float(cells);
    node = child;
  }
  ivec4 info = texelFetch(nodeTable, tableTexel(node, 0), 0);
  ivec3 page = info.xyz;
  int res = max(info.w, 1);
  vec2 T = t * float(res);
  ivec2 tc = clamp(ivec2(floor(T)), ivec2(0), ivec2(res - 1));
  // the leaf's texel in view units, and in world units at the receiver
  vec2 texelView = (e.zw - e.xy) / (scale * float(res));
  float texelWorld = (orthographic != 0) ? texelView.x : texelView.x * p.z;

  // the pixel's own caster triangle: the camera's nearest caster at this
  // pixel, if it is the G-buffer's surface (same depth along the view)
  uvec2 idd = texelFetch(idImage, pix, 0).rg;
  float gDepth = dot(g.xyz - eyeRel, viewDir);
  float idDepth = float(idd.g) / kFixed / camDepthScale;
  uint pixelId = (idd.r != 0u && abs(idDepth - gDepth) <= 1e-3 * abs(gDepth) + 1e-6) ? idd.r : 0u;

  // slope-scaled bias in the leaf's texels (the bias problem persists with
  // the ID test, §4.2; it matters only where the ID test fails)
  vec3 toLight = (orthographic != 0) ? -viewN[v] : normalize(-d);
  // the receiver's plane is its facet's (ssShadowCommon, receiverNormal):
  // the smooth normal's tangent plane cuts through the facet (issue 17)
  vec4 gn = texelFetch(gGeomNormal, pix, 0);
  bool hasFacet = gn.w > 0.5;
  vec3 nl = hasFacet ? gn.xyz : (hasNormal ? normalize(nrm) : toLight);
  float cosTheta = dot(nl, toLight);
  float tanTheta = (cosTheta > 1e-4) ? min(sqrt(max(0.0, 1.0 - cosTheta * cosTheta)) / cosTheta, 10.0) : 10.0;
  float bias = texelWorld * (constantBias + slopeBias * tanTheta);
  float dscale = viewDepthScale[v];
  bool lit = litAt(page, tc, p.z - bias, dscale, pixelId);

  // the neighbours, each against the receiver's tangent plane along its own ray
  vec3 n = vec3(dot(nl, viewU[v]), dot(nl, viewV[v]), dot(nl, viewN[v]));
  float maxDelta = 4.0 * texelWorld * (1.0 + slopeBias * tanTheta);
  bool edge = false;
  for (int dy = -1; dy <= 1; ++dy)
  {
    for (int dx = -1; dx <= 1; ++dx)
    {
      ivec2 q = tc + ivec2(dx, dy);
      if ((dx == 0 && dy == 0) || q.x < 0 || q.y < 0 || q.x >= res || q.y >= res)
      {
        continue;
      }
      vec2 Xq = X + (vec2(q) + 0.5 - T) * texelView;
      float zq;
      if (orthographic != 0)
      {
        zq = (abs(n.z) > 1e-6) ? p.z - (n.x * (Xq.x - p.x) + n.y * (Xq.y - p.y)) / n.z : p.z;
      }
      else
      {
        float den = dot(n, vec3(Xq, 1.0));
        zq = (abs(den) > 1e-12) ? dot(n, p) / den : p.z;
      }
      zq = clamp(zq, p.z - maxDelta, p.z + maxDelta);
      edge = edge || (litAt(page, q, zq - bias, dscale, pixelId) != lit);
    }
  }
  // thin casters: the block's conservative nearest depth, with the receiver's
  // own depth spread over the block allowed for (its slope-scaled bias there)
  if (lit && !edge)
  {
    float zc = texelFetch(summary, ivec3(page.xy / summaryBlock + tc / summaryBlock, page.z), 0).r;
    edge = p.z - float(summaryBlock) * bias > zc;
  }
  // no light reaches a surface facing away from it (as the other methods)
  // and the shadow terminator: the light's centre above the shading normal's
  // plane and the facet's (ssShadowCommon, centreAboveSurface)
  float facingLight = ((!hasNormal || dot(normalize(nrm), toLight) > 0.0) && (!hasFacet || cosTheta > 0.0)) ? 1.0 : 0.0;
  edge = edge && facingLight > 0.0;
  gl_FragData[0] = vec4((lit ? 1.0 : 0.0) * facingLight, 0.0, 0.0, 1.0);
  gl_FragData[1] = vec4(edge ? 1.0 : 0.0);
}
