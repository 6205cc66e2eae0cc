// The GL implementation's limits the pass sizes its textures and buffers by,
// queried from the current context instead of assumed. Machines differ:
// llvmpipe allows 16384^2 textures and 128 MB storage blocks, many GPUs 8192^2
// or 2 GB. Environment variables can lower (never raise) each limit, so the
// paths a smaller GPU takes are testable on this one:
//   SOFTSHADOWS_GL_MAX_TEXTURE_SIZE, SOFTSHADOWS_GL_MAX_ARRAY_TEXTURE_LAYERS,
//   SOFTSHADOWS_GL_MAX_SSBO_BYTES, SOFTSHADOWS_GL_MAX_SSBO_BINDINGS.
#ifndef ssGLLimits_h
#define ssGLLimits_h

#include <cstdint>

namespace ss
{
struct GLLimits
{
  int maxTextureSize = 0;        ///< GL_MAX_TEXTURE_SIZE
  int maxArrayTextureLayers = 0; ///< GL_MAX_ARRAY_TEXTURE_LAYERS
  std::int64_t maxSSBOBytes = 0; ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE (0: no SSBOs)
  int maxSSBOBindings = 0;       ///< GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS (GL 4.3 guarantees 8; llvmpipe 80)
  int maxComputeSSBOBlocks = 0;  ///< GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS (GL 4.3 guarantees 8; llvmpipe 16)
  bool lowered = false;          ///< an environment override lowered one of them
  /// GL_RENDERER names a CPU rasteriser (llvmpipe, softpipe, SWR, "Software"):
  /// the pass then does some GPU-shaped work on the CPU instead (pvsm_map_raster)
  bool softwareRenderer = false;
};

/// Limits of the current context (call with the context current).
GLLimits QueryGLLimits();

/// The largest power of two <= min(want rounded up to a power of two, limit),
/// and at least `floor`: shadow maps and tiles are powers of two.
int FitPowerOfTwo(int want, int limit, int floor = 64);
}

#endif
