//VTK::System::Dec
// ASM §4.2 and §5 ("an extra rendering and read-back of the scene to gather
// per-polygon ID information"): the caster set seen by the camera, each pixel
// keeping the nearest caster triangle's id and its distance along the view
// direction, so that the query can tell whether a G-buffer pixel lies on
// that triangle.
in vec3 vertexRel;
uniform vec3 casterOffset; // caster-set origin minus frame origin
uniform mat4 relToClip;    // camera: frame-origin-relative world -> clip
uniform vec3 eyeRel;
uniform vec3 viewDir;
out float camDepth;
flat out uint triangleId;
void main()
{
  vec3 p = vertexRel + casterOffset;
  camDepth = dot(p - eyeRel, viewDir);
  triangleId = uint(gl_VertexID / 3) + 1u;
  gl_Position = relToClip * vec4(p, 1.0);
}
