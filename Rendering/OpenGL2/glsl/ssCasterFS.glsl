//VTK::System::Dec
// Linear light-space depth, min-blended (GL_MIN) so no depth buffer is needed.
in float depthLS;
//VTK::Output::Dec
void main()
{
  gl_FragData[0] = vec4(depthLS, 0.0, 0.0, 1.0);
}
