//VTK::System::Dec
// ASM node pages (Fernando et al. 2001 §3, §4.2): the caster set drawn into
// one node's window of a light view (ssCasterVS with the triangle id added,
// ssASMSolver.cxx). A texel keeps the nearest caster (depth test on
// gl_FragDepth) as its light-space depth in 32-bit fixed point of the view's
// depth range, and that caster's triangle id + 1 for the ID test.
in float depthLS;
flat in uint triangleId;
uniform float depthScale; // 1 / the view's largest depth
out uvec4 nodeTexel;
void main()
{
  float d = clamp(depthLS * depthScale, 0.0, 1.0);
  gl_FragDepth = d;
  // 4294967040 = 2^32 - 256: the largest float below 2^32
  nodeTexel = uvec4(uint(d * 4294967040.0), triangleId, 0u, 0u);
}
