//VTK::System::Dec
// One level of the shadow maps' depth pyramid: each texel holds the minimum
// (R) and maximum (G) of the 2x2 texels below it (the sampled range is restricted to the level
// below, so reading and writing one texture is not a feedback loop).
uniform sampler2DArray src;
uniform int layer;
uniform ivec2 srcSize;
uniform ivec2 dstSize;
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
void main()
{
  ivec2 p = ivec2(floor(texCoord * vec2(dstSize))) * 2;
  ivec2 hi = srcSize - 1;
  vec2 a = texelFetch(src, ivec3(min(p, hi), layer), 0).rg;
  vec2 b = texelFetch(src, ivec3(min(p + ivec2(1, 0), hi), layer), 0).rg;
  vec2 c = texelFetch(src, ivec3(min(p + ivec2(0, 1), hi), layer), 0).rg;
  vec2 d = texelFetch(src, ivec3(min(p + ivec2(1, 1), hi), layer), 0).rg;
  gl_FragData[0] = vec4(min(min(a.x, b.x), min(c.x, d.x)), max(max(a.y, b.y), max(c.y, d.y)), 0.0, 1.0);
}
