#include "ssGLLimits.h"

#include "vtk_glew.h"

#include <algorithm>
#include <cstdlib>
#include <string>

namespace ss
{
namespace
{
template <typename T>
T Lowered(T value, const char* env, bool& lowered)
{
  const char* s = std::getenv(env);
  if (!s || !*s)
  {
    return value;
  }
  char* end = nullptr;
  const long long v = std::strtoll(s, &end, 10);
  if (end == s || v <= 0 || static_cast<long long>(value) <= v)
  {
    return value;
  }
  lowered = true;
  return static_cast<T>(v);
}
}

GLLimits QueryGLLimits()
{
  GLLimits L;
  GLint v = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &v);
  L.maxTextureSize = v > 0 ? v : 1024; // GL 3.x guarantees 1024
  v = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &v);
  L.maxArrayTextureLayers = v > 0 ? v : 256; // GL 3.x guarantees 256
  // 64-bit query: GPUs report 2 GB and more, which a GLint cannot hold.
  GLint64 b = 0;
  if (GLEW_VERSION_4_3 || GLEW_ARB_shader_storage_buffer_object)
  {
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &b);
    v = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &v);
    L.maxSSBOBindings = v > 0 ? v : 0;
    v = 0;
    glGetIntegerv(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, &v);
    L.maxComputeSSBOBlocks = v > 0 ? v : 0;
  }
  L.maxSSBOBytes = b > 0 ? static_cast<std::int64_t>(b) : 0;
  const GLubyte* renderer = glGetString(GL_RENDERER);
  if (renderer)
  {
    const std::string r = reinterpret_cast<const char*>(renderer);
    for (const char* name : { "llvmpipe", "softpipe", "SWR", "Software" })
    {
      L.softwareRenderer = L.softwareRenderer || r.find(name) != std::string::npos;
    }
  }
  while (glGetError() != GL_NO_ERROR)
  {
  }
  L.maxTextureSize = Lowered(L.maxTextureSize, "SOFTSHADOWS_GL_MAX_TEXTURE_SIZE", L.lowered);
  L.maxArrayTextureLayers = Lowered(L.maxArrayTextureLayers, "SOFTSHADOWS_GL_MAX_ARRAY_TEXTURE_LAYERS", L.lowered);
  L.maxSSBOBytes = Lowered(L.maxSSBOBytes, "SOFTSHADOWS_GL_MAX_SSBO_BYTES", L.lowered);
  L.maxSSBOBindings = Lowered(L.maxSSBOBindings, "SOFTSHADOWS_GL_MAX_SSBO_BINDINGS", L.lowered);
  L.maxComputeSSBOBlocks =
    Lowered(L.maxComputeSSBOBlocks, "SOFTSHADOWS_GL_MAX_COMPUTE_SSBO_BLOCKS", L.lowered);
  return L;
}

int FitPowerOfTwo(int want, int limit, int floor)
{
  int s = floor;
  while (s < want && s <= (1 << 29))
  {
    s *= 2;
  }
  while (s > limit && s > 1)
  {
    s /= 2;
  }
  return std::max(s, 1);
}
}
