//VTK::System::Dec
// PVSM §5.2 step 4 (see ssPVSMGridVS.glsl): min blending keeps each cell's
// smallest texel size.
flat in vec2 texelSize;
//VTK::Output::Dec
void main()
{
  gl_FragData[0] = vec4(texelSize, 0.0, 1.0);
}
