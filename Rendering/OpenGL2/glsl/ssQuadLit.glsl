// Used by the visibility shader (pasted where it says //SS::QuadLit, after
// it defined the three map hooks):
//   float mapTexelLit(View w, ivec2 t, float bias, float maxDelta)  shadow test of texel t
//   vec2 mapMinMax(View w, ivec2 q, int level)                       (min, max) depth of quad q
//   vec2 mapPlaneRange(View w, vec2 a, float s, float maxDelta)      receiver plane's (min, max)
//                                                                    over the quad [a, a + s]^2
// Lit fraction of the quad q of 2^level texels. The (min, max) depth of the
// quad decides it exactly when the receiver (its tangent plane over the
// quad, minus the bias) is nearer than every texel (lit) or farther than every
// texel (occluded); otherwise its four children are classified the same way
// and a child still undecided takes the test of its centre texel. Coarse quads
// thus stay exact where the shadow is uniform, and no fixed sampling lattice
// shows in wide penumbrae (one centre sample per coarse quad did).
// The depth bias scales with the quad's size in texels: a quad of s texels
// samples the map as a map s times coarser would, and the receiver's surface
// departs from its tangent plane over that size, not over one texel. With a
// one-texel bias, fine PVSM tiles under wide kernels let a faceted surface
// shadow itself (acne growing with the tile resolution; iso close-up MAE
// 0.051 -> 0.015 with this alone). Level 0 keeps the one-texel bias, so
// contact shadows (small kernels) are unchanged.
float quadLit(View w, int level, ivec2 q, float bias, float maxDelta)
{
  if (level == 0)
  {
    return mapTexelLit(w, q, bias, maxDelta);
  }
  float s = exp2(float(level));
  vec2 z = mapPlaneRange(w, vec2(q) * s, s, maxDelta) - bias * s;
  vec2 mm = mapMinMax(w, q, level);
  if (z.y <= mm.x)
  {
    return 1.0;
  }
  if (z.x > mm.y)
  {
    return 0.0;
  }
  float h = 0.5 * s;
  float sum = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    ivec2 child = 2 * q + ivec2(c & 1, c >> 1);
    vec2 b = vec2(child) * h;
    vec2 cz = mapPlaneRange(w, b, h, maxDelta) - bias * h;
    vec2 cm = mapMinMax(w, child, level - 1);
    if (cz.y <= cm.x)
    {
      sum += 1.0;
    }
    else if (cz.x <= cm.y)
    {
      // undecided: the test of the child's centre texel
      sum += mapTexelLit(w, ivec2(b + 0.5 * h), bias * h, maxDelta);
    }
  }
  return 0.25 * sum;
}
