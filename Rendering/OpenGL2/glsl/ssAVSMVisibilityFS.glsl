//VTK::System::Dec
// Visibility of one light for every G-buffer pixel from its AVSM: hard AVSM
// (the texel's transmittance at the receiver) or VPCSS (the paper's filter).
// Output 0: V (the mean of the channels for coloured shadows); output 1 (when
// the light has a colour layer): RGB. Built for one of the two
// (ssTranslucentSolver defines AVSM_HARD, AVSM_FILTERED and AVSM_COLORED).
uniform int hardAVSM;
uniform sampler2DArray avsmTex;
in vec2 texCoord; // from VTK's full-screen quad
//VTK::Output::Dec
//SS::Common
vec4 avsmFetch(ivec3 p, int level)
{
  return texelFetch(avsmTex, p, level);
}
//SS::AVSMLookup

void main()
{
  ivec2 pix = ivec2(floor(texCoord * vec2(textureSize(gPosition, 0))));
  vec4 g = texelFetch(gPosition, pix, 0);
  if (g.w <= 0.0)
  {
    gl_FragData[0] = vec4(-1.0); // background: NaN on download
    gl_FragData[1] = vec4(-1.0);
    return;
  }
  vec3 nrm = texelFetch(gNormal, pix, 0).xyz;
  vec3 ng = receiverNormal(pix, nrm); // the receiver's facet (ssShadowCommon)
  vec3 d = g.xyz - lightCenter;
  vec3 dLookup = d; // moved along ng by the normal offset
  View w = selectReceiverView(dLookup, ng);
  vec3 T;
  if (w.index < 0)
  {
    T = vec3(outsideViewsVisibility(d));
  }
  else
  {
    // the terminator (ssShadowCommon): hard AVSM from the light's centre
    float above = avsmAboveSurface(normalize(nrm), ng, d, hardAVSM);
    T = avsmVisibility(w, (dot(ng, ng) > 0.5) ? ng : nrm, dLookup, hardAVSM) * above;
  }
  T = clamp(T, 0.0, 1.0);
  float V = avsmIsColored ? (T.x + T.y + T.z) / 3.0 : T.x;
  gl_FragData[0] = vec4(V, 0.0, 0.0, 1.0);
  gl_FragData[1] = vec4(avsmIsColored ? T : vec3(V), 1.0);
}
