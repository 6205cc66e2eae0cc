// The GL backend of GEARS (ssGearsGL.cxx): its buffers' binding points, the
// limits its kernels keep to, and the helpers that size, fill, read and
// dispatch them. Included by ssGearsGL.cxx alone.
#ifndef ssGearsGLImpl_h
#define ssGearsGLImpl_h

#include "ssComputeProgram.h"
#include "ssGearsGL.h"

#include "ssGearsCSAssign.h"
#include "ssGearsCSCommon.h"
#include "ssGearsCSRaster.h"
#include "ssGearsCSWinding.h"
#include "vtk_glew.h"

#include <chrono>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace ss
{
namespace // (this header has one includer)
{
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// SSBO binding points (glsl/ssGearsCS.glsl)
enum Binding
{
  BTriV = 0,
  BTriA,
  BPos,
  BNrm,
  BSmp,
  BFace,
  BVis,
  BRed,
  BPixCell,
  BCellCnt,
  BCellDep,
  BSat,
  BRmq,
  BBox,
  BOff,
  BPairTri,
  BPairCell,
  BCellBegin,
  BCursor,
  BSorted,
  BMasks,
  BNec,
  BScanData,
  BScanSums,
  BTriL,
  BClosed,
  BCellBox,
  BTriLF,
  BPixStart,
  BPixOrder,
  BNbr,      // the winding count (glsl/ssGearsCSWinding.glsl)
  BPairStat,
  BSlotStat,
  BWind,
  BTriN,
  NumBindings
};

constexpr GLuint kWG = 64;        // work group size of the per-item kernels
constexpr GLuint kScanWG = 256;   // scan: 4 x 256 = 1024 elements per group
constexpr std::size_t kScanElems = 1024;
// Mesa's llvmpipe ends an invocation after 65535 loop iterations in all
// (LP_MAX_TGSI_LOOP_ITERATIONS, shared by every loop of a shader) and gives
// no error. So no kernel loops without bound: the bitmask kernel takes a
// pixel's cell list in chunks of kChunk triangles, and passes 1 and 2 loop
// over at most G + G^2 cells (pass 1's other loops add under 100
// iterations: 57,940 at the cap of 240). A triangle that is drawn costs the
// bitmask kernel at most about 120 iterations at k = 32 while Table 9 is
// counted (its three phases' loops, 32 rows to clear, draw and compare):
// 46,000 for a chunk of 384 (512 came to 61,000 once the phases were split).
// Near triangles (within the start offset of S) cost about 60 more; a chunk
// holds only a few of them.
constexpr std::uint32_t kChunk = 384;
// the most storage blocks one kernel declares (K_RASTER's USE_* list in
// glsl/ssGearsCSCommon.glsl); checked against GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS
constexpr int kMaxKernelBlocks = 13;
// with the winding count, K_RASTER declares one more (WINDING); with fewer
// blocks the GL backend runs without it
constexpr int kWindingKernelBlocks = 14;
constexpr int kMaxGrid = 240;
// depth buckets per cell (K_PASS2): the order of a cell's list, nearest the
// receivers first, so that umbra masks fill early (the CPU's depth order)
constexpr std::size_t kDepthBuckets = 16;
// depth layers per grid cell at most (K_CELL; pass 1 and 2 write them out)
constexpr int kMaxLayers = 4;
// pass 1 estimates the layers' pairs from every kLayerSample-th triangle
// (where there are at least kLayerSample * kWG)
constexpr std::size_t kLayerSample = 16;
// The sort's keys (list cell) x kDepthBuckets x 4 (the winding count's
// classes, K_WFLAG) stay below 2^24, so a key fits 32 bits with room. Their
// buffers (4 bytes per key: 59 MB at this bound) are checked against the
// context's SSBO limit at run time, with fewer layers where they do not fit.
static_assert(std::size_t(kMaxGrid) * kMaxGrid * kMaxLayers * kDepthBuckets * 4 < (std::size_t(1) << 24), "sort keys");

std::uint32_t Ord(float f)
{
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
float Unord(std::uint32_t u)
{
  const std::uint32_t b = (u & 0x80000000u) ? (u & 0x7FFFFFFFu) : ~u;
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}
}

struct GearsGL::Impl
{
  struct Buffer
  {
    GLuint id = 0;
    std::size_t capacity = 0;
  };
  Buffer Buf[NumBindings];
  std::vector<Buffer> ScanSums; // one per recursion level
  std::map<std::string, GLuint> Programs;
  std::map<std::pair<GLuint, std::string>, GLint> Locations;
  std::uint64_t TriVersion = 0, NbrVersion = 0;
  bool LayersFit = true; // (the depth layers' pairs fitted one buffer for these triangles)
  std::int64_t MaxBlock = 0;
  int MaxBindings = 0, MaxKernelBlocks = 0;
  GLuint Current = 0;

  void Ensure(Buffer& b, std::size_t bytes)
  {
    bytes = std::max<std::size_t>(bytes, 16);
    if (!b.id)
    {
      glGenBuffers(1, &b.id);
    }
    if (b.capacity < bytes)
    {
      const std::size_t cap = std::max(bytes, b.capacity + b.capacity / 2);
      glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id);
      glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(cap), nullptr, GL_DYNAMIC_COPY);
      b.capacity = cap;
    }
  }
  void Upload(Buffer& b, const void* data, std::size_t bytes)
  {
    Ensure(b, bytes);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id);
    if (bytes)
    {
      glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
    }
  }
  void Fill(Buffer& b, std::size_t bytes, std::uint32_t value, std::size_t offset = 0)
  {
    Ensure(b, offset + bytes);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id);
    glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, static_cast<GLintptr>(offset),
      static_cast<GLsizeiptr>((bytes + 3) / 4 * 4),
      GL_RED_INTEGER, GL_UNSIGNED_INT, &value);
  }
  void Download(Buffer& b, void* out, std::size_t bytes, std::size_t offset = 0)
  {
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b.id);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), out);
  }
  std::uint32_t ReadUint(Buffer& b, std::size_t index)
  {
    std::uint32_t v = 0;
    Download(b, &v, 4, 4 * index);
    return v;
  }
  void BindAll()
  {
    for (int i = 0; i < NumBindings; ++i)
    {
      if (Buf[i].id)
      {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(i), Buf[i].id);
      }
    }
  }

  // kernel: its K_* define; extra: one more define (or none)
  GLuint Program(const std::string& kernel, std::string* why, const char* extra = nullptr)
  {
    const GLuint wg = (kernel == "K_SCAN_BLOCK" || kernel == "K_SCAN_ADD") ? kScanWG : kWG;
    std::ostringstream head;
    head << "#version 430\n#define " << kernel << "\n#define WG " << wg << "\n";
    if (extra)
    {
      head << "#define " << extra << "\n";
    }
    const std::string key = head.str();
    auto it = Programs.find(key);
    if (it != Programs.end())
    {
      return it->second;
    }
    const std::string src = key + ssGearsCSCommon + ssGearsCSAssign + ssGearsCSRaster + ssGearsCSWinding;
    std::string error;
    const GLuint prog = CompileComputeProgram(src, error);
    if (!prog)
    {
      if (why)
      {
        *why = "GEARS GL: " + kernel + " " + error;
      }
      return 0;
    }
    Programs[key] = prog;
    return prog;
  }

  GLint Loc(const char* name)
  {
    const auto key = std::make_pair(Current, std::string(name));
    auto it = Locations.find(key);
    if (it != Locations.end())
    {
      return it->second;
    }
    const GLint l = glGetUniformLocation(Current, name);
    Locations[key] = l;
    return l;
  }
  void Use(GLuint prog)
  {
    Current = prog;
    glUseProgram(prog);
  }
  void U(const char* n, int v) { glUniform1i(Loc(n), v); }
  void Uu(const char* n, std::uint32_t v) { glUniform1ui(Loc(n), v); }
  void Ud(const char* n, double v) { glUniform1d(Loc(n), v); }
  void U3(const char* n, const glm::dvec3& v) { glUniform3d(Loc(n), v.x, v.y, v.z); }
  void U2d(const char* n, double x, double y) { glUniform2d(Loc(n), x, y); }

  // groups work groups, split over x and y (at most 65535 per axis)
  void Dispatch(std::size_t groups)
  {
    if (!groups)
    {
      return;
    }
    BindAll();
    const GLuint gx = static_cast<GLuint>(std::min<std::size_t>(groups, 65535));
    const GLuint gy = static_cast<GLuint>((groups + gx - 1) / gx);
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  // one invocation per item of the current program (uN = items)
  void Items(std::size_t items)
  {
    Uu("uN", static_cast<std::uint32_t>(items));
    Dispatch((items + kWG - 1) / kWG);
  }

  // In-place exclusive prefix sum of `count` uints of buffer b [§4.2]:
  // blocks of 1024 scanned in shared memory, their totals scanned
  // recursively and added back.
  bool Scan(Buffer& b, std::size_t count, std::size_t level, std::string* why)
  {
    const std::size_t blocks = (count + kScanElems - 1) / kScanElems;
    if (ScanSums.size() <= level)
    {
      ScanSums.resize(level + 1);
    }
    Ensure(ScanSums[level], 4 * blocks);
    const GLuint block = Program("K_SCAN_BLOCK", why), add = Program("K_SCAN_ADD", why);
    if (!block || !add)
    {
      return false;
    }
    Buffer savedData = Buf[BScanData], savedSums = Buf[BScanSums];
    Buf[BScanData] = b;
    Buf[BScanSums] = ScanSums[level];
    Use(block);
    Uu("uN", static_cast<std::uint32_t>(count));
    Dispatch(blocks);
    Buf[BScanData] = savedData;
    Buf[BScanSums] = savedSums;
    if (blocks > 1)
    {
      Buffer sums = ScanSums[level];
      if (!Scan(sums, blocks, level + 1, why))
      {
        return false;
      }
      Buf[BScanData] = b;
      Buf[BScanSums] = ScanSums[level];
      Use(add);
      Uu("uN", static_cast<std::uint32_t>(count));
      Dispatch((count + kScanWG - 1) / kScanWG);
      Buf[BScanData] = savedData;
      Buf[BScanSums] = savedSums;
    }
    return true;
  }

  void Release()
  {
    for (auto& p : Programs)
    {
      glDeleteProgram(p.second);
    }
    Programs.clear();
    Locations.clear();
    for (auto& b : Buf)
    {
      if (b.id)
      {
        glDeleteBuffers(1, &b.id);
      }
      b = Buffer{};
    }
    for (auto& b : ScanSums)
    {
      if (b.id)
      {
        glDeleteBuffers(1, &b.id);
      }
    }
    ScanSums.clear();
    TriVersion = 0;
    NbrVersion = 0;
    LayersFit = true;
  }
};
}

#endif
