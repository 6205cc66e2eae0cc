//VTK::System::Dec
// See ssASMIdVS.glsl: (triangle id + 1, camera depth in 32-bit fixed point of
// camDepthScale), nearest by the depth test.
in float camDepth;
flat in uint triangleId;
uniform float camDepthScale;
out uvec4 idTexel;
void main()
{
  idTexel = uvec4(triangleId, uint(clamp(camDepth * camDepthScale, 0.0, 1.0) * 4294967040.0), 0u, 0u);
}
