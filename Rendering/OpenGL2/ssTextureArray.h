// Float textures of the pass: GL_TEXTURE_2D_ARRAYs (shadow maps, PVSM tiles
// and tile grid, the visibility layers), their (min, max) mip pyramid, and
// the screen-size vtkTextureObjects (G-buffer, PVSM kernel buffers).
#ifndef ssTextureArray_h
#define ssTextureArray_h

#include "vtkSmartPointer.h"

#include <array>
#include <memory>
#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkTextureObject;

namespace ss
{
/// A GL_TEXTURE_2D_ARRAY: the shadow maps (RG32F linear light-space depth
/// whose mip levels hold the (min, max) of the level below; `Ensure`) or the
/// screen-space visibility layers (R32F, one level; `EnsureScreen`). Not a 3-D
/// texture: those are limited to GL_MAX_3D_TEXTURE_SIZE (2048 on llvmpipe and
/// many GPUs), so a window wider or taller than that had no visibility at all;
/// array layers allow GL_MAX_TEXTURE_SIZE. vtkTextureObject cannot bind 2-D
/// array textures (VTK 9.2): a texture unit is taken from the window's manager
/// and bound by hand.
struct TextureArray
{
  unsigned int Handle = 0;
  int Size = 0; ///< width of a square (shadow-map) array
  int Width = 0, Height = 0, Layers = 0, Levels = 0, Components = 0;

  void Release();
  /// Bytes of all levels (about 4/3 of level 0 with mip levels).
  long long Bytes() const;
  /// size x size RG32F layers with every mip level (shadow maps).
  void Ensure(int size, int layers);
  /// The same at `size` or, where this context cannot allocate that much
  /// (llvmpipe allows 16384^2 but cannot hold such an RG32F array with its
  /// mip levels), at the largest smaller power of two down to 64 that it can.
  /// A size that failed is not tried again until ForgetFailedSize (a new
  /// context). Returns the size allocated, 0 when not even 64 fits.
  int EnsureFitting(int size, int layers);
  void ForgetFailedSize() { this->FailedSize = 0; }
  int FailedSize = 0; ///< the smallest size EnsureFitting failed to allocate (0: none)
  /// width x height R32F layers, one level (the visibility of each light);
  /// false when GL refused them (larger than the implementation allows).
  bool EnsureScreen(int width, int height, int layers);
  /// `comps` 1, 2 or 4: R32F, RG32F or RGBA32F.
  void Allocate(int width, int height, int layers, int levels, int comps);
  /// Reads layer `layer` of level 0 (w x h x Components floats) through `fbo`.
  bool Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, float* out) const;
  /// Binds the array to a free texture unit of `win` and returns the unit (-1: none free).
  int Bind(vtkOpenGLRenderWindow* win) const;
  static void Unbind(vtkOpenGLRenderWindow* win, int unit);
  /// Renders into (level, layer) through the bound FBO.
  void Attach(vtkOpenGLFramebufferObject* fbo, int level, int layer) const;
  static void Detach();
};

/// Levels 1.. of the pyramid of `array` over its [0,w) x [0,h) corner (a
/// virtual PVSM tile uses only part of its texture): mode 0, depth (min, max);
/// mode 1, PVSM's tile grid (min, min) -- see ssMinReduceFS.glsl. `quad`
/// holds the reduction program (built on first use). False when it does not build.
/// `regions` (one [x0, x1) x [y0, y1) per level, in that level's texels):
/// each level is written only there (the scissor; each texel still reads
/// the same four below), and a level whose region is empty is not drawn.
bool BuildDepthPyramid(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo,
  std::unique_ptr<vtkOpenGLQuadHelper>& quad, const TextureArray& array, int w, int h, int mode = 0,
  const std::vector<std::array<int, 4>>* regions = nullptr);

/// A screen-space float texture of `comps` (1, 2 or 4) components, (re)sized.
void EnsureTexture2D(vtkOpenGLRenderWindow* win, vtkSmartPointer<vtkTextureObject>& t, int w, int h, int comps);

/// Reads layer `layer` of a screen-space texture (w x h x comps floats, comps 1 or 4) through `fbo`.
bool ReadTexture(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, vtkTextureObject* tex,
  int layer, int w, int h, int comps, std::vector<float>& out);

/// Bytes of a screen-space texture with `bytesPerTexel` (0 when it holds no GL texture).
long long TextureBytes(vtkTextureObject* t, int bytesPerTexel);
}

#endif
