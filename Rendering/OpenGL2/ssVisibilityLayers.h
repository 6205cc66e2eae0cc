// The visibility buffer (DESIGN.md: the contract between solvers and
// shading): one R32F layer per shadow-casting light, V(x, y) in [0, 1] on the
// G-buffer's foreground and -1 on the background. Solvers write their light's
// layer; the shading stage reads it; GetVisibilityImage reads it back.
#ifndef ssVisibilityLayers_h
#define ssVisibilityLayers_h

#include "ssGLLimits.h"
#include "ssTextureArray.h"

#include <string>
#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;

namespace ss
{
class VisibilityLayers
{
public:
  /// `layers` layers of width x height; false with `error` beyond the GL's
  /// limits or when it refuses the texture.
  bool Allocate(int width, int height, int layers, const GLLimits& limits, std::string& error);
  /// Renders into `layer` through the bound FBO (one draw buffer).
  void Attach(vtkOpenGLFramebufferObject* fbo, int layer) const;
  /// Writes V computed on the CPU (width x height floats, NaN on the
  /// background) into `layer`.
  void Upload(int layer, std::vector<float>& V) const;
  /// Level 0 of `layer` (width x height floats, -1 on the background).
  bool Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, std::vector<float>& out) const;
  int GetWidth() const { return this->Array.Width; }
  int GetHeight() const { return this->Array.Height; }

  /// RGB visibility (coloured shadows): `layers` RGBA32F layers of the
  /// same size for the lights whose solver writes colour (0: none, freed).
  bool AllocateColor(int layers, const GLLimits& limits, std::string& error);
  /// Renders V into `layer` (draw buffer 0) and RGB into colour layer
  /// `colorLayer` (draw buffer 1) through the bound FBO.
  void AttachWithColor(vtkOpenGLFramebufferObject* fbo, int layer, int colorLayer) const;
  /// Level 0 of colour layer `colorLayer`: width x height x 3 floats (RGB),
  /// NaN on the background.
  bool ReadColor(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int colorLayer,
    std::vector<float>& out) const;

  /// Binds the layers for the shading stage (texture units of `win`).
  void BindForShading(vtkOpenGLRenderWindow* win);
  void UnbindAfterShading(vtkOpenGLRenderWindow* win);
  /// The texture unit while shading, -1 otherwise.
  int GetShadingUnit() const { return this->Unit; }
  /// The colour layers' unit while shading (V's unit when there are none).
  int GetColorShadingUnit() const { return this->ColorUnit >= 0 ? this->ColorUnit : this->Unit; }

  long long Bytes() const { return this->Array.Bytes() + this->Color.Bytes(); }
  int CountGraphicsResources() const { return (this->Array.Handle != 0 ? 1 : 0) + (this->Color.Handle != 0 ? 1 : 0); }
  void ReleaseGraphicsResources()
  {
    this->Array.Release();
    this->Color.Release();
  }

private:
  TextureArray Array;
  TextureArray Color;
  int Unit = -1;
  int ColorUnit = -1;
};
}

#endif
