//VTK::System::Dec
// Linear light-space depth in R and G, min-blended (GL_MIN) so no depth
// buffer is needed; the pyramid above level 0 keeps min in R and max in G.
in float depthLS;
//VTK::Output::Dec
void main()
{
  gl_FragData[0] = vec4(depthLS, depthLS, 0.0, 1.0);
}
