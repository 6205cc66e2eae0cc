//VTK::System::Dec
// Draws the caster set (world-space triangles) into one shadow-map view.
// Light space: origin at the view origin, axes (u, v, n). Perspective views
// project X = (x/z, y/z) (unit plane), orthographic views X = (x, y).
in vec3 vertexRel;
uniform vec3 casterOffset; // caster-set origin minus frame origin (double on the CPU)
uniform vec3 viewOrigin;   // light centre relative to the frame origin
uniform vec3 axisU;
uniform vec3 axisV;
uniform vec3 axisN;
uniform vec4 extent; // x0 y0 x1 y1 of the view in projected units
uniform int orthographic;
out float depthLS;
void main()
{
  vec3 d = vertexRel + casterOffset - viewOrigin;
  float x = dot(d, axisU);
  float y = dot(d, axisV);
  float z = dot(d, axisN);
  depthLS = z;
  float w = (orthographic != 0) ? 1.0 : z;
  // z_clip = 0 keeps every depth inside the clip volume; for perspective views
  // the w >= 0 clip removes what lies behind the light plane (one-sided light).
  gl_Position = vec4((2.0 * x - (extent.x + extent.z) * w) / (extent.z - extent.x),
    (2.0 * y - (extent.y + extent.w) * w) / (extent.w - extent.y), 0.0, w);
}
