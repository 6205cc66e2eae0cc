//VTK::System::Dec
// PVSM §5.2 step 4: the shadow map tile grid. One point per screen pixel
// (no attributes: gl_VertexID is the pixel), min-blended into the G x G grid:
// each cell keeps the smallest predicted texel size per axis. The paper
// splats the pixel's own cell; the point here covers every cell the kernel's
// bounding box touches, so a kernel reaching into a cell no pixel projects to
// still finds a tile there.
uniform sampler2D kernel0;
uniform sampler2D kernel1;
uniform sampler2D kernel2;
uniform int screenWidth;
uniform int view;
uniform vec4 extent;      // the view's shadow-map extent
uniform float gridSize;
uniform float maxPointSize;
flat out vec2 texelSize;
void main()
{
  ivec2 pix = ivec2(gl_VertexID % screenWidth, gl_VertexID / screenWidth);
  vec4 k0 = texelFetch(kernel0, pix, 0);
  vec4 k1 = texelFetch(kernel1, pix, 0);
  texelSize = texelFetch(kernel2, pix, 0).xy;
  gl_PointSize = 1.0;
  if (k0.w != 1.0 || int(k1.z) != view)
  {
    gl_Position = vec4(2.0, 2.0, 0.0, 1.0); // clipped
    return;
  }
  vec2 toGrid = vec2(gridSize) / (extent.zw - extent.xy);
  vec2 g = (k1.xy - extent.xy) * toGrid;
  vec2 halfSize = vec2(abs(k0.x), abs(k0.y) + abs(k0.z)) * toGrid;
  vec2 lo = floor(g - halfSize);
  vec2 hi = floor(g + halfSize);
  gl_PointSize = min(max(hi.x - lo.x, hi.y - lo.y) + 1.0, maxPointSize);
  gl_Position = vec4(0.5 * (lo + hi + 1.0) / gridSize * 2.0 - 1.0, 0.0, 1.0);
}
