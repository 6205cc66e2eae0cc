#version 430 core
// The caster set into one AVSM view (ssAVSMMaps.cxx), the light space of
// ssCasterVS.glsl. Pass 0 draws the opaque casters (the nearest opaque depth
// per texel, min-blended); passes 1 and 2 the translucent ones (count, then
// store the fragments). A triangle of the other kind is moved outside the
// clip volume, so the rasteriser never sees it.
in vec3 vertexRel;
in vec4 avsmLook; // opacity, colour
in vec3 avsmUV;   // texture coordinates and the alpha texture's index (-1: none)
uniform vec3 casterOffset; // caster-set origin minus frame origin
uniform vec3 viewOrigin;
uniform vec3 axisU;
uniform vec3 axisV;
uniform vec3 axisN;
uniform vec4 extent;
uniform int orthographic;
uniform int pass; // 0 opaque, 1 count, 2 store
out float depthLS;
out vec4 look;
out vec3 uv;
void main()
{
  bool opaque = avsmLook.x >= 1.0 && avsmUV.z < 0.0;
  if ((pass == 0) != opaque || avsmLook.x <= 0.0)
  {
    gl_Position = vec4(2.0, 2.0, 0.0, 1.0); // outside: not this pass's caster
    depthLS = 0.0;
    look = vec4(0.0);
    uv = vec3(0.0);
    return;
  }
  vec3 d = vertexRel + casterOffset - viewOrigin;
  float x = dot(d, axisU);
  float y = dot(d, axisV);
  float z = dot(d, axisN);
  depthLS = z;
  look = avsmLook;
  uv = avsmUV;
  float w = (orthographic != 0) ? 1.0 : z;
  gl_Position = vec4((2.0 * x - (extent.x + extent.z) * w) / (extent.z - extent.x),
    (2.0 * y - (extent.y + extent.w) * w) / (extent.w - extent.y), 0.0, w);
}
