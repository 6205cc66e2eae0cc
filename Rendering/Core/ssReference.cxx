#include "ssReference.h"
#include "ssTriangleSet.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
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
using Triangle = std::array<glm::dvec3, 3>;

// Cut points along the edge u-w (relative to the casters' centre), ordered
// from u, each with its parameter from u: from the end nearer the centre,
// each step max(scale, a quarter of the distance from the centre reached), so
// a piece near the scene is no longer than the bulk and one far out no longer
// than a quarter of its distance. A function of the edge alone (its ends
// taken in a fixed order, the points computed from that end), so triangles
// sharing an edge cut it at bitwise the same points.
std::vector<std::pair<double, glm::dvec3>> EdgeCuts(const glm::dvec3& u, const glm::dvec3& w, double scale)
{
  const double lu = glm::length(u), lw = glm::length(w);
  const bool flip = lw < lu || (lw == lu && (w.x < u.x || (w.x == u.x && (w.y < u.y || (w.y == u.y && w.z < u.z)))));
  const glm::dvec3 a = flip ? w : u, e = (flip ? u : w) - a;
  const double len = glm::length(e);
  std::vector<std::pair<double, glm::dvec3>> cuts;
  for (double s = 0.0; len > 0.0;)
  {
    s += std::max(scale, 0.25 * glm::length(a + (s / len) * e));
    if (!(s < len))
    {
      break;
    }
    cuts.emplace_back(flip ? 1.0 - s / len : s / len, a + (s / len) * e);
  }
  if (flip)
  {
    std::reverse(cuts.begin(), cuts.end());
  }
  return cuts;
}

// A needle: two edges longer than 64 bulk diagonals, the third within one.
// Returns the index of its short edge (t[i], t[i + 1]), or -1.
int NeedleShortEdge(const Triangle& t, double scale)
{
  double len[3];
  int shortest = 0;
  for (int e = 0; e < 3; ++e)
  {
    len[e] = glm::length(t[(e + 1) % 3] - t[e]);
    shortest = len[e] < len[shortest] ? e : shortest;
  }
  const double longer = std::max(len[(shortest + 1) % 3], len[(shortest + 2) % 3]);
  return (scale > 0.0 && longer > 64.0 * scale && len[shortest] <= scale) ? shortest : -1;
}

// A far-reaching caster in pieces for Embree (beyond the papers; stability.md
// "A thin caster far from the scene"). Embree tests rays in float against
// vertices relative to the ray: a sliver from the scene out to (1e6, 0, -1e6)
// cast a jagged shadow edge near the scene (mean error 0.010 against exact
// segment tests at 1e6, 0.059 at 1e7, 0.16 at 1e8). A needle is cut along
// both long edges (EdgeCuts) and the strip between them triangulated
// zipper-wise: its pieces share their vertices, and the edges it shares with
// other triangles are cut alike, so the surface stays watertight. `t` is
// relative to the centre; `shortest` from NeedleShortEdge.
void AppendPieces(const Triangle& t, int shortest, double scale, std::vector<Triangle>& out)
{
  const glm::dvec3 a = t[shortest], b = t[(shortest + 1) % 3], c = t[(shortest + 2) % 3];
  // the two sides from the short edge to the apex c
  auto ca = EdgeCuts(a, c, scale), cb = EdgeCuts(b, c, scale);
  ca.emplace_back(1.0, c);
  cb.emplace_back(1.0, c);
  glm::dvec3 pa = a, pb = b;
  std::size_t ia = 0, ib = 0;
  while (ia < ca.size() || ib < cb.size())
  {
    // advance the side whose next point comes first; the winding stays (a, b, c)'s
    const bool sideA = ib == cb.size() || (ia < ca.size() && ca[ia].first <= cb[ib].first);
    const glm::dvec3 next = sideA ? ca[ia++].second : cb[ib++].second;
    out.push_back({ pa, pb, next });
    (sideA ? pa : pb) = next;
  }
}

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
  double Unit = 1.0; ///< a power of two near Scale: Embree's length unit (SetTriangles)
  double Scale = 1.0; ///< the bulk's diagonal (ssTriangleSet.h)
  std::size_t Triangles = 0, Skipped = 0;
  std::size_t Pieces = 0; ///< triangles given to Embree (far-reaching ones in pieces: AppendPieces)
  std::vector<float> Opacity; ///< per Embree triangle
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
  P->Scale = sel.scale;
  // Embree sees the casters in units of a power of two near their scale
  // (exact: no rounding changes), so that its own tolerances meet a scene of
  // unit size whatever the world's units. Stop 45's Python sweep: scaled by
  // 1e14 or 1e-12, the ground truth missed about 1,000 pixels of shadow that
  // GEARS found (1e-8 .. 1e8 were exact).
  P->Unit = sel.scale > 0.0 && std::isfinite(sel.scale) ? std::ldexp(1.0, std::ilogb(sel.scale)) : 1.0;
  P->Opacity.clear();
  P->Pieces = 0;
  P->Translucent = false;
  P->Scene = rtcNewScene(P->Device);
  // Robust traversal and intersection: without it, rays through an edge two
  // triangles share slipped between them (a box standing on a plane let 4 of
  // 256 samples through its top to the point under its centre; GEARS' exact
  // raster is watertight). Cost: stability.md.
  rtcSetSceneFlags(P->Scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(P->Scene, RTC_BUILD_QUALITY_HIGH);
  if (P->Triangles > 0)
  {
    // the needles' pieces first (most meshes have none), then every kept
    // triangle, a needle as its pieces, relative to the centre in Embree's unit
    std::vector<Triangle> cut;
    std::vector<std::pair<std::size_t, std::size_t>> needles; // (triangle, the end of its pieces in `cut`)
    for (std::size_t t = 0; t < nt; ++t)
    {
      if (!keep[t])
      {
        continue;
      }
      const Triangle c = { v[3 * t] - P->Center, v[3 * t + 1] - P->Center, v[3 * t + 2] - P->Center };
      const int shortest = NeedleShortEdge(c, P->Scale);
      if (shortest >= 0)
      {
        AppendPieces(c, shortest, P->Scale, cut);
        needles.emplace_back(t, cut.size());
      }
    }
    P->Pieces = P->Triangles - needles.size() + cut.size();
    RTCGeometry geom = rtcNewGeometry(P->Device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * P->Pieces));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), P->Pieces));
    std::size_t out = 0, cutBegin = 0, next = 0;
    auto write = [&](const Triangle& r, float a) {
      for (int j = 0; j < 3; ++j)
      {
        const glm::dvec3 q = r[j] / P->Unit;
        vb[9 * out + 3 * j + 0] = static_cast<float>(q.x);
        vb[9 * out + 3 * j + 1] = static_cast<float>(q.y);
        vb[9 * out + 3 * j + 2] = static_cast<float>(q.z);
        ib[3 * out + j] = static_cast<unsigned>(3 * out + j);
      }
      P->Opacity.push_back(a);
      P->Translucent = P->Translucent || a < 1.0f;
      ++out;
    };
    for (std::size_t t = 0; t < nt; ++t)
    {
      if (!keep[t])
      {
        continue;
      }
      const float a = TriangleOpacity(opacity, t);
      if (next < needles.size() && needles[next].first == t)
      {
        for (std::size_t k = cutBegin; k < needles[next].second; ++k)
        {
          write(cut[k], a);
        }
        cutBegin = needles[next++].second;
        continue;
      }
      write({ v[3 * t] - P->Center, v[3 * t + 1] - P->Center, v[3 * t + 2] - P->Center }, a);
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

std::size_t ReferenceSolver::EmbreeTriangles() const
{
  return P->Pieces;
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
  const bool directional = light.type == LightType::Directional;
  const bool regular = opt.pattern == LightSamplePattern::Regular || k == 1;
  const double T = std::tan(0.5 * light.angularDiameter) * 2.0;

  // Light sample s (of k x k) as a point (rect/point) or a direction
  // (directional), for pixel `pix` (stratified jitter is per pixel and
  // sample, deterministic).
  auto sample = [&](std::size_t pix, int s, glm::dvec3& target) {
    const int i = s % k, j = s / k;
    double a = 0.5, b = 0.5;
    if (!regular)
    {
      const std::uint64_t key = (static_cast<std::uint64_t>(pix) * 4096u + s) * 1315423911u + opt.seed;
      a = Hash01(key);
      b = Hash01(key ^ 0x5bd1e995u);
    }
    const double su = (i + a) / k - 0.5, sv = (j + b) / k - 0.5;
    target = directional ? glm::normalize(-light.n + su * T * light.u + sv * T * light.v)
                         : light.center + su * light.width * light.u + sv * light.height * light.v;
  };
  // Regular samples are the same for every pixel: set up once, in float,
  // relative to the scene's centre (points) or as unit directions. Not for
  // a light whose samples lie 1e18 or more from the scene: their squares
  // overflow float (a light of 1e20 gave zero directions, rays that hit
  // nothing: V 0.93 where 0.46 is right; one of 1e39 gave infinite ones, and
  // Embree aborted the process). Those take the per-pixel path in double.
  std::vector<float> fixed;
  bool fixedFloat = regular;
  if (regular)
  {
    fixed.resize(3 * static_cast<std::size_t>(ns));
    for (int s = 0; s < ns; ++s)
    {
      glm::dvec3 t;
      sample(0, s, t);
      const glm::dvec3 r = directional ? t : (t - P->Center) / P->Unit;
      fixedFloat = fixedFloat && std::max({ std::abs(r.x), std::abs(r.y), std::abs(r.z) }) < 1e18;
      fixed[3 * s] = static_cast<float>(r.x);
      fixed[3 * s + 1] = static_cast<float>(r.y);
      fixed[3 * s + 2] = static_cast<float>(r.z);
    }
  }

  // Pixels in an order that keeps neighbours in space together (Morton
  // order of their positions), so that consecutive packets traverse the
  // same parts of the BVH.
  std::vector<std::uint32_t> order;
  {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::size_t i = 0; i < n; ++i)
    {
      const float* pf = positions + 3 * i;
      if (std::isfinite(pf[0]) && std::isfinite(pf[1]) && std::isfinite(pf[2]))
      {
        order.push_back(static_cast<std::uint32_t>(i));
        lo = glm::min(lo, glm::dvec3(pf[0], pf[1], pf[2]));
        hi = glm::max(hi, glm::dvec3(pf[0], pf[1], pf[2]));
      }
    }
    const double size = std::max({ hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300 });
    auto spread = [](std::uint64_t v) {
      v &= 0x3ff;
      v = (v | (v << 16)) & 0x030000FFull;
      v = (v | (v << 8)) & 0x0300F00Full;
      v = (v | (v << 4)) & 0x030C30C3ull;
      v = (v | (v << 2)) & 0x09249249ull;
      return v;
    };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(order.size());
    tbb::parallel_for(std::size_t(0), order.size(), [&](std::size_t q) {
      const float* pf = positions + 3 * order[q];
      const glm::dvec3 u = (glm::dvec3(pf[0], pf[1], pf[2]) - lo) / size * 1023.0;
      const std::uint64_t key = spread(static_cast<std::uint64_t>(u.x)) | (spread(static_cast<std::uint64_t>(u.y)) << 1) |
        (spread(static_cast<std::uint64_t>(u.z)) << 2);
      keyed[q] = { static_cast<std::uint32_t>(key), order[q] };
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    for (std::size_t q = 0; q < order.size(); ++q)
    {
      order[q] = keyed[q].second;
    }
  }

  auto solvePixels = [&](const tbb::blocked_range<std::size_t>& r) {
    long long localRays = 0;
    for (std::size_t q = r.begin(); q != r.end(); ++q)
    {
      const std::size_t pix = order[q];
      const float* pf = positions + 3 * pix;
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
      // Push the start off the surface by the offset GEARS uses, scaled to
      // the casters and to the distance from their centre, at most 1e-3 of
      // the distance to the light (ssTriangleSet.h).
      const double eps = StartOffset(p - P->Center, P->Scale, DistanceToLight(light, p - light.center));
      const glm::dvec3 startWorld = p + N * eps;
      const glm::dvec3 start = (startWorld - P->Center) / P->Unit; // (Embree's units)
      const float sx = static_cast<float>(start.x), sy = static_cast<float>(start.y), sz = static_cast<float>(start.z);
      const float nx = static_cast<float>(N.x), ny = static_cast<float>(N.y), nz = static_cast<float>(N.z);
      double visible = 0.0;
      for (int s0 = 0; s0 < ns; s0 += 16)
      {
        RTCRay16 rays;
        alignas(64) int valid[16]; // rtcOccluded16 wants the mask 64-byte aligned
        float transmittance[16];
        float laneLen[16]; // volumes: each lane's segment length
        for (int q2 = 0; q2 < 16; ++q2)
        {
          const int s = s0 + q2;
          transmittance[q2] = 1.0f;
          // Every lane is written, active or not: an 8-wide kernel (AVX2)
          // serving a 16-ray packet reads all 16 lanes, and Debian's Embree
          // asserts that each one is a valid ray. An inactive lane is a finite
          // ray with tfar < tnear, so it could never hit even if it were read.
          float dx = 0.0f, dy = 0.0f, dz = 1.0f, tfar = -1.0f;
          bool ok = false;
          if (s < ns)
          {
            if (fixedFloat)
            {
              // in float, from the fixed samples
              const float* t = &fixed[3 * s];
              if (directional)
              {
                dx = t[0];
                dy = t[1];
                dz = t[2];
                tfar = 1e30f;
                ok = true;
              }
              else
              {
                dx = t[0] - sx;
                dy = t[1] - sy;
                dz = t[2] - sz;
                const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
                ok = len > 0.0f;
                if (ok)
                {
                  dx /= len;
                  dy /= len;
                  dz /= len;
                  tfar = len * (1.0f - 1e-6f);
                }
              }
            }
            else
            {
              glm::dvec3 target, dir;
              sample(pix, s, target);
              double tf = 1e30;
              if (directional)
              {
                dir = target;
              }
              else
              {
                dir = target - startWorld;
                tf = glm::length(dir);
                dir = tf > 0.0 ? dir / tf : dir;
                tf = std::min(tf / P->Unit * (1.0 - 1e-6), 1e30); // (float's range: nothing lies beyond)
              }
              ok = tf > 0.0;
              dx = static_cast<float>(dir.x);
              dy = static_cast<float>(dir.y);
              dz = static_cast<float>(dir.z);
              tfar = static_cast<float>(tf);
            }
            // behind the surface: not seen from it
            ok = ok && !(dx * nx + dy * ny + dz * nz < 0.0f);
          }
          valid[q2] = ok ? -1 : 0;
          rays.org_x[q2] = sx;
          rays.org_y[q2] = sy;
          rays.org_z[q2] = sz;
          rays.dir_x[q2] = ok ? dx : 0.0f;
          rays.dir_y[q2] = ok ? dy : 0.0f;
          rays.dir_z[q2] = ok ? dz : 1.0f;
          rays.tnear[q2] = ok ? static_cast<float>(eps / P->Unit) : 0.0f;
          rays.tfar[q2] = ok ? tfar : -1.0f;
          rays.time[q2] = 0.0f;
          rays.mask[q2] = ok ? 0xFFFFFFFFu : 0u;
          rays.id[q2] = static_cast<unsigned>(q2);
          rays.flags[q2] = 0;
          laneLen[q2] = directional ? 1e9f : tfar; // a direction: every volume is clipped out of a long ray
        }
        if (P->Translucent)
        {
          TransmittanceContext ctx;
          rtcInitIntersectContext(&ctx.context);
          ctx.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
          ctx.opacity = P->Opacity.data();
          ctx.transmittance = transmittance;
          std::fill(std::begin(ctx.seenCount), std::end(ctx.seenCount), 0);
          ctx.tEpsilon = static_cast<float>(0.1 * eps);
          rtcOccluded16(valid, P->Scene, &ctx.context, &rays);
        }
        else
        {
          // opaque scene: no filter callback, nothing to pass along
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
          rtcOccluded16(valid, P->Scene, &ctx, &rays);
        }
        for (int q2 = 0; q2 < 16; ++q2)
        {
          if (valid[q2] == 0)
          {
            continue;
          }
          ++localRays;
          // occluded rays get tfar = -inf
          if (rays.tfar[q2] >= 0.0f)
          {
            double t = P->Translucent ? transmittance[q2] : 1.0;
            if (!P->Volumes.empty())
            {
              const glm::dvec3 dir(rays.dir_x[q2], rays.dir_y[q2], rays.dir_z[q2]);
              const double len = static_cast<double>(laneLen[q2]) * (directional ? 1.0 : P->Unit); // (world)
              const glm::dvec3 a = startWorld, b = a + dir * len;
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
  };
  // in chunks, so that the caller hears of progress and can stop the solve
  const std::size_t numOrdered = order.size(), chunk = std::max<std::size_t>(4096, numOrdered / 64);
  for (std::size_t b = 0; b < numOrdered; b += chunk)
  {
    const std::size_t e = std::min(numOrdered, b + chunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(b, e, 64), solvePixels);
    if (opt.progress && !opt.progress(static_cast<double>(e) / numOrdered))
    {
      break;
    }
  }
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
