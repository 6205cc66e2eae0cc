//VTK::System::Dec
// PVSM §5.2 step 2, fragment half of the conservative rasterisation: drop
// fragments outside the grown bounding box, write the depth clamped to the
// triangle's range (the enlarged triangle extrapolates it). Min-blended as
// in ssCasterFS.glsl.
noperspective in vec2 ndcPos;
noperspective in float depthLinear;
smooth in float depthSmooth;
flat in vec4 bbox;
flat in vec2 depthRange;
flat in int mode;
uniform int orthographic;
//VTK::Output::Dec
void main()
{
  if (ndcPos.x < bbox.x || ndcPos.y < bbox.y || ndcPos.x > bbox.z || ndcPos.y > bbox.w)
  {
    discard;
  }
  float z = depthSmooth;
  if (mode == 1)
  {
    z = (orthographic != 0) ? depthLinear : 1.0 / max(depthLinear, 1e-30);
  }
  else if (mode == 2)
  {
    z = depthRange.x;
  }
  z = clamp(z, depthRange.x, depthRange.y);
  gl_FragData[0] = vec4(z, z, 0.0, 1.0);
}
