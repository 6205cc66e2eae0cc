// The whole-view shadow maps of a frame: one GL_TEXTURE_2D_ARRAY shared by
// every light that uses shadow maps (hard, PCF, PCSS, PVSM's conservative
// low-resolution map, the map average's per-sample maps), one layer per view,
// RG32F linear light-space depth whose mip levels hold the (min, max) depth of
// the level below: the PCSS blocker search looks at a whole region without
// missing a blocker between samples, and the filters decide coarse quads
// exactly where they can. Filament's ShadowMapManager plays this part there.
#ifndef ssShadowMaps_h
#define ssShadowMaps_h

#include "ssCasterSet.h"
#include "ssGLLimits.h"
#include "ssTextureArray.h"

#include <memory>
#include <string>
#include <vector>

class vtkObject;
class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkOpenGLVertexArrayObject;
class vtkShaderProgram;
class vtkWindow;

namespace ss
{
struct ShadowLight;
struct SolverFrame;

class ShadowMaps
{
public:
  ShadowMaps();
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  /// The map size of the frame: what every light asked for when they agree
  /// (`asked`, one entry per light with maps), else `fallback`; rounded up to
  /// a power of two (every texel of the min pyramid covered) and capped at
  /// `maxTextureSize` (8192 on many GPUs, 16384 on llvmpipe): a larger
  /// request renders at the limit, with a note in the stats and one warning
  /// through `reporter`, instead of failing to allocate.
  int ChooseSize(const std::vector<int>& asked, int fallback, int maxTextureSize, vtkObject* reporter);
  /// `views` layers (at least one) of size^2, or of a smaller power of two
  /// when the context cannot allocate that much (halved down to 64, with a
  /// note and one warning); false with `error` when the GL allows fewer
  /// layers or refuses even 64^2.
  bool Allocate(int size, int views, const GLLimits& limits, std::string& error);

  /// Binds `fbo` (pushing the framebuffer bindings) for drawing maps:
  /// viewport of the map size, no depth test or culling, MIN blending, the
  /// far-away clear colour.
  void BeginDrawing(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo) const;
  /// Clears `light`'s layers (from light.FirstLayer, one per view) and draws
  /// the caster set into each with `program` (vertex array `vao`); with
  /// `ranges` (one per view), only those triangles into each view.
  void DrawViews(const SolverFrame& frame, const ShadowLight& light, vtkShaderProgram* program,
    vtkOpenGLVertexArrayObject* vao, const std::vector<TriangleRanges>* ranges = nullptr) const;
  /// Ends blending, builds every layer's (min, max) pyramid and pops the
  /// bindings; false when the reduction program does not build.
  bool EndDrawing(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo);

  /// The array (its Size, Levels and Bind are what the filters use).
  const TextureArray& GetArray() const { return this->Array; }
  /// Writes into layer (level 0) of the array through the bound FBO.
  void Attach(vtkOpenGLFramebufferObject* fbo, int layer) const { this->Array.Attach(fbo, 0, layer); }
  /// Level 0 of `layer`: size^2 (min, max) pairs, row 0 at the bottom.
  bool Read(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, int layer, float* out) const;
  /// Writes level 0 of `layer` from Size x Size depths (rows from the
  /// bottom), as drawn maps hold them: (depth, depth) per texel. Between
  /// BeginDrawing and EndDrawing, instead of drawing that layer.
  void WriteLayer(vtkOpenGLRenderWindow* win, int layer, const std::vector<float>& depth) const;
  /// Why the maps are smaller than asked (the GL limit), or empty.
  const std::string& GetSizeNote() const { return this->SizeNote; }
  /// A frame without maps: no note.
  void ClearSizeNote() { this->SizeNote.clear(); }

  long long Bytes() const { return this->Array.Bytes(); }
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

private:
  TextureArray Array;
  std::string SizeNote;
  int WarnedSize = 0; ///< the request last warned about (warn once)
  int WarnedAlloc = 0; ///< the size last warned about as not allocatable
  std::unique_ptr<vtkOpenGLQuadHelper> ReduceQuad;
};
}

#endif
