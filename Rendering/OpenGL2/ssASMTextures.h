// ASM's GPU objects (Fernando et al. 2001 §3; Documentation/asm.md): the
// atlas whose pages hold the tree's nodes, the node table the query shader
// walks, the target one node is rendered into before it is copied to its
// page, the camera-view triangle ids (§4.2) and the per-pixel edge flags the
// analysis reads back (§3.1). Raw GL textures with integer formats:
// vtkTextureObject has no integer 2-D array textures in VTK 9.2.
#ifndef ssASMTextures_h
#define ssASMTextures_h

#include "ssASMTree.h"

#include "vtkSmartPointer.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;
class vtkWindow;

namespace ss
{
class ASMTextures
{
public:
  /// The atlas (RG32UI 2-D array: depth in 32-bit fixed point, triangle id +
  /// 1) laid out by `layout`, and its summary (R32F, the same layout with
  /// pages of `summarySize`^2: the nearest caster depth per block of texels,
  /// conservatively rasterised); false with `error` when GL refuses them.
  bool EnsureAtlas(const ASMAtlasLayout& layout, int pageSize, int summarySize, std::string& error);
  /// The targets of one node: RG32UI and a 32-bit float depth buffer of P^2,
  /// and the R32F summary of `summarySize`^2.
  bool EnsureScratch(int pageSize, int summarySize);
  /// The camera-view ids (RG32UI), their depth buffer and the edge flags (R8).
  bool EnsureScreen(int width, int height);
  /// The tree as the query shader reads it (RGBA32I): per node (page x, page
  /// y, layer, resolution) and its C*C children, -1 where a cell is empty or
  /// its node not yet rendered. Uploaded when the tree's version changed.
  void UploadNodeTable(const ASMTree& tree, int maxTextureSize);

  /// Binds the render target: `fbo` (pushing the window's framebuffer
  /// bindings) with `color` (a 2-D texture, or layer `layer` of a 2-D array)
  /// on attachment 0 and `depth` on the depth attachment (0: none).
  void Begin(vtkOpenGLRenderWindow* win, unsigned int color, int layer, unsigned int depth);
  /// Begin on a w x h corner of an unsigned `color` target with a depth
  /// buffer: viewport and scissor set, color cleared to `clear`, depth to 1.
  void BeginCleared(vtkOpenGLRenderWindow* win, unsigned int color, unsigned int depth, int w, int h,
    const unsigned int clear[4]);
  void End(vtkOpenGLRenderWindow* win);
  /// Copies the bound scratch target's corner of `res`^2 into page `page`
  /// of the atlas (`summary` false) or of the summary.
  void CopyScratchToPage(int page, int res, bool summary = false);
  /// The edge flags of the last query pass (attachment 1 of the bound target).
  void ReadEdges(std::vector<std::uint8_t>& out);

  /// A free texture unit of `win` with `handle` bound to `target`; -1 when none.
  static int Bind(vtkOpenGLRenderWindow* win, unsigned int target, unsigned int handle);
  static void Unbind(vtkOpenGLRenderWindow* win, unsigned int target, int unit);

  long long AtlasBytes() const;
  long long Bytes() const;
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

  unsigned int Atlas = 0, Summary = 0, Scratch = 0, ScratchDepth = 0, SummaryScratch = 0, Ids = 0, IdDepth = 0,
               Edges = 0, Nodes = 0;
  ASMAtlasLayout Layout;
  int PageSize = 0, SummarySize = 0, ScratchSize = 0, SummaryScratchSize = 0;
  int Width = 0, Height = 0;
  int NodeWidth = 0, NodesPerRow = 1, NodeRows = 0, NodeTableWidth = 0;
  unsigned long long UploadedVersion = 0;
  vtkSmartPointer<vtkOpenGLFramebufferObject> FBO;
};
}

#endif
