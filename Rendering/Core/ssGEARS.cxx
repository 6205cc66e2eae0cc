// GEARS: exact soft shadows by assigning triangles to pixel samples through a
// grid and rasterising them into per-pixel light bitmasks.
//   Wang, Zhou, Ke, Popescu, "GEARS: A General and Efficient Algorithm for
//   Rendering Shadows", Computer Graphics Forum 2014.
// Section numbers refer to that paper (../shared/papers/gears-*.md). This
// file holds the solver's input and the order of the stages; the stages are
// in ssGearsGrid / Pairs / Sort / Cells / Raster (see ssGearsInternal.h).
#include "ssGEARS.h"
#include "ssCasterClusters.h"
#include "ssGearsInternal.h"
#include "ssTriangleSet.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ss
{
namespace gears
{
Isa ResolveIsa(GearsSimd wanted)
{
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2");
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
    __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  switch (wanted)
  {
    case GearsSimd::Scalar:
      return Isa::Scalar;
    case GearsSimd::AVX2:
      return avx2 ? Isa::AVX2 : Isa::Scalar;
    case GearsSimd::Auto:
    {
      // SOFTSHADOWS_GEARS_ISA=scalar|avx2|avx512 picks the kernels Auto
      // takes (never wider than the CPU runs): another machine's path on this one
      const char* env = std::getenv("SOFTSHADOWS_GEARS_ISA");
      const std::string e = env ? env : "";
      if (e == "scalar")
      {
        return Isa::Scalar;
      }
      if (e == "avx2")
      {
        return avx2 ? Isa::AVX2 : Isa::Scalar;
      }
      return avx512 ? Isa::AVX512 : (avx2 ? Isa::AVX2 : Isa::Scalar);
    }
    case GearsSimd::AVX512:
    default:
      return avx512 ? Isa::AVX512 : (avx2 ? Isa::AVX2 : Isa::Scalar);
  }
}

const char* IsaName(Isa isa)
{
  return isa == Isa::AVX512 ? "avx512" : (isa == Isa::AVX2 ? "avx2" : "scalar");
}
}

using namespace gears;

namespace
{
bool SameLight(const LightFrame& P, const LightFrame& L)
{
  return P.type == L.type && P.center == L.center && P.u == L.u && P.v == L.v && P.n == L.n &&
    P.width == L.width && P.height == L.height && P.angularDiameter == L.angularDiameter;
}
}

struct GearsSolver::Impl
{
  SolverData D;
  std::vector<std::uint8_t> inputStatus; // per input triangle: 0 kept, 1 zero area, 2 not finite, 3 transparent
  std::vector<std::int64_t> inputToSolver; // -1: not kept
  mutable std::mutex LUTMutex;
  mutable std::unique_ptr<HalfPlaneLUT> Table;
  struct Scratch
  {
    std::vector<glm::dvec3> start, normal;
    std::vector<double> eps; ///< per pixel: its start offset
    std::vector<std::int8_t> face;
    FaceGrid grid;
    FaceTriangles tris;
    // what `tris` was prepared from: it depends only on the casters (their
    // generation), the light, the face's frame and two options, so a solve
    // that changes none of them (a camera move, new pixels) reuses it
    std::uint64_t trisGeneration = 0;
    std::uint64_t trisData = 0; ///< 0: the solver's triangles, else warpedStamp
    LightFrame trisLight;
    glm::dvec3 trisFrame[4];
    bool trisClosedRule = false, trisDepthOrder = false;
    bool SamePreparation(std::uint64_t generation, std::uint64_t data, const LightFrame& L, const GearsGridCamera& C,
      const GearsOptions& opt) const
    {
      return trisGeneration != 0 && trisGeneration == generation && trisData == data && SameLight(trisLight, L) &&
        trisFrame[0] == C.Lc && trisFrame[1] == C.u && trisFrame[2] == C.v && trisFrame[3] == C.n &&
        trisClosedRule == opt.closedMeshRule && trisDepthOrder == opt.depthOrder;
    }
    // a far light's warped triangles (ssGearsFarLight.cxx), and what of
    SolverData warped;
    std::uint64_t warpedGeneration = 0, warpedStamp = 0;
    LightFrame warpedFrom;
    PairScratch pairs;
    FacePairs facePairs;
    GearsNeighbours neighbours; ///< the winding count's, built by the first solve that uses it
  };
  mutable std::mutex SolveMutex;
  mutable Scratch Work;
  /// changes with every SetTriangles, SetClusters, SetPieces (0: never prepared)
  std::uint64_t generation = 0;
  void Changed()
  {
    static std::atomic<std::uint64_t> generations{ 0 };
    generation = ++generations;
  }

  const HalfPlaneLUT& GetLUT(int k, int res) const
  {
    std::lock_guard<std::mutex> lock(LUTMutex);
    if (!Table || Table->k != k || Table->res != res)
    {
      Table.reset(new HalfPlaneLUT);
      Table->Build(k, res);
    }
    return *Table;
  }

  // Stores the kept triangles cluster by cluster (order over input triangles).
  void Arrange(const std::vector<std::size_t>& order, const std::vector<std::size_t>& first)
  {
    SolverData& d = D;
    std::vector<float> V;
    std::vector<float> opacity;
    std::vector<std::size_t> input;
    // room for the inner occluders AppendOccluders adds after SetPieces
    // (reserved, not touched: without it the append moved the whole array
    // to fresh pages, 0.59 s on the 5M assembly)
    V.reserve(d.V.size() + d.V.size() / kOccluderHeadroom);
    opacity.reserve(d.opacity.size() + d.opacity.size() / kOccluderHeadroom);
    input.reserve(d.input.size());
    d.clusterFirst.assign(1, 0);
    for (std::size_t c = 0; c + 1 < first.size(); ++c)
    {
      for (std::size_t q = first[c]; q < first[c + 1]; ++q)
      {
        const std::int64_t s = inputToSolver[order[q]];
        if (s < 0)
        {
          continue;
        }
        V.insert(V.end(), d.V.begin() + 9 * s, d.V.begin() + 9 * s + 9);
        opacity.push_back(d.opacity[s]);
        input.push_back(d.input[s]);
      }
      if (input.size() > d.clusterFirst.back())
      {
        d.clusterFirst.push_back(static_cast<std::uint32_t>(input.size()));
      }
    }
    d.V.swap(V);
    d.opacity.swap(opacity);
    d.input.swap(input);
    for (std::size_t t = 0; t < d.input.size(); ++t)
    {
      inputToSolver[d.input[t]] = static_cast<std::int64_t>(t);
    }
    d.real = d.input.size();
    d.realClusters = d.clusterFirst.size() - 1;
    static std::atomic<std::uint64_t> arrangements{ 0 };
    d.arrangement = ++arrangements;
    // the triangle array changed: so does the version caches key on (the GL
    // backend's uploaded vertices)
    static std::atomic<std::uint64_t> versions{ 0 };
    d.version = ++versions;
    d.orient.clear();
    d.piece.clear();
    d.pieceBox.clear();
    d.closedTriangles = 0;
  }
};

GearsSolver::GearsSolver()
  : P(new Impl)
{
}

GearsSolver::~GearsSolver() = default;

void GearsSolver::SetTriangles(const std::vector<glm::dvec3>& v, const std::vector<float>& opacity)
{
  // The same selection, centre and size as the reference (so both start
  // their rays at the same points); fully transparent triangles are then
  // dropped as well, since they hide nothing.
  const TriangleSelection sel = SelectTriangles(v, opacity, false);
  const std::size_t nt = v.size() / 3;
  SolverData& d = P->D;
  d = SolverData{};
  d.center = sel.center;
  d.extent = sel.extent;
  d.scale = sel.scale;
  d.skipped = sel.skipped;
  d.V.reserve(9 * sel.kept);
  d.opacity.reserve(sel.kept);
  d.input.reserve(sel.kept);
  P->Changed();
  P->inputStatus.assign(nt, 0);
  P->inputToSolver.assign(nt, -1);
  for (std::size_t t = 0; t < nt; ++t)
  {
    const float a = TriangleOpacity(opacity, t);
    if (!sel.keep[t] || a <= 0.0f)
    {
      bool finite = true;
      for (int j = 0; j < 3; ++j)
      {
        finite = finite && std::isfinite(v[3 * t + j].x) && std::isfinite(v[3 * t + j].y) && std::isfinite(v[3 * t + j].z);
      }
      P->inputStatus[t] = !finite ? 2 : (sel.keep[t] ? 3 : 1);
      d.skipped += sel.keep[t] ? 1 : 0;
      continue;
    }
    for (int j = 0; j < 3; ++j)
    {
      const glm::dvec3 r = v[3 * t + j] - d.center;
      d.V.push_back(static_cast<float>(r.x));
      d.V.push_back(static_cast<float>(r.y));
      d.V.push_back(static_cast<float>(r.z));
    }
    P->inputToSolver[t] = static_cast<std::int64_t>(d.opacity.size());
    d.opacity.push_back(a);
    d.translucent = d.translucent || a < 1.0f;
    d.input.push_back(t);
  }
  // clusters: octree cells of the centroids' Morton order (ss::ClusterTriangles)
  const TriangleClusters cl = ClusterTriangles(v, 32);
  P->Arrange(cl.order, cl.first);
}

void GearsSolver::SetClusters(const std::vector<std::size_t>& order, const std::vector<std::size_t>& first)
{
  P->Changed();
  const std::size_t nt = P->inputToSolver.size();
  std::vector<char> seen(nt, 0);
  bool ok = order.size() == nt && !first.empty() && first.front() == 0 && first.back() == nt;
  for (std::size_t q = 0; ok && q < order.size(); ++q)
  {
    ok = order[q] < nt && !seen[order[q]];
    if (ok)
    {
      seen[order[q]] = 1;
    }
  }
  for (std::size_t c = 0; ok && c + 1 < first.size(); ++c)
  {
    ok = first[c] <= first[c + 1];
  }
  if (!ok)
  {
    throw std::invalid_argument("GearsSolver::SetClusters: the order must be a permutation of the " +
      std::to_string(nt) + " input triangles and first its increasing cluster starts from 0 to " + std::to_string(nt));
  }
  // keep the pieces across the rearrangement (per input triangle)
  std::vector<std::int8_t> orient(nt, 0);
  std::vector<std::uint32_t> piece(nt, 0);
  const bool havePieces = !P->D.piece.empty();
  std::vector<double> boxes = P->D.pieceBox;
  const std::size_t closed = P->D.closedTriangles;
  if (havePieces)
  {
    for (std::size_t t = 0; t < P->D.input.size(); ++t)
    {
      orient[P->D.input[t]] = P->D.orient[t];
      piece[P->D.input[t]] = P->D.piece[t];
    }
  }
  P->Arrange(order, first);
  if (havePieces)
  {
    SolverData& d = P->D;
    d.orient.resize(d.input.size());
    d.piece.resize(d.input.size());
    for (std::size_t t = 0; t < d.input.size(); ++t)
    {
      d.orient[t] = orient[d.input[t]];
      d.piece[t] = piece[d.input[t]];
    }
    d.pieceBox = boxes;
    d.closedTriangles = closed;
    AppendOccluders(d);
  }
}

void GearsSolver::SetPieces(const GearsPieces& pieces)
{
  P->Changed();
  const std::size_t nt = P->inputToSolver.size();
  const std::size_t np = pieces.orientation.size();
  if (pieces.piece.size() != nt)
  {
    throw std::invalid_argument("GearsSolver::SetPieces: " + std::to_string(pieces.piece.size()) +
      " piece ids for " + std::to_string(nt) + " input triangles");
  }
  for (std::uint32_t p : pieces.piece)
  {
    if (p >= np)
    {
      throw std::invalid_argument("GearsSolver::SetPieces: piece " + std::to_string(p) + " of " +
        std::to_string(np) + " pieces does not exist");
    }
  }
  // a piece is used only if every triangle of it is finite and opaque
  std::vector<char> usable(np, 1);
  for (std::size_t t = 0; t < nt; ++t)
  {
    const std::uint8_t s = P->inputStatus[t];
    const std::int64_t q = P->inputToSolver[t];
    if (s == 2 || s == 3 || (q >= 0 && P->D.opacity[q] < 1.0f))
    {
      usable[pieces.piece[t]] = 0;
    }
  }
  SolverData& d = P->D;
  const std::size_t ns = d.input.size();
  d.orient.reserve(ns + ns / kOccluderHeadroom);
  d.piece.reserve(ns + ns / kOccluderHeadroom);
  d.orient.assign(ns, 0);
  d.piece.assign(ns, 0);
  d.closedTriangles = 0;
  d.V.resize(9 * d.real);
  d.opacity.resize(d.real);
  for (std::size_t t = 0; t < ns; ++t)
  {
    const std::uint32_t p = pieces.piece[d.input[t]];
    const int o = pieces.orientation[p];
    d.piece[t] = p;
    d.orient[t] = static_cast<std::int8_t>(usable[p] ? (o > 0 ? 1 : (o < 0 ? -1 : 0)) : 0);
    d.closedTriangles += d.orient[t] != 0;
  }
  PieceBoxes(d, np);
  BuildOccluders(d);
  AppendOccluders(d);
}

std::size_t GearsSolver::NumberOfTriangles() const
{
  return P->D.real;
}

std::size_t GearsSolver::NumberOfClusters() const
{
  return P->D.Clusters();
}

std::vector<std::int8_t> GearsSolver::ClosedRuleFlags(const LightFrame& light, const GearsOptions& options) const
{
  LightFrame L = light;
  L.center -= P->D.center;
  if (L.type == LightType::Directional)
  {
    // a directional light has no position: its frame's centre goes to the
    // caster centre, so depths and the culling margin (ft.margin) stay at the
    // scene's scale wherever the scene lies (else everything is kept far from
    // the world origin)
    L.center = glm::dvec3(0.0);
  }
  std::vector<std::int8_t> flags;
  gears::ClosedRuleFlags(P->D, L, options, flags);
  flags.resize(P->D.real);
  return flags;
}

std::size_t GearsSolver::ClosedTriangles() const
{
  return P->D.closedTriangles;
}

std::size_t GearsSolver::SkippedTriangles() const
{
  return P->D.skipped;
}

std::size_t GearsSolver::InputIndex(std::size_t t) const
{
  return P->D.input.at(t);
}

glm::dvec3 GearsSolver::RayStart(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& normal) const
{
  glm::dvec3 N = normal;
  const double l = glm::length(N);
  N = (l > 0.0 && std::isfinite(l)) ? N / l : glm::dvec3(0.0);
  return p + N * StartOffset(p - P->D.center, P->D.scale, DistanceToLight(light, p - light.center));
}

std::array<glm::dvec3, 3> GearsSolver::Triangle(std::size_t t) const
{
  const SolverData& d = P->D;
  return { d.center + d.Vertex(t, 0), d.center + d.Vertex(t, 1), d.center + d.Vertex(t, 2) };
}

GearsTriangleData GearsSolver::Data() const
{
  const SolverData& d = P->D;
  GearsTriangleData r;
  r.vertices = d.V.data();
  r.opacity = d.opacity.data();
  r.count = d.real;
  r.center = d.center;
  r.extent = d.extent;
  r.scale = d.scale;
  r.translucent = d.translucent;
  r.version = d.version;
  return r;
}

std::vector<std::uint32_t> GearsSolver::EdgeNeighbours() const
{
  std::vector<std::uint32_t> nbr;
  GlobalNeighbours(P->D, nbr);
  return nbr;
}

std::vector<float> GearsSolver::Solve(const LightFrame& light, const glm::dvec3& origin,
  const float* positions, const float* normals, std::size_t n, const GearsOptions& options,
  GearsStats* statsOut, std::vector<GearsMask>* masksOut, GearsAssignment* assignOut) const
{
  const auto tStart = Clock::now();
  GearsStats st;
  const Impl& I = *P;
  const SolverData* solverData = &I.D; // a far light's: the warped copy (below)
  // Buffers are kept between solves: re-mapping fresh pages every frame
  // cost more than some stages themselves. One solve at a time per solver.
  std::lock_guard<std::mutex> solveLock(I.SolveMutex);
  Impl::Scratch& WS = I.Work;
  // the winding count's neighbours, once per arrangement of the triangles
  // and only where it runs (not for the GL backend, translucent casters, ...)
  GearsOptions opt = options;
  bool winding = opt.windingCount && !I.D.translucent && opt.raster == GearsRaster::EdgePlane &&
    light.type != LightType::Point && opt.k > 1 &&
    (!opt.countNecessary || opt.necessaryWithWinding);
  if (winding && WS.neighbours.arrangement != I.D.arrangement)
  {
    const auto tn = Clock::now();
    BuildNeighbours(I.D, WS.neighbours);
    WS.neighbours.arrangement = I.D.arrangement;
    st.msPrepare += Ms(tn, Clock::now());
  }
  winding = winding && !WS.neighbours.nbr.empty();
  // automatic grid and group sizes: coarser where the winding count runs
  // (its cost per pixel does not grow with the lists; gears.md, measured)
  opt.grid = opt.grid > 0 ? opt.grid : (winding ? 64 : 128);
  opt.groupSize = opt.groupSize > 0 ? opt.groupSize : (winding ? 16 : 8);
  const int k = (light.type == LightType::Point) ? 1 : std::clamp(opt.k, 1, 32);
  const std::uint32_t fullRow = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
  st.grid = opt.grid;
  st.triangles = I.D.real;
  st.clusters = I.D.Clusters();
  std::vector<float> V(n, std::numeric_limits<float>::quiet_NaN());
  if (masksOut)
  {
    masksOut->assign(n, GearsMask{});
  }
  if (assignOut)
  {
    *assignOut = GearsAssignment{};
    assignOut->pixelFace.assign(n, -1);
    assignOut->pixelCell.assign(n, -1);
    assignOut->pixelGroup.assign(n, -1);
  }
  // Everything below works relative to the caster centre, in double.
  LightFrame L = light;
  L.center -= I.D.center;
  if (L.type == LightType::Directional)
  {
    // a directional light has no position: its frame's centre goes to the
    // caster centre, so depths and the culling margin (ft.margin) stay at the
    // scene's scale wherever the scene lies (else everything is kept far from
    // the world origin)
    L.center = glm::dvec3(0.0);
  }
  const glm::dvec3 rel = origin - I.D.center;

  // --- step 2: pixel samples (ray starts), with the reference's rules
  auto& start = WS.start;
  auto& normal = WS.normal;
  auto& eps = WS.eps;
  auto& face = WS.face;
  start.resize(n);
  normal.resize(n);
  eps.assign(n, 0.0);
  face.assign(n, -1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
    {
      const float* pf = positions + 3 * i;
      if (!(std::isfinite(pf[0]) && std::isfinite(pf[1]) && std::isfinite(pf[2])))
      {
        continue; // background
      }
      const glm::dvec3 p = rel + glm::dvec3(pf[0], pf[1], pf[2]);
      glm::dvec3 N(0.0);
      if (normals)
      {
        N = glm::dvec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
        const double l = glm::length(N);
        N = (l > 0.0 && std::isfinite(l)) ? N / l : glm::dvec3(0.0);
      }
      if (L.type == LightType::Rect && glm::dot(p - L.center, L.n) <= 0.0)
      {
        V[i] = 0.0f; // behind the one-sided light
        if (masksOut)
        {
          (*masksOut)[i].fill(fullRow);
        }
        continue;
      }
      eps[i] = StartOffset(p, I.D.scale, DistanceToLight(L, p - L.center)); // p, L relative to the centre
      start[i] = p + N * eps[i];
      normal[i] = N;
      if (L.type == LightType::Point)
      {
        // cube faces around the light: +x -x +y -y +z -z
        const glm::dvec3 d = start[i] - L.center;
        const glm::dvec3 a = glm::abs(d);
        const int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
        if (!(a[axis] > 0.0))
        {
          V[i] = 1.0f; // at the light itself: nothing lies between
          continue;
        }
        face[i] = static_cast<std::int8_t>(2 * axis + (d[axis] < 0.0 ? 1 : 0));
      }
      else
      {
        face[i] = 0;
      }
    }
  });

  // --- a far rect or point light: the exact projective map to a directional
  // light (ssGearsFarLight.cxx), when every start point lies well in front
  FarLightWarp warp;
  LightFrame warpedL;
  std::uint64_t dataStamp = 0; // which triangles: 0 the solver's, else the warped copy's
  if (opt.farLightWarp && MakeFarLightWarp(L, I.D.extent, warp, warpedL))
  {
    bool inFront = true;
    for (std::size_t i = 0; i < n && inFront; ++i)
    {
      inFront = face[i] < 0 || warp.InFront(start[i]);
    }
    if (inFront)
    {
      const auto tw = Clock::now();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
        {
          if (face[i] >= 0)
          {
            normal[i] = warp.Normal(start[i], normal[i]);
            eps[i] *= warp.Reach(start[i]); // the start rule's reach, in the mapped frame
            start[i] = warp.Point(start[i]);
            face[i] = 0; // a point light's cube faces become the one face
          }
        }
      });
      if (WS.warpedGeneration != I.generation || !SameLight(WS.warpedFrom, L))
      {
        WS.warpedGeneration = 0; // invalid while it is rebuilt
        WarpSolverData(I.D, warp, WS.warped);
        WS.warpedGeneration = I.generation;
        WS.warpedFrom = L;
        static std::atomic<std::uint64_t> stamps{ 0 };
        WS.warpedStamp = ++stamps;
      }
      solverData = &WS.warped;
      dataStamp = WS.warpedStamp;
      L = warpedL;
      st.farLightWarped = true;
      st.msPrepare += Ms(tw, Clock::now());
    }
  }
  if (dataStamp == 0 && WS.warpedGeneration != 0)
  {
    // a near light again: the mapped copy (as large as the solver's triangles) goes
    WS.warped = SolverData{};
    WS.warpedGeneration = 0;
  }
  const SolverData& D = *solverData;
  const glm::dvec2 sides = SampleSides(L);
  // (the vector kernels address the solver's floats with 32-bit offsets:
  // past 238M triangles the scalar ones, whose offsets are 64-bit; the
  // triangles solved, a far light's mapped copy with its own occluders)
  const Isa isa = KernelOffsetsFit(D.Triangles()) ? ResolveIsa(opt.simd) : Isa::Scalar;
  st.simd = IsaName(isa);

  const int numFaces = (L.type == LightType::Point) ? 6 : 1;
  const HalfPlaneLUT* lut = nullptr;
  if (opt.raster == GearsRaster::LUT && k > 1)
  {
    lut = &I.GetLUT(k, std::clamp(opt.lutResolution, 16, 4096));
  }
  CellCounters counters;
  std::size_t sumTrisPerCell = 0;
  bool stopped = false; // opt.progress asked to stop

  for (int f = 0; f < numFaces; ++f)
  {
    auto t0 = Clock::now();
    // --- 3.1, 3.2: camera C, grid, samples to cells
    FaceGrid& g = WS.grid;
    BuildFaceGrid(L, f, start, face, n, opt, g);
    if (g.pix.empty())
    {
      continue;
    }
    const int G = g.C.G;
    const std::size_t NC = static_cast<std::size_t>(G) * G;
    st.samples += g.pix.size();
    st.gridCells += NC;
    st.nonEmptyCells += g.nonEmpty;
    for (std::size_t c = 0; c < NC; ++c)
    {
      st.samplesPerCellMax = std::max<std::size_t>(st.samplesPerCellMax, g.Count(c));
    }
    auto t1 = Clock::now();
    st.msProject += Ms(t0, t1);
    // --- the triangles in the face's light frame, the closed-mesh rule, clusters
    FaceTriangles& ft = WS.tris;
    if (WS.SamePreparation(I.generation, dataStamp, L, g.C, opt))
    {
      ++st.prepareReused;
    }
    else
    {
      WS.trisGeneration = 0; // invalid while it is rebuilt
      PrepareFaceTriangles(D, L, g.C, opt, ft);
      WS.trisGeneration = I.generation;
      WS.trisData = dataStamp;
      WS.trisLight = L;
      WS.trisFrame[0] = g.C.Lc;
      WS.trisFrame[1] = g.C.u;
      WS.trisFrame[2] = g.C.v;
      WS.trisFrame[3] = g.C.n;
      WS.trisClosedRule = opt.closedMeshRule;
      WS.trisDepthOrder = opt.depthOrder;
    }
    st.droppedTriangles += ft.dropped;
    auto t2 = Clock::now();
    st.msPrepare += Ms(t1, t2);
    // --- 3.3: cluster shadow volumes with P_far, pairs, sort by cell
    FacePairs& fp = WS.facePairs;
    BuildPairs(D, L, g, ft, opt, WS.pairs, fp, st);
    st.fullGridTriangles += fp.fullGrid;
    auto t3 = Clock::now();
    // --- step 4: per cell, per pixel [§4.2]
    CellJob job;
    job.D = &D;
    job.L = &L;
    job.g = &g;
    job.ft = &ft;
    job.pairs = &fp;
    job.start = &start;
    job.normal = &normal;
    job.opt = &opt;
    job.k = k;
    job.fullRow = fullRow;
    job.eps = eps.data();
    job.dir = L.type == LightType::Directional;
    job.W = sides.x;
    job.H = sides.y;
    job.lut = lut;
    job.isa = isa;
    job.V = V.data();
    job.masks = masksOut ? masksOut->data() : nullptr;
    job.neighbours = winding ? &WS.neighbours : nullptr;
    job.face = f;
    job.numFaces = numFaces;
    CellCounters cc;
    GearsAssignment::Face fa;
    stopped = !SolveCells(job, cc, assignOut ? &fa : nullptr, assignOut ? assignOut->pixelGroup.data() : nullptr);
    counters.Add(cc);
    st.trianglesPerCellMax = std::max(st.trianglesPerCellMax, cc.cellTrianglesMax);
    sumTrisPerCell += static_cast<std::size_t>(cc.cellTriangles);
    st.msRaster += Ms(t3, Clock::now());
    if (assignOut)
    {
      fa.grid = G;
      for (std::size_t q = 0; q < g.pix.size(); ++q)
      {
        assignOut->pixelFace[g.pix[q]] = static_cast<std::int32_t>(assignOut->faces.size());
        assignOut->pixelCell[g.pix[q]] = static_cast<std::int32_t>(g.pixCell[q]);
      }
      assignOut->faces.push_back(std::move(fa));
    }
    if (stopped)
    {
      break;
    }
  }
  st.pairs = sumTrisPerCell;
  st.trianglesPerCellAvg = st.nonEmptyCells ? static_cast<double>(sumTrisPerCell) / st.nonEmptyCells : 0.0;
  st.samplesPerCellAvg = st.nonEmptyCells ? static_cast<double>(st.samples) / st.nonEmptyCells : 0.0;
  st.assignmentsListed = counters.listed;
  st.assignmentsTotal = counters.total;
  st.assignmentsRasterised = counters.rasterised;
  st.assignmentsNecessary = opt.countNecessary ? counters.necessary : -1.0;
  st.clustersCulled = counters.clustersCulled;
  st.trianglesCulled = counters.trianglesCulled;
  st.clustersBelowHorizon = counters.clustersBelowHorizon;
  st.trianglesBelowHorizon = counters.trianglesBelowHorizon;
  st.clustersBehindOccluders = counters.clustersBehindOccluders;
  st.groups = counters.groups;
  st.coveredSkips = counters.coveredSkips;
  st.outsidePyramid = counters.outsidePyramid;
  st.occluderBoxes = D.occPiece.size();
  st.cpuCellLists = counters.msLists;
  st.cpuGroups = counters.msGroups;
  st.cpuPixels = counters.msExact;
  st.cellsInUmbra = counters.cellsInUmbra;
  st.occluderDrawsStopped = counters.occluderDrawsStopped;
  st.lutFallbacks = counters.lutFallbacks;
  st.windingPixels = counters.windingPixels;
  st.windingDeclined = counters.windingDeclined;
  st.windingMembers = counters.windingMembers;
  st.windingRest = counters.windingRest;
  st.filteredPairs = counters.filtered;
  st.windingContour = counters.windingContour;
  st.windingTested = counters.windingTested;
  st.contourTriangles = counters.contourTriangles;
  st.contourNecessary = opt.countNecessary && opt.necessaryWithWinding ? counters.contourNecessary : -1.0;
  st.contourEdgesNecessary = opt.countNecessary && opt.necessaryWithWinding ? counters.contourEdgesNecessary : -1.0;
  st.msTotal = Ms(tStart, Clock::now());
  if (statsOut)
  {
    *statsOut = st;
  }
  return V;
}

void AddGearsStats(GearsStats& a, const GearsStats& st)
{
  // -1 is "not counted": a solve that did not count makes the sum -1
  auto counted = [](double sum, double add) { return add < 0.0 ? -1.0 : std::max(sum, 0.0) + add; };
  a.msProject += st.msProject;
  a.msPrefixSum += st.msPrefixSum;
  a.msRelate += st.msRelate;
  a.msSort += st.msSort;
  a.msRaster += st.msRaster;
  a.msTotal += st.msTotal;
  a.triangles = st.triangles;
  a.samples += st.samples;
  a.gridCells += st.gridCells;
  a.grid = st.grid;
  a.layers = std::max(a.layers, st.layers);
  a.layersRetried += st.layersRetried;
  a.pairs += st.pairs;
  a.trianglesPerCellMax = std::max(a.trianglesPerCellMax, st.trianglesPerCellMax);
  a.samplesPerCellMax = std::max(a.samplesPerCellMax, st.samplesPerCellMax);
  // averages over all non-empty cells of the solves folded in
  const std::size_t cells = a.nonEmptyCells + st.nonEmptyCells;
  a.trianglesPerCellAvg = cells ? (a.trianglesPerCellAvg * a.nonEmptyCells + st.trianglesPerCellAvg * st.nonEmptyCells) /
      static_cast<double>(cells)
                                : 0.0;
  a.nonEmptyCells = cells;
  a.samplesPerCellAvg = cells ? static_cast<double>(a.samples) / cells : 0.0;
  a.assignmentsTotal += st.assignmentsTotal;
  a.assignmentsNecessary = counted(a.assignmentsNecessary, st.assignmentsNecessary);
  a.fullGridTriangles += st.fullGridTriangles;
  a.lutFallbacks += st.lutFallbacks;
  a.msPrepare += st.msPrepare;
  a.prepareReused += st.prepareReused;
  a.clusters = st.clusters;
  a.clusterPairs += st.clusterPairs;
  a.droppedTriangles += st.droppedTriangles;
  a.clustersCulled += st.clustersCulled;
  a.trianglesCulled += st.trianglesCulled;
  a.clustersBelowHorizon += st.clustersBelowHorizon;
  a.trianglesBelowHorizon += st.trianglesBelowHorizon;
  a.clustersBehindOccluders += st.clustersBehindOccluders;
  a.groups += st.groups;
  a.assignmentsListed += st.assignmentsListed;
  a.assignmentsRasterised += st.assignmentsRasterised;
  a.coveredSkips += st.coveredSkips;
  a.outsidePyramid += st.outsidePyramid;
  a.occluderBoxes = st.occluderBoxes;
  a.simd = st.simd;
  a.farLightWarped = a.farLightWarped || st.farLightWarped;
  a.cpuCellLists += st.cpuCellLists;
  a.cpuGroups += st.cpuGroups;
  a.cpuPixels += st.cpuPixels;
  a.cellsInUmbra += st.cellsInUmbra;
  a.occluderDrawsStopped += st.occluderDrawsStopped;
  a.windingPixels += st.windingPixels;
  a.windingDeclined += st.windingDeclined;
  a.filteredPairs += st.filteredPairs;
  a.windingMembers += st.windingMembers;
  a.windingRest += st.windingRest;
  a.windingContour += st.windingContour;
  a.windingTested += st.windingTested;
  a.contourTriangles += st.contourTriangles;
  a.contourNecessary = counted(a.contourNecessary, st.contourNecessary);
  a.contourEdgesNecessary = counted(a.contourEdgesNecessary, st.contourEdgesNecessary);
}

std::string GearsStatsToJSON(const GearsStats& s)
{
  std::ostringstream o;
  o << "{\"ms\": {\"project\": " << s.msProject << ", \"prefix_sum\": " << s.msPrefixSum
    << ", \"relate\": " << s.msRelate << ", \"sort\": " << s.msSort << ", \"raster\": " << s.msRaster
    << ", \"total\": " << s.msTotal << "}, \"triangles\": " << s.triangles << ", \"samples\": " << s.samples
    << ", \"grid\": " << s.grid << ", \"gl_layers\": " << s.layers << ", \"gl_layers_retried\": " << s.layersRetried
    << ", \"grid_cells\": " << s.gridCells << ", \"non_empty_cells\": " << s.nonEmptyCells
    << ", \"pairs\": " << s.pairs << ", \"triangles_per_cell\": {\"max\": " << s.trianglesPerCellMax
    << ", \"avg\": " << s.trianglesPerCellAvg << "}, \"samples_per_cell\": {\"max\": " << s.samplesPerCellMax
    << ", \"avg\": " << s.samplesPerCellAvg << "}, \"assignments\": {\"total\": " << s.assignmentsTotal
    << ", \"necessary\": " << s.assignmentsNecessary << "}, \"full_grid_triangles\": " << s.fullGridTriangles
    << ", \"lut_fallbacks\": " << s.lutFallbacks << ", \"simd\": \"" << s.simd << "\", \"ms_prepare\": " << s.msPrepare
    << ", \"clusters\": " << s.clusters << ", \"cluster_pairs\": " << s.clusterPairs
    << ", \"dropped_triangles\": " << s.droppedTriangles << ", \"clusters_culled\": " << s.clustersCulled
    << ", \"triangles_culled\": " << s.trianglesCulled << ", \"clusters_below_horizon\": " << s.clustersBelowHorizon
    << ", \"triangles_below_horizon\": " << s.trianglesBelowHorizon
    << ", \"clusters_behind_occluders\": " << s.clustersBehindOccluders << ", \"prepare_reused\": " << s.prepareReused
    << ", \"groups\": " << s.groups
    << ", \"covered_skips\": " << s.coveredSkips << ", \"outside_pyramid\": " << s.outsidePyramid
    << ", \"occluder_boxes\": " << s.occluderBoxes
    << ", \"far_light_warped\": " << (s.farLightWarped ? "true" : "false")
    << ", \"assignments_listed\": " << s.assignmentsListed << ", \"assignments_rasterised\": " << s.assignmentsRasterised
    << ", \"cpu_ms\": {\"cell_lists\": " << s.cpuCellLists
    << ", \"groups\": " << s.cpuGroups << ", \"pixels\": " << s.cpuPixels << "}, \"cells_in_umbra\": " << s.cellsInUmbra
    << ", \"occluder_draws_stopped\": " << s.occluderDrawsStopped
    << ", \"winding\": {\"pixels\": " << s.windingPixels << ", \"declined\": " << s.windingDeclined
    << ", \"members\": " << s.windingMembers << ", \"rest\": " << s.windingRest
    << ", \"contour_edges\": " << s.windingContour << ", \"contour_tested\": " << s.windingTested
    << ", \"contour_triangles\": " << s.contourTriangles << ", \"contour_necessary\": " << s.contourNecessary
    << ", \"contour_edges_necessary\": " << s.contourEdgesNecessary << "}, \"filtered_pairs\": " << s.filteredPairs
    << "}";
  return o.str();
}
}
