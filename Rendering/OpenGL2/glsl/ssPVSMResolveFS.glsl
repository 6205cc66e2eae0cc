//VTK::System::Dec
// PVSM: the light's visibility from the merged sums, V = (V·A) / A (§5.2),
// times the fraction of the light above the tangent plane; pixels decided in
// the kernel pass (fully lit, behind the light, outside the views) keep
// their value. A kernel no tile saw (nothing drawn there) is lit.
uniform sampler2D kernel0;
uniform sampler2D kernel1;
uniform sampler2D accum;
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(kernel0, 0))));
  vec4 k0 = texelFetch(kernel0, pix, 0);
  vec4 k1 = texelFetch(kernel1, pix, 0);
  if (k0.w < 0.0)
  {
    gl_FragData[0] = vec4(-1.0); // background: NaN on download
    return;
  }
  float V = k1.w;
  if (k0.w == 1.0)
  {
    vec3 acc = texelFetch(accum, pix, 0).rgb;
    float reach = (acc.y > 0.0) ? clamp(acc.x / acc.y, 0.0, 1.0) : 1.0;
    V *= min(reach, 1.0 - clamp(acc.z, 0.0, 1.0));
  }
  gl_FragData[0] = vec4(V, 0.0, 0.0, 1.0);
}
