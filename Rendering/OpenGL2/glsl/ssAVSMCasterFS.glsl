#version 430 core
// Fragments of the caster set in one AVSM view (ssAVSMCasterVS.glsl).
// Pass 0: the opaque depth (R, min-blended). Pass 1: count the translucent
// fragments in front of the texel's nearest opaque one. Pass 2: store them
// (depth and transmittance) at the texel's list offset plus an atomic
// cursor. The same triangles are rasterised the same way in passes 1 and 2
// (GL's invariance rules), so each list gets exactly its counted fragments;
// a store past the count is dropped all the same. Colour writes are masked
// in passes 1 and 2; nothing is discarded after a buffer write.
in float depthLS;
in vec4 look;
in vec3 uv;
uniform int pass;
uniform int mapSize;
uniform int coloured;     // 1: RGB transmittance (ss::ColoredTransmittance)
uniform int view;         // layer of the opaque map
uniform int fragCapacity; // entries the fragment buffer holds
uniform sampler2DArray opaqueMap;
uniform sampler2D alphaTex0;
uniform sampler2D alphaTex1;
uniform sampler2D alphaTex2;
uniform sampler2D alphaTex3;
layout(std430, binding = 0) buffer Counts { uint counts[]; };
layout(std430, binding = 1) buffer Local { uint local[]; };
layout(std430, binding = 3) buffer RowStart { uint rowStart[]; };
layout(std430, binding = 4) buffer Cursor { uint cursor[]; };
layout(std430, binding = 6) buffer Frags { vec4 frags4[]; };
layout(std430, binding = 7) buffer Frags2 { vec2 frags2[]; };
layout(location = 0) out vec4 fragOut;

vec4 alphaTexel(int i, vec2 st)
{
  if (i == 0)
  {
    return texture(alphaTex0, st);
  }
  if (i == 1)
  {
    return texture(alphaTex1, st);
  }
  if (i == 2)
  {
    return texture(alphaTex2, st);
  }
  return texture(alphaTex3, st);
}

void main()
{
  fragOut = vec4(depthLS, depthLS, 0.0, 1.0);
  if (pass == 0)
  {
    return;
  }
  float alpha = look.x;
  vec3 color = look.yzw;
  if (uv.z >= 0.0)
  {
    vec4 s = alphaTexel(int(uv.z + 0.5), uv.xy);
    alpha *= s.a;
    color *= s.rgb;
  }
  ivec2 t = ivec2(gl_FragCoord.xy);
  if (alpha <= 0.0 || !(depthLS < texelFetch(opaqueMap, ivec3(t, view), 0).r))
  {
    return;
  }
  uint idx = uint(t.y) * uint(mapSize) + uint(t.x);
  if (pass == 1)
  {
    atomicAdd(counts[idx], 1u);
    return;
  }
  uint slot = atomicAdd(cursor[idx], 1u);
  if (slot >= counts[idx])
  {
    return;
  }
  uint at = rowStart[t.y] + local[idx] + slot;
  if (at >= uint(fragCapacity))
  {
    return; // a row with more fragments than the buffer holds (ssAVSMMaps reports it)
  }
  alpha = clamp(alpha, 0.0, 1.0);
  if (coloured != 0)
  {
    // ss::ColoredTransmittance
    vec3 c = clamp(color, 0.0, 1.0);
    float m = max(c.x, max(c.y, c.z));
    vec3 k = m > 1e-6 ? c / m : vec3(1.0);
    frags4[at] = vec4(depthLS, (1.0 - alpha) * (vec3(1.0) - alpha * (vec3(1.0) - k)));
  }
  else
  {
    frags2[at] = vec2(depthLS, 1.0 - alpha);
  }
}
