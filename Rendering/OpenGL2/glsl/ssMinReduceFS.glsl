//VTK::System::Dec
// One level of a pyramid: each texel combines the 2x2 texels below it (the
// sampled range is restricted to the level below, so reading and writing one
// texture is not a feedback loop).
//  mode 0, the shadow maps' depth pyramid: minimum (R) and maximum (G).
//  mode 1, PVSM's shadow map tile grid (§5.2 step 5, "the SMTG pyramid is
//          constructed on the GPU"): the minimum of both components, the
//          smallest predicted texel size per axis. Values that are not finite
//          and positive mean "no pixel needs this cell" and become 3e38, as
//          Core's TileGridPyramid treats them.
uniform sampler2DArray src;
uniform int layer;
uniform int mode;
uniform ivec2 srcSize;
uniform ivec2 dstSize;
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
vec2 cell(vec2 t)
{
  // NaN fails both comparisons; 3e38 stands for +inf
  return vec2((t.x > 0.0 && t.x < 3.0e38) ? t.x : 3.0e38, (t.y > 0.0 && t.y < 3.0e38) ? t.y : 3.0e38);
}
void main()
{
  ivec2 p = ivec2(floor(texCoord * vec2(dstSize))) * 2;
  ivec2 hi = srcSize - 1;
  vec2 a = texelFetch(src, ivec3(min(p, hi), layer), 0).rg;
  vec2 b = texelFetch(src, ivec3(min(p + ivec2(1, 0), hi), layer), 0).rg;
  vec2 c = texelFetch(src, ivec3(min(p + ivec2(0, 1), hi), layer), 0).rg;
  vec2 d = texelFetch(src, ivec3(min(p + ivec2(1, 1), hi), layer), 0).rg;
  if (mode == 1)
  {
    gl_FragData[0] = vec4(min(min(cell(a), cell(b)), min(cell(c), cell(d))), 0.0, 1.0);
    return;
  }
  gl_FragData[0] = vec4(min(min(a.x, b.x), min(c.x, d.x)), max(max(a.y, b.y), max(c.y, d.y)), 0.0, 1.0);
}
