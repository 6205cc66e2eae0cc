// GEARS on the GPU (GL 4.3 compute). The kernels are in glsl/ssGearsCS*.glsl;
// this file sizes the buffers, dispatches the stages in the order of the CPU
// backend (Rendering/Core/ssGEARS.cxx) and collects the paper's statistics.
#include "ssGearsGL.h"
#include "ssGLLimits.h"
#include "ssGearsGLImpl.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{

GearsGL::GearsGL()
  : P(new Impl)
{
}

GearsGL::~GearsGL() = default;

bool GearsGL::Supported(std::string* why)
{
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 43 || !glDispatchCompute || !glClearBufferSubData || !glUniform1d)
  {
    if (why)
    {
      std::ostringstream o;
      o << "GEARS GL backend needs OpenGL 4.3 (compute shaders, SSBOs, doubles); this context is " << major << "."
        << minor;
      *why = o.str();
    }
    return false;
  }
  return true;
}

void GearsGL::ReleaseGraphicsResources()
{
  P->Release();
}

bool GearsGL::Solve(const GearsSolver& solver, const LightFrame& light, const glm::dvec3& origin,
  const float* positions, const float* normals, std::size_t n, const GearsOptions& opt, std::vector<float>& V,
  GearsStats* statsOut, std::vector<GearsMask>* masksOut, std::string* why)
{
  const auto tStart = Clock::now();
  Impl& I = *P;
  const int k = (light.type == LightType::Point) ? 1 : std::clamp(opt.k, 1, 32);
  if (opt.raster == GearsRaster::LUT && k > 1)
  {
    if (why)
    {
      *why = "GEARS GL backend rasterises by edge planes only (LUT: CPU)";
    }
    return false;
  }
  if (!Supported(why))
  {
    return false;
  }
  if (solver.Data().translucent)
  {
    // per-sample transmittance (k^2 floats per pixel) cannot persist between
    // the chunked raster dispatches
    if (why)
    {
      *why = "GEARS GL backend: translucent casters run on the CPU backend";
    }
    return false;
  }
  if (std::clamp(opt.grid > 0 ? opt.grid : 128, 1, 4096) > kMaxGrid)
  {
    if (why)
    {
      *why = "GEARS GL backend: grids above " + std::to_string(kMaxGrid) +
        " cells per side run on the CPU (a full-grid triangle's pair loop would pass llvmpipe's 65535-iteration budget)";
    }
    return false;
  }
  if (!I.MaxBlock)
  {
    // queried in 64 bits (GPUs report 2 GB and more); lowered by
    // SOFTSHADOWS_GL_MAX_SSBO_BYTES (and the bindings by
    // SOFTSHADOWS_GL_MAX_SSBO_BINDINGS) to test a smaller GPU's path
    const GLLimits limits = QueryGLLimits();
    I.MaxBlock = limits.maxSSBOBytes;
    I.MaxBindings = limits.maxSSBOBindings;
    I.MaxKernelBlocks = limits.maxComputeSSBOBlocks;
  }
  if (I.MaxBindings < NumBindings || I.MaxKernelBlocks < kMaxKernelBlocks)
  {
    // each buffer has its own binding point (glsl/ssGearsCSCommon.glsl), and
    // the bitmask kernel declares 13 buffers; GL 4.3 guarantees 8 of each
    if (why)
    {
      std::ostringstream o;
      o << "GEARS GL backend: needs " << static_cast<int>(NumBindings) << " shader storage buffer bindings and "
        << kMaxKernelBlocks << " storage blocks per compute shader; this context has " << I.MaxBindings << " and "
        << I.MaxKernelBlocks;
      *why = o.str();
    }
    return false;
  }
  // GL 4.3 guarantees 2^24 bytes (used if the query gave nothing)
  const std::size_t maxBlock = static_cast<std::size_t>(I.MaxBlock > 0 ? I.MaxBlock : (1 << 24));
  auto fits = [&](std::size_t bytes, const char* what) {
    if (bytes <= maxBlock)
    {
      return true;
    }
    if (why)
    {
      std::ostringstream o;
      o << "GEARS GL backend: " << what << " need " << bytes << " bytes, more than this context's SSBO limit of "
        << maxBlock;
      *why = o.str();
    }
    return false;
  };
  const GearsTriangleData D = solver.Data();
  const std::size_t NT = D.count;
  const int G = std::clamp(opt.grid > 0 ? opt.grid : 128, 1, 4096); // 0: automatic, the raster's 128
  const std::size_t NC = static_cast<std::size_t>(G) * G;
  // each grid cell's samples split by depth into this many list cells
  // (K_CELL); without the shafts pass 1 counts grid cells (its summed-area
  // table), so one; where a solve of these triangles found the layers' pairs
  // too many for a buffer, one
  int layers = opt.shaftCulling && (I.LayersFit || I.TriVersion != D.version)
    ? std::clamp(opt.depthLayers, 1, kMaxLayers)
    : 1;
  // a cell's list in depth order (GearsOptions::depthOrder): one sort key per
  // (cell, depth bucket); off, one bucket per cell
  const std::size_t buckets = opt.depthOrder ? kDepthBuckets : 1;
  int levels = 1;
  while ((1 << levels) <= G)
  {
    ++levels;
  }
  if (!fits(48 * n, "pixel samples") || !fits(9 * 4 * NT, "triangles") || !fits(128 * n, "bitmasks") ||
    !fits(4 * NT, "the closed-mesh flags") ||
    (opt.retractToFarthest && !fits(4 * NC * levels * levels, "the grid's range-maximum table")) ||
    n > 0xFFFFFFF0u || NT > 0xFFFFFFF0u)
  {
    return false;
  }
  // the winding count (glsl/ssGearsCSWinding.glsl): where the CPU backend's
  // would run, with the triangles' light-frame copy (K_TOLIGHT) and the
  // buffers it needs
  const bool dirLight0 = light.type == LightType::Directional;
  const double W0 = dirLight0 ? 2.0 * std::tan(0.5 * light.angularDiameter) : light.width;
  const double H0 = dirLight0 ? W0 : light.height;
  const bool pre = 72 * NT <= maxBlock; // (the triangles' light-frame copy fits)
  const bool windingBlocks = I.MaxKernelBlocks >= kWindingKernelBlocks;
  bool winding = opt.windingCount && !opt.countNecessary && k > 1 && pre && windingBlocks && W0 > 0.0 &&
    H0 > 0.0 && NT > 0 && NT <= 0x3FFFFFFFu && 16 * NT <= maxBlock;
  // the sort's keys (cellBegin, cursor): per list cell the depth buckets,
  // times 4 with the winding count; fewer layers where they would not fit
  // one buffer (GL 4.3 guarantees 16 MB: a grid of 240 with 4 layers needs 59)
  const std::size_t keysPerList = buckets * (winding ? 4 : 1);
  while (layers > 1 && 4 * (NC * layers * keysPerList + 1) > maxBlock)
  {
    --layers;
  }
  if (!fits(4 * (NC * layers * keysPerList + 1), "the cells' sort keys"))
  {
    return false;
  }
  const char* names[] = { "K_START", "K_PROJECT", "K_CELL", "K_SAT_ROWS", "K_SAT_COLS", "K_RMQ", "K_PASS1",
    "K_PASS2", "K_HIST", "K_SCATTER", "K_PIXSORT", "K_TOLIGHT", "K_RASTER", "K_FINISH", "K_WFLAG", "K_WINDING" };
  std::map<std::string, GLuint> prog;
  for (const char* nm : names)
  {
    const std::string name = nm;
    if (!winding && (name == "K_WFLAG" || name == "K_WINDING"))
    {
      continue;
    }
    // (K_RASTER reads wind[] where the context has the blocks; where the
    // count runs, K_TOLIGHT writes the planes and K_SCATTER copies the
    // pairs' statuses)
    const bool w =
      (name == "K_RASTER" && windingBlocks) || ((name == "K_SCATTER" || name == "K_TOLIGHT") && winding);
    prog[nm] = I.Program(nm, why, w ? "WINDING" : nullptr);
    if (!prog[nm])
    {
      return false;
    }
  }

  GearsStats st;
  st.triangles = NT;
  const std::uint32_t fullRow = k == 32 ? 0xFFFFFFFFu : ((1u << k) - 1u);
  LightFrame L = light;
  L.center -= D.center;
  if (L.type == LightType::Directional)
  {
    // a directional light has no position: its frame's centre goes to the
    // caster centre, so depths and the culling margin (ft.margin) stay at the
    // scene's scale wherever the scene lies (else everything is kept far from
    // the world origin)
    L.center = glm::dvec3(0.0);
  }
  const glm::dvec3 rel = origin - D.center;
  const double T = (L.type == LightType::Directional) ? 2.0 * std::tan(0.5 * L.angularDiameter) : 0.0;
  const int type = L.type == LightType::Rect ? 0 : (L.type == LightType::Directional ? 1 : 2);

  // --- inputs
  if (I.TriVersion != D.version || !I.Buf[BTriV].id)
  {
    I.Upload(I.Buf[BTriV], D.vertices, 9 * 4 * NT);
    I.Upload(I.Buf[BTriA], D.opacity, 4 * NT);
    I.TriVersion = D.version;
    I.NbrVersion = 0;
    I.LayersFit = true;
  }
  if (winding && I.NbrVersion != D.version)
  {
    // the edge neighbours, once per set of triangles (counted in msPrepare)
    const auto tn = Clock::now();
    const std::vector<std::uint32_t> nbr = solver.EdgeNeighbours();
    if (nbr.size() == 3 * NT)
    {
      I.Upload(I.Buf[BNbr], nbr.data(), 4 * nbr.size());
      I.NbrVersion = D.version;
    }
    st.msPrepare += Ms(tn, Clock::now());
  }
  if (winding && I.NbrVersion != D.version)
  {
    // (no table: the count does not run, and neither do its kernels' variants)
    winding = false;
    prog["K_SCATTER"] = I.Program("K_SCATTER", why);
    prog["K_TOLIGHT"] = I.Program("K_TOLIGHT", why);
  }
  {
    // the closed-mesh rule of the CPU backend, for this light
    const std::vector<std::int8_t> flags8 = solver.ClosedRuleFlags(light, opt);
    std::vector<std::int32_t> flags(flags8.begin(), flags8.end());
    I.Upload(I.Buf[BClosed], flags.data(), 4 * flags.size());
  }
  I.Upload(I.Buf[BPos], positions, 12 * n);
  if (normals)
  {
    I.Upload(I.Buf[BNrm], normals, 12 * n);
  }
  else
  {
    I.Fill(I.Buf[BNrm], 12 * n, 0u);
  }
  I.Ensure(I.Buf[BSmp], 56 * n);
  I.Ensure(I.Buf[BFace], 4 * n);
  const float nanf = std::numeric_limits<float>::quiet_NaN();
  std::uint32_t nanBits;
  std::memcpy(&nanBits, &nanf, 4);
  I.Fill(I.Buf[BVis], 4 * n, nanBits);
  std::vector<std::uint32_t> red(64, 0u);
  for (int f = 0; f < 6; ++f)
  {
    for (int c = 0; c < 3; ++c)
    {
      red[8 * f + c] = 0xFFFFFFFFu;
    }
    red[8 * f + 6] = Ord(0.0f);
  }
  red[61] = Ord(0.0f); // (atomicMax: the largest start offset)
  I.Upload(I.Buf[BRed], red.data(), 4 * red.size());
  I.Ensure(I.Buf[BPixCell], 4 * n);
  I.Fill(I.Buf[BMasks], 128 * n, 0u); // the bitmasks: the raster's state between chunks
  if (opt.countNecessary)
  {
    I.Fill(I.Buf[BNec], 4 * n, 0u);
  }
  // every binding needs a buffer, even where a kernel does not use it
  for (int b = 0; b < NumBindings; ++b)
  {
    I.Ensure(I.Buf[b], 16);
  }

  // --- step 2: pixel samples, per-face 3-D AABBs and far depths
  auto t0 = Clock::now();
  I.Use(prog["K_START"]);
  I.U3("uRel", rel);
  I.U3("uLc", L.center);
  I.U3("uLn", L.n);
  I.Ud("uScale", D.scale);
  I.U3("uLu", L.u);
  I.U3("uLv", L.v);
  I.U2d("uLhalf", 0.5 * L.width, 0.5 * L.height);
  I.U("uType", type);
  I.Uu("uFullRow", fullRow);
  I.Items(n);
  I.Download(I.Buf[BRed], red.data(), 4 * 62);
  const double epsMax = Unord(red[61]);

  const int numFaces = (L.type == LightType::Point) ? 6 : 1;
  double assignmentsTotal = 0, assignmentsNecessary = 0;
  std::size_t sumTrisPerCell = 0;
  const double diag = (L.type == LightType::Rect) ? std::hypot(L.width, L.height) : 0.0;
  glFinish();
  auto t1 = Clock::now();
  st.msProject += Ms(t0, t1);
  const bool dirLight = L.type == LightType::Directional;
  const double W = dirLight ? T : L.width, H = dirLight ? T : L.height;
  // the shaft test of passes 1 and 2 (double, on float-rounded boxes) keeps
  // the CPU's margin (ft.margin, ssGearsPairs.cxx): far above the rounding,
  // and wide enough that a sliver's ill-conditioned edge planes in the raster
  // cannot reach a sample from a triangle the test drops
  const double shaftMargin = 1e-5 * (D.extent + glm::length(L.center) + W + H);
  for (int f = 0; f < numFaces; ++f)
  {
    t0 = Clock::now();
    if (red[8 * f] == 0xFFFFFFFFu)
    {
      continue; // no pixel sample on this face
    }
    glm::dvec3 lo, hi;
    for (int c = 0; c < 3; ++c)
    {
      lo[c] = Unord(red[8 * f + c]);
      hi[c] = Unord(red[8 * f + 3 + c]);
    }
    GearsGridCamera C = GearsFaceCamera(L, f, lo, hi, opt.eyeDistance);
    const double maxDepth = Unord(red[8 * f + 6]);
    int faceLayers = layers; // (K_CELL; fewer where the pairs do not fit)
    auto cameraUniforms = [&]() {
      I.U("uFace", f);
      I.U("uG", G);
      I.U("uLayers", faceLayers);
      I.U("uOrtho", C.ortho ? 1 : 0);
      I.U3("uE", C.E);
      I.U3("uLc", C.Lc);
      I.U3("uU", C.u);
      I.U3("uV", C.v);
      I.U3("uNrm", C.n);
      I.Ud("uGx0", C.gx0);
      I.Ud("uGy0", C.gy0);
      I.Ud("uSx", C.sx);
      I.Ud("uSy", C.sy);
    };
    // the cell shafts of passes 1 and 2
    auto shaftUniforms = [&]() {
      I.U("uShaft", opt.shaftCulling ? 1 : 0);
      I.U("uDir", dirLight ? 1 : 0);
      I.Ud("uW", W);
      I.Ud("uH", H);
      I.Ud("uShaftMargin", shaftMargin);
    };
    // --- 3.2: the grid over the projected samples, samples to cells
    const std::uint32_t init2[4] = { 0xFFFFFFFFu, 0xFFFFFFFFu, 0u, 0u };
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, I.Buf[BRed].id);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 4 * 48, 16, init2);
    I.Use(prog["K_PROJECT"]);
    cameraUniforms();
    I.Items(n);
    std::uint32_t box2[4];
    I.Download(I.Buf[BRed], box2, 16, 4 * 48);
    GearsFitGrid(C, G, Unord(box2[0]), Unord(box2[2]), Unord(box2[1]), Unord(box2[3]));
    // (a second round without layers where their pairs do not fit)
    std::size_t NL = NC * faceLayers, samples = 0, numPairs = 0;
    std::vector<std::uint32_t> cellCount;
    // this face once more without layers (fewer pairs), and the next solves
    // of these triangles too; pass 1's time so far counts as its stage's
    auto oneLayer = [&]() {
      faceLayers = 1;
      NL = NC;
      I.LayersFit = false;
      t0 = Clock::now();
      st.msPrefixSum += Ms(t1, t0);
    };
    for (;;)
    {
      I.Fill(I.Buf[BCellCnt], 4 * NL, 0u);
      // (per grid cell the farthest depth, the nearest, the depth bins in use;
      // sized first: a larger buffer would not keep the first fills)
      I.Ensure(I.Buf[BCellDep], 12 * NC);
      I.Fill(I.Buf[BCellDep], 4 * NC, Ord(-std::numeric_limits<float>::infinity()));
      I.Fill(I.Buf[BCellDep], 4 * NC, Ord(std::numeric_limits<float>::infinity()), 4 * NC);
      I.Fill(I.Buf[BCellDep], 4 * NC, 0u, 8 * NC); // (the bins in use: atomicOr)
      I.Fill(I.Buf[BCellBox], 24 * NL, 0xFFFFFFFFu); // (atomicMin on every slot)
      I.Use(prog["K_CELL"]);
      cameraUniforms();
      for (int stage = faceLayers > 1 ? 0 : 2; stage < 3; ++stage)
      {
        I.U("uStage", stage);
        I.Items(n);
      }
      cellCount.resize(NL);
      I.Download(I.Buf[BCellCnt], cellCount.data(), 4 * NL);
      samples = 0;
      for (std::size_t c = 0; c < NL; ++c)
      {
        samples += cellCount[c];
      }
      // the face's pixels cell by cell, for the bitmask kernel (K_PIXSORT)
      {
        std::vector<std::uint32_t> pixStart(NL + 1, 0u);
        for (std::size_t c = 0; c < NL; ++c)
        {
          pixStart[c + 1] = pixStart[c] + cellCount[c];
        }
        I.Upload(I.Buf[BPixStart], pixStart.data(), 4 * (NL + 1));
        I.Ensure(I.Buf[BPixOrder], 4 * std::max<std::size_t>(samples, 1));
        I.Fill(I.Buf[BCursor], 4 * NL, 0u);
        I.Use(prog["K_PIXSORT"]);
        I.U("uFace", f);
        I.Items(n);
      }
      // summed-area table of non-empty cells, range-maximum table of far depths
      I.Fill(I.Buf[BSat], 4 * (G + 1) * (G + 1), 0u);
      I.Use(prog["K_SAT_ROWS"]);
      I.U("uG", G);
      I.U("uLayers", faceLayers);
      I.Items(G);
      I.Use(prog["K_SAT_COLS"]);
      I.U("uG", G);
      I.Items(G);
      if (opt.retractToFarthest)
      {
        I.Ensure(I.Buf[BRmq], 4 * NC * levels * levels);
        I.Use(prog["K_RMQ"]);
        I.U("uG", G);
        I.U("uL", levels);
        for (int ly = 0; ly < levels; ++ly)
        {
          for (int lx = 0; lx < levels; ++lx)
          {
            I.U("uLx", lx);
            I.U("uLy", ly);
            I.Items(NC);
          }
        }
      }
      glFinish();
      t1 = Clock::now();
      st.msProject += Ms(t0, t1);

      // --- 3.3 pass 1 and the prefix sum of cellsN
      I.Ensure(I.Buf[BBox], 16 * NT);
      I.Fill(I.Buf[BOff], 4 * (NT + 1), 0u);
      const std::uint32_t zero = 0, none = 0xFFFFFFFFu; // (none: atomicMin)
      auto resetCounters = [&]() {
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, I.Buf[BRed].id);
        for (int q : { 56, 57, 58, 59 })
        {
          glBufferSubData(GL_SHADER_STORAGE_BUFFER, 4 * q, 4, &zero);
        }
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 4 * 60, 4, &none);
      };
      resetCounters();
      I.Use(prog["K_PASS1"]);
      cameraUniforms();
      shaftUniforms();
      I.U("uL", levels);
      I.Ud("uMaxDepth", maxDepth);
      I.Ud("uMinDepth", 1e-9 * std::max(D.extent, diag));
      I.U("uCorners", (L.type == LightType::Point) ? 1 : 4);
      I.U("uRetract", opt.retractToFarthest ? 1 : 0);
      {
        double corner[12], away[12];
        for (int c = 0; c < 4; ++c)
        {
          const double a = (c & 1) ? 0.5 : -0.5, b = (c & 2) ? 0.5 : -0.5;
          const glm::dvec3 co = L.center + a * L.width * L.u + b * L.height * L.v;
          const glm::dvec3 aw = L.n - a * T * L.u - b * T * L.v;
          for (int q = 0; q < 3; ++q)
          {
            corner[3 * c + q] = co[q];
            away[3 * c + q] = aw[q];
          }
        }
        glUniform3dv(I.Loc("uCorner"), 4, corner);
        glUniform3dv(I.Loc("uAway"), 4, away);
      }
      if (faceLayers > 1 && NT >= kLayerSample * kWG)
      {
        // the layers' pairs estimated from every kLayerSample-th triangle:
        // where they would not fit one buffer, one layer at once (where the
        // estimate falls short, the check after the full pass runs it again)
        I.Uu("uSample", static_cast<std::uint32_t>(kLayerSample));
        I.Uu("uN", static_cast<std::uint32_t>(NT));
        I.Dispatch((NT / kLayerSample + kWG) / kWG);
        const double estimate = double(kLayerSample) * I.ReadUint(I.Buf[BRed], 59);
        const bool wrapped = I.ReadUint(I.Buf[BRed], 57) != 0;
        I.Uu("uSample", 0u);
        resetCounters();
        if (wrapped || 4.0 * estimate > 0.9 * double(maxBlock))
        {
          oneLayer();
          continue;
        }
      }
      I.Items(NT);
      if (!I.Scan(I.Buf[BOff], NT + 1, 0, why))
      {
        return false;
      }
      numPairs = I.ReadUint(I.Buf[BOff], NT);
      const bool pairsWrapped = I.ReadUint(I.Buf[BRed], 57) != 0;
      if ((pairsWrapped || 4 * numPairs > maxBlock) && faceLayers > 1)
      {
        // more pairs than one buffer holds (or than 32 bits count)
        oneLayer();
        ++st.layersRetried;
        continue;
      }
      if (pairsWrapped)
      {
        if (why)
        {
          *why = "GEARS GL backend: more than 2^32 (triangle, cell) pairs";
        }
        return false;
      }
      if (!fits(4 * numPairs, "the (triangle, cell) pairs"))
      {
        return false;
      }
      break;
    }
    st.layers = std::max(st.layers, faceLayers);
    st.samples += samples;
    st.gridCells += NC;
    for (std::size_t c = 0; c < NL; ++c)
    {
      st.nonEmptyCells += cellCount[c] > 0;
      st.samplesPerCellMax = std::max<std::size_t>(st.samplesPerCellMax, cellCount[c]);
    }
    st.fullGridTriangles += I.ReadUint(I.Buf[BRed], 56);
    st.trianglesCulled += I.ReadUint(I.Buf[BRed], 58); // outside their cell's shaft
    st.pairs += numPairs;
    glFinish();
    auto t2 = Clock::now();
    st.msPrefixSum += Ms(t1, t2);

    // --- 3.3 pass 2: the pairs; keys per cell: the depth buckets, times the
    // winding count's four classes (K_WFLAG) where it runs
    const std::size_t cellKeys = buckets * (winding ? 4 : 1);
    I.Ensure(I.Buf[BPairTri], 4 * numPairs);
    I.Ensure(I.Buf[BPairCell], 4 * numPairs);
    I.Use(prog["K_PASS2"]);
    cameraUniforms();
    shaftUniforms();
    I.U("uBuckets", static_cast<int>(buckets));
    I.Uu("uCellKeys", static_cast<std::uint32_t>(cellKeys));
    I.Ud("uMaxDepth", maxDepth);
    I.Items(NT);
    glFinish();
    auto t3 = Clock::now();
    st.msRelate += Ms(t2, t3);

    // the winding count's margin: the shafts' plus 1e-6 of the face's reach
    // (the farthest start plus the farthest vertex from the light's centre)
    const glm::dvec3 reachS = glm::max(glm::abs(lo - C.Lc), glm::abs(hi - C.Lc));
    const double far = glm::length(reachS) + glm::length(C.Lc) + D.extent;
    const double windingMargin = shaftMargin + 1e-6 * far;
    // the triangles in the light's frame once per face, when the buffer fits
    if (pre)
    {
      I.Ensure(I.Buf[BTriL], 72 * NT);
      I.Ensure(I.Buf[BTriLF], 36 * NT);
      I.Use(prog["K_TOLIGHT"]);
      cameraUniforms();
      if (winding)
      {
        I.Ensure(I.Buf[BTriN], 16 * NT);
        I.U("uDir", dirLight ? 1 : 0);
        I.Ud("uW", W);
        I.Ud("uH", H);
        I.Ud("uMargin", windingMargin);
        I.Ud("uFar", far);
      }
      I.Items(NT);
    }
    const int hand = glm::dot(glm::cross(C.u, C.v), C.n) < 0.0 ? -1 : 1;
    if (windingBlocks)
    {
      I.Ensure(I.Buf[BWind], 4 * n); // (K_RASTER declares it whether or not the count runs)
    }
    if (winding)
    {
      // the winding count's statuses and contour edges per pair, and its
      // class in the cell's list
      I.Ensure(I.Buf[BPairStat], 4 * numPairs);
      I.Ensure(I.Buf[BSlotStat], 4 * numPairs);
      I.Use(prog["K_WFLAG"]);
      cameraUniforms();
      shaftUniforms();
      I.Ud("uEpsMax", epsMax);
      I.Ud("uMargin", windingMargin);
      I.U("uHand", hand);
      I.Uu("uBuckets", static_cast<std::uint32_t>(buckets));
      I.Uu("uCellKeys", static_cast<std::uint32_t>(cellKeys));
      I.Items(numPairs);
      glFinish();
      const auto tw = Clock::now();
      st.msRelate += Ms(t3, tw);
      t3 = tw;
    }

    // --- sort on the key (K_PASS2, K_WFLAG): counting sort (histogram,
    // prefix sum, scatter); cell c's list is the keys c K .. (c + 1) K - 1
    // (K = cellKeys), in each class nearest the receivers first
    const std::size_t NB = NL * cellKeys;
    I.Fill(I.Buf[BCellBegin], 4 * (NB + 1), 0u);
    I.Fill(I.Buf[BCursor], 4 * NB, 0u);
    I.Ensure(I.Buf[BSorted], 4 * numPairs);
    I.Use(prog["K_HIST"]);
    I.Items(numPairs);
    if (!I.Scan(I.Buf[BCellBegin], NB + 1, 0, why))
    {
      return false;
    }
    I.Use(prog["K_SCATTER"]);
    I.Items(numPairs);
    std::vector<std::uint32_t> cellBegin(NB + 1);
    I.Download(I.Buf[BCellBegin], cellBegin.data(), 4 * (NB + 1));
    std::size_t longestList = 0;
    const std::size_t drawnKeys = std::min(cellKeys, 3 * buckets); // (class 3 is never drawn)
    for (std::size_t c = 0; c < NL; ++c)
    {
      if (cellCount[c])
      {
        const std::size_t nt = cellBegin[(c + 1) * cellKeys] - cellBegin[c * cellKeys];
        const std::size_t drawn = cellBegin[c * cellKeys + drawnKeys] - cellBegin[c * cellKeys];
        longestList = std::max(longestList, drawn);
        st.trianglesPerCellMax = std::max(st.trianglesPerCellMax, nt);
        sumTrisPerCell += nt;
        assignmentsTotal += static_cast<double>(nt) * cellCount[c];
        if (winding)
        {
          // (the CPU's members and rest, summed over lists instead of groups)
          const std::size_t rest = cellBegin[c * cellKeys + 2 * buckets] - cellBegin[c * cellKeys + buckets];
          st.windingRest += static_cast<double>(rest);
          st.windingMembers += static_cast<double>(drawn - rest);
        }
      }
    }
    glFinish();
    auto t4 = Clock::now();
    st.msSort += Ms(t3, t4);

    // --- step 4: the bitmasks (first the winding count's, where it runs)
    const double hx = (0.5 - 0.5 / k) * W, hy = (0.5 - 0.5 / k) * H;
    const double slackX = 1e-7 * (W / k) + 1e-12 * D.extent, slackY = 1e-7 * (H / k) + 1e-12 * D.extent;
    if (winding)
    {
      I.Use(prog["K_WINDING"]);
      cameraUniforms();
      I.U("uK", k);
      I.U("uDir", dirLight ? 1 : 0);
      I.Ud("uW", W);
      I.Ud("uH", H);
      I.Ud("uInvK", 1.0 / k);
      I.Uu("uBuckets", static_cast<std::uint32_t>(buckets));
      I.Uu("uCellKeys", static_cast<std::uint32_t>(cellKeys));
      I.Uu("uMinList", static_cast<std::uint32_t>(std::max(0, opt.windingMinList)));
      I.Items(samples);
    }
    I.Use(prog["K_RASTER"]);
    cameraUniforms();
    I.U("uPre", pre ? 1 : 0);
    I.U("uHand", hand);
    I.Ud("uInvK", 1.0 / k);
    I.U("uK", k);
    I.U("uDir", dirLight ? 1 : 0);
    I.U("uCountNecessary", opt.countNecessary ? 1 : 0);
    I.Uu("uFullRow", fullRow);
    I.Ud("uW", W);
    I.Ud("uH", H);
    I.Ud("uXlo", -hx - slackX);
    I.Ud("uXhi", hx + slackX);
    I.Ud("uYlo", -hy - slackY);
    I.Ud("uYhi", hy + slackY);
    I.Uu("uChunkSize", kChunk);
    if (windingBlocks)
    {
      I.U("uWinding", winding ? 1 : 0);
    }
    I.Uu("uBuckets", static_cast<std::uint32_t>(buckets));
    I.Uu("uCellKeys", static_cast<std::uint32_t>(cellKeys));
    const std::size_t chunks = std::max<std::size_t>(1, (longestList + kChunk - 1) / kChunk);
    for (std::size_t ch = 0; ch < chunks; ++ch)
    {
      I.Uu("uChunk", static_cast<std::uint32_t>(ch));
      I.Items(samples);
    }
    I.Use(prog["K_FINISH"]);
    I.U("uFace", f);
    I.U("uK", k);
    I.Uu("uFullRow", fullRow);
    I.Items(n);
    glFinish();
    st.msRaster += Ms(t4, Clock::now());
  }
  if (winding)
  {
    st.windingPixels = I.ReadUint(I.Buf[BRed], 62);
    st.windingDeclined = I.ReadUint(I.Buf[BRed], 63);
  }
  V.resize(n);
  I.Download(I.Buf[BVis], V.data(), 4 * n);
  if (masksOut)
  {
    masksOut->assign(n, GearsMask{});
    I.Download(I.Buf[BMasks], masksOut->data(), 128 * n);
  }
  if (opt.countNecessary)
  {
    std::vector<std::uint32_t> nec(n);
    I.Download(I.Buf[BNec], nec.data(), 4 * n);
    for (std::uint32_t v : nec)
    {
      assignmentsNecessary += v;
    }
  }
  glUseProgram(0);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  st.trianglesPerCellAvg = st.nonEmptyCells ? static_cast<double>(sumTrisPerCell) / st.nonEmptyCells : 0.0;
  st.samplesPerCellAvg = st.nonEmptyCells ? static_cast<double>(st.samples) / st.nonEmptyCells : 0.0;
  st.assignmentsTotal = assignmentsTotal;
  st.assignmentsNecessary = opt.countNecessary ? assignmentsNecessary : -1.0;
  st.msTotal = Ms(tStart, Clock::now());
  if (statsOut)
  {
    *statsOut = st;
  }
  return true;
}
}
