#include "ssReference.h"
#include "ssTriangleSet.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace ss
{
namespace
{
// Deterministic per-(pixel, sample) jitter in [0,1).
double Hash01(std::uint64_t x)
{
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) * (1.0 / 9007199254740992.0);
}

// Occlusion context extended with per-ray transmittance (Embree's documented
// way to pass data to filter functions).
struct TransmittanceContext
{
  RTCIntersectContext context;
  const float* opacity;
  float* transmittance; // 16 entries
  // Embree may report one primitive more than once (BVH references); each
  // ray remembers the translucent primitives it already crossed.
  // Two triangles sharing an edge are both reported by a ray through that
  // edge: hits at the same distance count as one surface.
  unsigned seen[16][16];
  float seenT[16][16];
  int seenCount[16];
  float tEpsilon;
};

void OccludedFilter(const RTCFilterFunctionNArguments* args)
{
  const auto* ctx = reinterpret_cast<const TransmittanceContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
  {
    if (args->valid[i] == 0)
    {
      continue;
    }
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const float a = ctx->opacity[prim];
    // ray ids are the lanes of our 16-wide packets
    const unsigned rayIndex = RTCRayN_id(args->ray, args->N, i) & 15u;
    auto* mctx = const_cast<TransmittanceContext*>(ctx);
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    bool repeated = false;
    for (int s = 0; s < mctx->seenCount[rayIndex]; ++s)
    {
      repeated = repeated || mctx->seen[rayIndex][s] == prim ||
        std::abs(mctx->seenT[rayIndex][s] - t) <= mctx->tEpsilon;
    }
    if (repeated)
    {
      args->valid[i] = 0;
      continue;
    }
    if (mctx->seenCount[rayIndex] < 16)
    {
      mctx->seen[rayIndex][mctx->seenCount[rayIndex]] = prim;
      mctx->seenT[rayIndex][mctx->seenCount[rayIndex]++] = t;
    }
    else
    {
      // more than 16 translucent layers: treat the rest as opaque
      continue;
    }
    ctx->transmittance[rayIndex] *= (1.0f - a);
    if (ctx->transmittance[rayIndex] > 1e-4f)
    {
      args->valid[i] = 0; // keep going: the ray passes through
    }
  }
}
}

std::string EmbreeDeviceConfigFromEnvironment()
{
  const char* isa = std::getenv("SOFTSHADOWS_EMBREE_ISA");
  return (isa && *isa) ? std::string("isa=") + isa : std::string();
}

std::vector<std::string> SupportedEmbreeISAs()
{
  // Only ISAs this CPU runs: asking Embree for a wider one than the CPU has
  // would run instructions it does not have.
  std::vector<std::string> isas;
  __builtin_cpu_init();
  if (__builtin_cpu_supports("sse4.2"))
  {
    isas.push_back("sse4.2");
  }
  if (__builtin_cpu_supports("avx"))
  {
    isas.push_back("avx");
  }
  if (__builtin_cpu_supports("avx2"))
  {
    isas.push_back("avx2");
  }
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
    __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") &&
    __builtin_cpu_supports("avx512vl"))
  {
    isas.push_back("avx512");
  }
  return isas;
}

struct ReferenceSolver::Impl
{
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  glm::dvec3 Center{ 0.0 };
  double Extent = 1.0;
  std::size_t Triangles = 0, Skipped = 0;
  std::vector<float> Opacity;
  bool Translucent = false;
  std::vector<VolumeGrid> Volumes;

  ~Impl()
  {
    if (Scene)
    {
      rtcReleaseScene(Scene);
    }
    if (Device)
    {
      rtcReleaseDevice(Device);
    }
  }
};

ReferenceSolver::ReferenceSolver()
  : ReferenceSolver(EmbreeDeviceConfigFromEnvironment())
{
}

ReferenceSolver::ReferenceSolver(const std::string& deviceConfig)
  : P(new Impl)
{
  P->Device = rtcNewDevice(deviceConfig.empty() ? nullptr : deviceConfig.c_str());
  if (!P->Device || rtcGetDeviceError(P->Device) != RTC_ERROR_NONE)
  {
    throw std::runtime_error("Embree: could not create a device with configuration '" +
      deviceConfig + "'");
  }
}

ReferenceSolver::~ReferenceSolver() = default;

void ReferenceSolver::SetTriangles(const std::vector<glm::dvec3>& v, const std::vector<float>& opacity)
{
  if (P->Scene)
  {
    rtcReleaseScene(P->Scene);
    P->Scene = nullptr;
  }
  const std::size_t nt = v.size() / 3;
  const TriangleSelection sel = SelectTriangles(v, opacity, false);
  const std::vector<char>& keep = sel.keep;
  P->Skipped = sel.skipped;
  P->Triangles = sel.kept;
  P->Center = sel.center;
  P->Extent = sel.extent;
  P->Opacity.clear();
  P->Translucent = false;
  P->Scene = rtcNewScene(P->Device);
  rtcSetSceneBuildQuality(P->Scene, RTC_BUILD_QUALITY_HIGH);
  if (P->Triangles > 0)
  {
    RTCGeometry geom = rtcNewGeometry(P->Device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * P->Triangles));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), P->Triangles));
    std::size_t out = 0;
    for (std::size_t t = 0; t < nt; ++t)
    {
      if (!keep[t])
      {
        continue;
      }
      for (int j = 0; j < 3; ++j)
      {
        const glm::dvec3 r = v[3 * t + j] - P->Center;
        vb[9 * out + 3 * j + 0] = static_cast<float>(r.x);
        vb[9 * out + 3 * j + 1] = static_cast<float>(r.y);
        vb[9 * out + 3 * j + 2] = static_cast<float>(r.z);
        ib[3 * out + j] = static_cast<unsigned>(3 * out + j);
      }
      const float a = TriangleOpacity(opacity, t);
      P->Opacity.push_back(a);
      P->Translucent = P->Translucent || a < 1.0f;
      ++out;
    }
    if (P->Translucent)
    {
      rtcSetGeometryOccludedFilterFunction(geom, OccludedFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(P->Scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(P->Scene);
}

void ReferenceSolver::SetVolumes(const std::vector<VolumeGrid>& volumes)
{
  P->Volumes.clear();
  for (const auto& v : volumes)
  {
    if (!v.Empty())
    {
      P->Volumes.push_back(v);
    }
  }
}

std::size_t ReferenceSolver::NumberOfTriangles() const
{
  return P->Triangles;
}

std::size_t ReferenceSolver::SkippedTriangles() const
{
  return P->Skipped;
}

std::vector<float> ReferenceSolver::Solve(const LightFrame& light, const glm::dvec3& origin,
  const float* positions, const float* normals, std::size_t n, const ReferenceOptions& opt,
  ReferenceStats* stats) const
{
  const auto t0 = std::chrono::steady_clock::now();
  const int k = (light.type == LightType::Point) ? 1 : std::clamp(opt.k, 1, 64);
  const int ns = k * k;
  std::vector<float> V(n, std::numeric_limits<float>::quiet_NaN());
  std::atomic<long long> rayCount{ 0 };
  if (!P->Scene)
  {
    const_cast<ReferenceSolver*>(this)->SetTriangles({}, {});
  }
  const double eps = 1e-5 * P->Extent;

  // Light sample s (of k x k) as a point (rect/point) or a direction (directional),
  // for pixel `pix` (stratified jitter is per pixel and sample, deterministic).
  auto sample = [&](std::size_t pix, int s, glm::dvec3& target, bool& isDirection) {
    const int i = s % k, j = s / k;
    double a = 0.5, b = 0.5;
    if (opt.pattern == LightSamplePattern::Stratified && k > 1)
    {
      const std::uint64_t key = (static_cast<std::uint64_t>(pix) * 4096u + s) * 1315423911u + opt.seed;
      a = Hash01(key);
      b = Hash01(key ^ 0x5bd1e995u);
    }
    const double su = (i + a) / k - 0.5, sv = (j + b) / k - 0.5;
    if (light.type == LightType::Directional)
    {
      // a square of directions of the given angular size around -n
      const double t = std::tan(0.5 * light.angularDiameter) * 2.0;
      target = glm::normalize(-light.n + su * t * light.u + sv * t * light.v);
      isDirection = true;
    }
    else
    {
      target = light.center + su * light.width * light.u + sv * light.height * light.v;
      isDirection = false;
    }
  };

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 64), [&](const tbb::blocked_range<std::size_t>& r) {
    long long localRays = 0;
    for (std::size_t pix = r.begin(); pix != r.end(); ++pix)
    {
      const float* pf = positions + 3 * pix;
      if (!(std::isfinite(pf[0]) && std::isfinite(pf[1]) && std::isfinite(pf[2])))
      {
        continue;
      }
      const glm::dvec3 p = origin + glm::dvec3(pf[0], pf[1], pf[2]);
      glm::dvec3 N(0.0);
      if (normals)
      {
        const float* nf = normals + 3 * pix;
        N = glm::dvec3(nf[0], nf[1], nf[2]);
        const double l = glm::length(N);
        N = (l > 0.0 && std::isfinite(l)) ? N / l : glm::dvec3(0.0);
      }
      if (light.type == LightType::Rect && glm::dot(p - light.center, light.n) <= 0.0)
      {
        V[pix] = 0.0f; // behind a one-sided light
        continue;
      }
      // Push the start off the surface; scaled to the scene so it works at any size.
      const glm::dvec3 start = p + N * eps - P->Center;
      double visible = 0.0;
      for (int s0 = 0; s0 < ns; s0 += 16)
      {
        RTCRay16 rays;
        alignas(64) int valid[16]; // rtcOccluded16 wants the mask 64-byte aligned
        float transmittance[16];
        int below[16];
        glm::dvec3 rayDir[16];
        double rayLen[16];
        for (int q = 0; q < 16; ++q)
        {
          const int s = s0 + q;
          valid[q] = 0;
          below[q] = 0;
          transmittance[q] = 1.0f;
          // Every lane is written, active or not: an 8-wide kernel (AVX2)
          // serving a 16-ray packet reads all 16 lanes, and Debian's Embree
          // asserts that each one is a valid ray. An inactive lane is a finite
          // ray with tfar < tnear, so it could never hit even if it were read.
          rays.org_x[q] = static_cast<float>(start.x);
          rays.org_y[q] = static_cast<float>(start.y);
          rays.org_z[q] = static_cast<float>(start.z);
          rays.dir_x[q] = 0.0f;
          rays.dir_y[q] = 0.0f;
          rays.dir_z[q] = 1.0f;
          rays.tnear[q] = 0.0f;
          rays.tfar[q] = -1.0f;
          rays.time[q] = 0.0f;
          rays.mask[q] = 0u;
          rays.id[q] = static_cast<unsigned>(q);
          rays.flags[q] = 0;
          if (s >= ns)
          {
            continue;
          }
          glm::dvec3 target;
          bool isDir = false;
          sample(pix, s, target, isDir);
          glm::dvec3 dir;
          double tfar;
          if (isDir)
          {
            dir = target;
            tfar = 1e30;
          }
          else
          {
            dir = target - (start + P->Center);
            tfar = glm::length(dir);
            if (!(tfar > 0.0))
            {
              continue;
            }
            dir /= tfar;
            tfar *= (1.0 - 1e-6);
          }
          if (glm::dot(dir, N) < 0.0)
          {
            below[q] = 1; // behind the surface: not seen from it
            continue;
          }
          valid[q] = -1;
          rayDir[q] = dir;
          rayLen[q] = isDir ? 1e9 : tfar; // a direction: every volume is clipped out of a long ray
          rays.org_x[q] = static_cast<float>(start.x);
          rays.org_y[q] = static_cast<float>(start.y);
          rays.org_z[q] = static_cast<float>(start.z);
          rays.dir_x[q] = static_cast<float>(dir.x);
          rays.dir_y[q] = static_cast<float>(dir.y);
          rays.dir_z[q] = static_cast<float>(dir.z);
          rays.tnear[q] = static_cast<float>(eps);
          rays.tfar[q] = static_cast<float>(tfar);
          rays.time[q] = 0.0f;
          rays.mask[q] = 0xFFFFFFFFu;
          rays.id[q] = static_cast<unsigned>(q);
          rays.flags[q] = 0;
        }
        TransmittanceContext ctx;
        rtcInitIntersectContext(&ctx.context);
        ctx.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        ctx.opacity = P->Opacity.data();
        ctx.transmittance = transmittance;
        std::fill(std::begin(ctx.seenCount), std::end(ctx.seenCount), 0);
        ctx.tEpsilon = static_cast<float>(1e-6 * P->Extent);
        rtcOccluded16(valid, P->Scene, &ctx.context, &rays);
        for (int q = 0; q < 16; ++q)
        {
          if (valid[q] == 0 || below[q])
          {
            continue;
          }
          ++localRays;
          // occluded rays get tfar = -inf
          if (rays.tfar[q] >= 0.0f)
          {
            double t = P->Translucent ? transmittance[q] : 1.0;
            if (!P->Volumes.empty())
            {
              const glm::dvec3 a = start + P->Center, b = a + rayDir[q] * rayLen[q];
              double tau = 0.0;
              for (const auto& vol : P->Volumes)
              {
                tau += vol.OpticalDepth(a, b);
              }
              t *= std::exp(-tau);
            }
            visible += t;
          }
        }
      }
      V[pix] = static_cast<float>(visible / ns);
    }
    rayCount += localRays;
  });
  if (stats)
  {
    stats->rays = static_cast<double>(rayCount.load());
    stats->milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    stats->raysPerSecond = stats->milliseconds > 0 ? stats->rays / (stats->milliseconds * 1e-3) : 0.0;
    stats->triangles = P->Triangles;
  }
  return V;
}
}
