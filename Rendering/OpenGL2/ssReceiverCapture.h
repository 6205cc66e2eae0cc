// The capture of the translucent receivers' V (vtkSoftShadowPass::
// SetCaptureTranslucentReceivers; tests and diagnostics). Translucent props
// are not in the G-buffer: their fragments compute V in the shading stage
// (ssTranslucentReceivers), so no visibility layer holds it. With a capture
// light set, the shading code of translucent receivers also stores, per
// pixel, the V that light's solver gave the fragment drawn there last, with
// the fragment's position (relative to the frame origin) and the normal of
// the plane its filter used, into two RGBA32F image layers; the reference can
// then be computed at exactly those points (ss::ReferenceSolver). The code is
// in the shaders only while a capture light is set (it needs image stores:
// GL 4.2 or GL_ARB_shader_image_load_store).
#ifndef ssReceiverCapture_h
#define ssReceiverCapture_h

#include "ssTextureArray.h"

#include <string>
#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;
class vtkShaderProgram;

namespace ss
{
class ReceiverCapture
{
public:
  /// The shading code's declarations and the store of one fragment
  /// (ssCaptureFragment(layer, V, p, n)); a no-op function when `enabled` is false.
  static std::string Code(bool enabled);

  /// Before the shading stage: the image (width x height, cleared to NaN)
  /// bound to an image unit for `layer` (the shadow light's visibility
  /// layer). False when GL has no image stores.
  bool Begin(vtkOpenGLRenderWindow* win, int width, int height, int layer, std::string& error);
  /// The capture uniforms of one draw (the image unit and the layer; -1: off).
  void SetUniforms(vtkShaderProgram* program) const;
  /// After the shading stage: unbinds the image and makes its stores visible.
  void End();

  /// What the last capture stored: V (1 per pixel), positions and normals
  /// (3 per pixel), NaN where no translucent receiver was drawn. False
  /// without a capture.
  bool Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, std::vector<float>& V,
    std::vector<float>& positions, std::vector<float>& normals) const;

  long long Bytes() const { return this->Image.Bytes(); }
  int CountGraphicsResources() const { return this->Image.Handle != 0 ? 1 : 0; }
  void ReleaseGraphicsResources() { this->Image.Release(); this->Layer = -1; this->Captured = false; }

private:
  TextureArray Image; ///< layer 0: position xyz, V; layer 1: normal xyz, 1
  int Layer = -1;     ///< the visibility layer captured (-1: none this frame)
  bool Captured = false;
};
}

#endif
