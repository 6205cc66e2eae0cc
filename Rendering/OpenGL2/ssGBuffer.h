// The G-buffer (DESIGN.md "one data flow", first stage): the opaque props
// drawn through their own VTK mappers into float targets holding the world
// position relative to the frame origin with the prop id, and the world
// normal. Every solver reads it; the shading stage looks up the prop id.
#ifndef ssGBuffer_h
#define ssGBuffer_h

#include "vtkSmartPointer.h"

#include <map>
#include <string>
#include <vector>

class vtkCamera;
class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;
class vtkProp;
class vtkRenderer;
class vtkShaderProgram;
class vtkTextureObject;
class vtkWindow;

namespace ss
{
struct FrameState;

class GBuffer
{
public:
  vtkSmartPointer<vtkTextureObject> Position; ///< RGBA32F: position - origin, prop id (0: background)
  vtkSmartPointer<vtkTextureObject> Normal;   ///< RGBA32F: world (shading) normal, 1 where written
  /// RGBA32F: the world normal of the drawn triangle's plane, on the side of
  /// the shading normal; w 1 where the triangle had an area on screen.
  vtkSmartPointer<vtkTextureObject> GeometricNormal;
  /// Colour targets the G-buffer stage writes (position, normal, geometric normal).
  static constexpr int NumberOfTargets = 3;
  vtkSmartPointer<vtkTextureObject> Depth;

  /// Sizes the targets to the frame, computes the camera transforms the
  /// injected code uses, and binds and clears the targets on `fbo` (pushing
  /// the framebuffer bindings). The caller then draws the opaque props.
  void Begin(vtkRenderer* ren, vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, const FrameState& frame);
  /// Detaches the targets and pops the framebuffer bindings.
  void End(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo);

  /// The G-buffer stage's code in a polydata mapper's fragment shader: the
  /// outputs are written at the end of main() (`mainPos`: where "void main"
  /// starts, `endPos`: its closing brace).
  static void InjectOutputs(std::string& fragmentShader, std::size_t mainPos, std::size_t endPos);
  /// The uniforms of that code for `prop` (a new prop gets the next id).
  void SetShaderParameters(vtkShaderProgram* program, vtkProp* prop, int width, int height);
  /// The camera transform of the frame (view coordinates to world relative
  /// to the frame origin: ssVCToWC, ssVCToRelOffset), for code that places
  /// fragments in the world.
  void SetCameraUniforms(vtkShaderProgram* program) const;
  /// The id `prop` was drawn with into the G-buffer, 0 if it never was.
  int FindPropId(vtkProp* prop) const;

  /// Level 0 of the position (which = 0), normal (1) or geometric normal (2) target,
  /// w x h x 4 floats, row 0 at the bottom.
  bool Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int which, int w, int h,
    std::vector<float>& rgba) const;
  /// Positions (background NaN) and normals, 3 floats a pixel, for solvers
  /// that run on the CPU; read once per G-buffer.
  bool ReadForCPU(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int w, int h,
    const std::vector<float>*& positions, const std::vector<float>*& normals);

  long long Bytes() const;
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

private:
  float VCToWC[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  float VCToRelOffset[3] = { 0, 0, 0 };
  float DCToVC[16] = { 0 };
  std::map<vtkProp*, int> PropIds;
  bool HaveCPUCopy = false;
  std::vector<float> CPUPositions, CPUNormals;
};
}

#endif
