// PVSM §5.2 steps 7-8: what of each tile the filter pass can read, and which
// pixels read it. A tile's shadow map is used only by the pixels whose kernel
// reaches it (ssPVSMFilterFS.glsl), and each of them reads only the quads of
// its kernel's box. So a tile needs to be cleared, drawn and reduced only
// where those reads fall, and filtered only over those pixels' screen box; a
// tile no pixel reaches needs nothing. Computed on the CPU from the kernel
// buffer (kernel0, kernel1 as read back), conservatively: every texel the GPU
// may read lies in the region, every pixel it may filter in the box, so
// neither the tile maps where they are read nor V change.
#ifndef ssPVSMTileReads_h
#define ssPVSMTileReads_h

#include <array>
#include <cstddef>
#include <vector>

namespace ss
{
/// One tile as the filter pass sees it (the uniforms tileRect, tileRes,
/// tileLevels of ssPVSMFilterFS.glsl).
struct TileReadInput
{
  double rect[4] = { 0, 0, 0, 0 }; ///< shadow-map extent (x0, y0, x1, y1); used as float, as the uniform
  int resX = 0, resY = 0;          ///< texels of the tile
  int levels = 1;                  ///< the shader's tileLevels: quads of up to 2^(levels-1) texels
};

/// A region [x0, x1) x [y0, y1) of one pyramid level's texels; empty when x0 >= x1 or y0 >= y1.
using LevelRegion = std::array<int, 4>;

/// What the filter pass can read of one tile, and from which pixels.
struct TileReadRegion
{
  std::size_t pixels = 0; ///< pixels whose kernel may reach the tile (their kernel box meets it)
  int screen[4] = { 0, 0, -1, -1 }; ///< their box in pixels, inclusive (x0, y0, x1, y1); empty when x1 < x0
  /// Per pyramid level l (level l has ceil(res / 2^l) texels a side): the
  /// texels a read at level l or above depends on. Reads at a level are
  /// nested in those of the level below (each texel's four children are in
  /// the region below), so a pyramid built only there, from a tile drawn only
  /// in levels[0], has every value that is read.
  std::vector<LevelRegion> levels;
  bool Reached() const { return this->pixels > 0; }
  /// texels of levels[0]
  double Texels() const;
};

/// The kernel buffer (RGBA float per pixel, rows bottom-up as glReadPixels
/// gives them): kernel0 = (u.x, u.y, v.y, state) with state 1 for a pixel the
/// tiles filter, kernel1 = (centre.x, centre.y, view, -) in shadow-map units.
struct KernelBuffer
{
  const float* kernel0 = nullptr;
  const float* kernel1 = nullptr;
  int width = 0, height = 0;
};

/// For each tile of `view`: the pixels whose kernel box (ssPVSMFilterFS's
/// discard test) meets it, and the texels their quads (of 2^l texels, l
/// chosen as the shader does from maxQuads) can read, per level of a pyramid
/// of `pyramidLevels` levels. A pixel whose kernel is not finite may read
/// anything: the whole tile, every level. Runs in parallel over rows.
std::vector<TileReadRegion> PVSMTileReads(
  const KernelBuffer& kernels, int view, const std::vector<TileReadInput>& tiles, int maxQuads, int pyramidLevels);
}

#endif
