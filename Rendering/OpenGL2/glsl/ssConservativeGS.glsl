//VTK::System::Dec
// PVSM §5.2 step 2: conservative rasterisation of the low-resolution shadow
// map (Hasselgren, Akenine-Möller & Ohlsson, GPU Gems 2 ch. 42, second
// algorithm): each triangle is enlarged so that every texel it touches has
// its centre inside, and the fragment shader discards what lies outside the
// triangle's bounding box grown by half a texel. Thin geometry (a bar 0.1
// texel wide) thus keeps its texels, so the blocker search never misses it.
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out; // 3, or the 4 corners of a degenerate triangle's box
in float depthLS[];
uniform vec2 viewportSize;
uniform int orthographic;
noperspective out vec2 ndcPos;
noperspective out float depthLinear; // z (orthographic) or 1/z (perspective): linear on screen
smooth out float depthSmooth;        // the plain interpolated depth (pass-through triangles)
flat out vec4 bbox;                  // NDC x0 y0 x1 y1, grown by half a texel
flat out vec2 depthRange;            // the triangle's (min, max) depth
flat out int mode;                   // 0 pass-through, 1 enlarged, 2 degenerate (its min depth)

float cross2(vec2 a, vec2 b)
{
  return a.x * b.y - a.y * b.x;
}

// One output vertex with its attributes (range: the triangle's (min, max) depth).
void emit(vec4 pos, vec2 ndc, float linear, float smoothDepth, vec4 box, vec2 range, int m)
{
  gl_Position = pos;
  ndcPos = ndc;
  depthLinear = linear;
  depthSmooth = smoothDepth;
  bbox = box;
  depthRange = range;
  mode = m;
  EmitVertex();
}

void main()
{
  vec4 P[3] = vec4[3](gl_in[0].gl_Position, gl_in[1].gl_Position, gl_in[2].gl_Position);
  float zmin = min(depthLS[0], min(depthLS[1], depthLS[2]));
  float zmax = max(depthLS[0], max(depthLS[1], depthLS[2]));
  vec2 hp = vec2(1.0) / viewportSize; // half a texel in NDC
  if (!(P[0].w > 0.0 && P[1].w > 0.0 && P[2].w > 0.0))
  {
    // crosses the light plane: clipping decides; drawn as is (not enlarged)
    for (int i = 0; i < 3; ++i)
    {
      emit(P[i], vec2(0.0), 0.0, depthLS[i], vec4(-1e30, -1e30, 1e30, 1e30), vec2(zmin, zmax), 0);
    }
    EndPrimitive();
    return;
  }
  vec2 v[3];
  float a[3];
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  for (int i = 0; i < 3; ++i)
  {
    v[i] = P[i].xy / P[i].w;
    a[i] = (orthographic != 0) ? depthLS[i] : 1.0 / depthLS[i];
    lo = min(lo, v[i]);
    hi = max(hi, v[i]);
  }
  vec4 box = vec4(lo - hp, hi + hp);
  float area = cross2(v[1] - v[0], v[2] - v[0]);
  float s = area >= 0.0 ? 1.0 : -1.0;
  // edge i runs v[i] -> v[i+1]; its outward line n.x = c moved out by the
  // half-texel box's support |n.x| hp.x + |n.y| hp.y
  vec2 n[3];
  float c[3];
  bool ok = abs(area) > 1e-12 * max(1.0, dot(hi - lo, hi - lo));
  for (int i = 0; i < 3; ++i)
  {
    vec2 e = v[(i + 1) % 3] - v[i];
    n[i] = s * vec2(e.y, -e.x);
    c[i] = dot(n[i], v[i]) + abs(n[i].x) * hp.x + abs(n[i].y) * hp.y;
  }
  vec2 q[3];
  for (int i = 0; i < 3 && ok; ++i)
  {
    // the new vertex i: where the moved lines of edges i-1 and i meet
    vec2 n0 = n[(i + 2) % 3], n1 = n[i];
    float det = cross2(n0, n1);
    if (abs(det) <= 1e-20)
    {
      ok = false;
      break;
    }
    float c0 = c[(i + 2) % 3], c1 = c[i];
    q[i] = vec2(c0 * n1.y - c1 * n0.y, n0.x * c1 - n1.x * c0) / det;
  }
  if (!ok)
  {
    // degenerate in the map (a sliver or a point): its grown bounding box,
    // at its nearest depth, as one strip of its 4 corners (two triangles of 3
    // would be 6 vertices, past max_vertices: the second half would be lost)
    vec2 qq[4] = vec2[4](box.xy, vec2(box.z, box.y), vec2(box.x, box.w), box.zw);
    for (int i = 0; i < 4; ++i)
    {
      emit(vec4(qq[i], 0.0, 1.0), qq[i], 0.0, zmin, box, vec2(zmin, zmax), 2);
    }
    EndPrimitive();
    return;
  }
  for (int i = 0; i < 3; ++i)
  {
    // the depth attribute extrapolated to the new vertex (barycentric in the
    // original triangle; exact for a plane since it is linear on screen)
    float b1 = cross2(q[i] - v[0], v[2] - v[0]) / area;
    float b2 = cross2(v[1] - v[0], q[i] - v[0]) / area;
    emit(vec4(q[i], 0.0, 1.0), q[i], (1.0 - b1 - b2) * a[0] + b1 * a[1] + b2 * a[2], zmin, box, vec2(zmin, zmax), 1);
  }
  EndPrimitive();
}
