// Random GEARS test scenes shared by the CPU solver's tests (TestSSGEARS) and
// the GL compute backend's (TestGearsGL): triangles in a slab over a
// receiver, pixel samples on the receiver and on tilted patches, and five
// lights covering every light type and every cube face of a point light;
// a closed bumpy surface (the culling and silhouette tests); and connected
// meshes over a meshed floor (the winding count's tests, the GL backend's).
#ifndef ssGearsTestScenes_h
#define ssGearsTestScenes_h

#include "ssGEARS.h"
#include "ssGearsPieces.h"
#include "ssLightFrame.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace sstest
{
struct Scene
{
  std::vector<glm::dvec3> tris;
  std::vector<float> pos, nrm;
};

// Random small triangles in a slab between a receiver plane z = 0 (with
// bumps: random normals) and the light, plus receivers as pixel samples.
inline Scene RandomScene(std::mt19937& rng, int ntri, int npix, const glm::dvec3& offset)
{
  std::uniform_real_distribution<double> U(-1.0, 1.0), Z(0.05, 1.5), S(0.02, 0.4);
  Scene s;
  for (int t = 0; t < ntri; ++t)
  {
    const glm::dvec3 c(U(rng), U(rng), Z(rng));
    const double r = S(rng);
    for (int j = 0; j < 3; ++j)
    {
      s.tris.push_back(offset + c + r * glm::dvec3(U(rng), U(rng), 0.5 * U(rng)));
    }
  }
  for (int i = 0; i < npix; ++i)
  {
    // receivers on the floor and on random triangles' planes nearby
    const glm::dvec3 p(1.5 * U(rng), 1.5 * U(rng), (i % 4 == 0) ? Z(rng) : 0.0);
    glm::dvec3 n = (i % 4 == 0) ? glm::normalize(glm::dvec3(U(rng), U(rng), 1.2 + U(rng))) : glm::dvec3(0, 0, 1);
    s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
    s.nrm.insert(s.nrm.end(), { float(n.x), float(n.y), float(n.z) });
  }
  return s;
}

// A closed, star-shaped, bumpy surface around c (radius about r): an
// octahedron subdivided `levels` times, its vertices pushed out to a radius
// that varies with direction (amplitudes amp1, amp2; 0: a sphere), so it
// shadows itself. Counter-clockwise seen from outside; vertices of shared
// edges are bit-identical.
inline std::vector<glm::dvec3> BumpySphere(
  const glm::dvec3& c, double r, int levels, double amp1 = 0.25, double amp2 = 0.12)
{
  std::vector<glm::dvec3> tris;
  for (int f = 0; f < 8; ++f)
  {
    const double sx = (f & 1) ? -1 : 1, sy = (f & 2) ? -1 : 1, sz = (f & 4) ? -1 : 1;
    const glm::dvec3 a(sx, 0, 0), b(0, sy, 0), d(0, 0, sz);
    if (sx * sy * sz > 0)
    {
      tris.insert(tris.end(), { a, b, d });
    }
    else
    {
      tris.insert(tris.end(), { a, d, b });
    }
  }
  for (int l = 0; l < levels; ++l)
  {
    std::vector<glm::dvec3> next;
    for (std::size_t t = 0; t < tris.size(); t += 3)
    {
      const glm::dvec3 a = tris[t], b = tris[t + 1], d = tris[t + 2];
      const glm::dvec3 ab = 0.5 * (a + b), bd = 0.5 * (b + d), da = 0.5 * (d + a);
      next.insert(next.end(), { a, ab, da, ab, b, bd, da, bd, d, ab, bd, da });
    }
    tris.swap(next);
  }
  for (auto& v : tris)
  {
    const glm::dvec3 u = glm::normalize(v);
    const double bump = 1.0 + amp1 * std::sin(6.0 * u.x) * std::cos(5.0 * u.y) + amp2 * std::sin(7.0 * u.z);
    v = c + r * bump * u;
  }
  return tris;
}

// count pixel samples at the centroids of random ones of the first ntri
// triangles of s.tris (world; pixels relative to offset), with their
// normals: receivers on the casters themselves (self-shadowing).
inline void PixelsOnTriangles(Scene& s, std::size_t ntri, const glm::dvec3& offset, int count, std::mt19937& rng)
{
  for (int i = 0; i < count; ++i)
  {
    const std::size_t t = rng() % ntri;
    const glm::dvec3 a = s.tris[3 * t] - offset, b = s.tris[3 * t + 1] - offset, c = s.tris[3 * t + 2] - offset;
    const glm::dvec3 p = (a + b + c) / 3.0, n = glm::normalize(glm::cross(b - a, c - a));
    s.pos.insert(s.pos.end(), { float(p.x), float(p.y), float(p.z) });
    s.nrm.insert(s.nrm.end(), { float(n.x), float(n.y), float(n.z) });
  }
}

// Pieces for a scene whose first `closed` triangles form one closed,
// outward piece and the rest one open piece.
inline ss::GearsPieces ClosedThenOpen(std::size_t triangles, std::size_t closed)
{
  ss::GearsPieces pieces;
  pieces.piece.assign(triangles, 1u);
  std::fill(pieces.piece.begin(), pieces.piece.begin() + static_cast<std::ptrdiff_t>(closed), 0u);
  pieces.orientation = { 1, 0 };
  return pieces;
}

// The GEARS kernels' instruction sets this CPU runs (Scalar always).
inline std::vector<ss::GearsSimd> RunnableIsas()
{
  __builtin_cpu_init();
  std::vector<ss::GearsSimd> v = { ss::GearsSimd::Scalar };
  if (__builtin_cpu_supports("avx2"))
  {
    v.push_back(ss::GearsSimd::AVX2);
  }
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
    __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq"))
  {
    v.push_back(ss::GearsSimd::AVX512);
  }
  return v;
}

inline std::vector<ss::LightFrame> Lights(const glm::dvec3& offset)
{
  using namespace ss;
  return { MakeRectLightFrame(offset + glm::dvec3(0.3, -0.2, 3.0), { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2, 0.7 }),
    MakeRectLightFrame(offset + glm::dvec3(-2.0, 0.5, 2.0), { 0.7, -0.2, -0.6 }, { 0, 0, 1 }, { 0.5, 0.5 }),
    MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, 0.1), MakePointLightFrame(offset + glm::dvec3(0.2, 0.1, 2.5)),
    // a point light among the casters: every cube face of the grid is used
    MakePointLightFrame(offset + glm::dvec3(0.0, 0.0, 0.8)) };
}

// Connected meshes (TestSSGEARSWinding, TestGearsGL): casters with pixel
// samples relative to the origin on a meshed floor and on the casters.
struct Mesh
{
  std::vector<glm::dvec3> tris;
  Scene pixels; // pos, nrm (relative to the offset)
};

inline void AddQuad(
  std::vector<glm::dvec3>& t, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d)
{
  t.insert(t.end(), { a, b, c, a, c, d });
}

// A connected grid of nx x ny quads over [x0, x1] x [y0, y1] at height h(x, y).
template <typename F>
std::vector<glm::dvec3> Sheet(int nx, int ny, double x0, double x1, double y0, double y1, F h)
{
  std::vector<glm::dvec3> t;
  auto P = [&](int i, int j) {
    const double x = x0 + (x1 - x0) * i / nx, y = y0 + (y1 - y0) * j / ny;
    return glm::dvec3(x, y, h(x, y));
  };
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      AddQuad(t, P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1));
    }
  }
  return t;
}

// A tilted torus of nu x nv quads (closed; vertices of shared edges bit-identical).
inline std::vector<glm::dvec3> Torus(const glm::dvec3& c, double R, double r, int nu, int nv)
{
  std::vector<glm::dvec3> t;
  auto P = [&](int a, int b) {
    const double u = 2.0 * M_PI * (a % nu) / nu, v = 2.0 * M_PI * (b % nv) / nv;
    return c +
      glm::dvec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u) * 0.8,
        r * std::sin(v) + 0.3 * (R + r * std::cos(v)) * std::sin(u));
  };
  for (int a = 0; a < nu; ++a)
  {
    for (int b = 0; b < nv; ++b)
    {
      AddQuad(t, P(a, b), P(a + 1, b), P(a + 1, b + 1), P(a, b + 1));
    }
  }
  return t;
}

// Pixel samples: on the floor grid (z = 0) and on random caster triangles.
inline void AddPixels(Mesh& m, std::size_t casterTris, int onFloor, int onCasters, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.4, 1.4);
  for (int i = 0; i < onFloor; ++i)
  {
    m.pixels.pos.insert(m.pixels.pos.end(), { float(U(rng)), float(U(rng)), 0.0f });
    m.pixels.nrm.insert(m.pixels.nrm.end(), { 0.0f, 0.0f, 1.0f });
  }
  Scene s;
  s.tris = m.tris;
  PixelsOnTriangles(s, casterTris, glm::dvec3(0.0), onCasters, rng);
  m.pixels.pos.insert(m.pixels.pos.end(), s.pos.begin(), s.pos.end());
  m.pixels.nrm.insert(m.pixels.nrm.end(), s.nrm.begin(), s.nrm.end());
}

// The casters first (so that pixels can sit on them), then a meshed floor.
inline Mesh WithFloor(std::vector<glm::dvec3> casters, std::uint32_t seed)
{
  Mesh m;
  m.tris = std::move(casters);
  const std::size_t n = m.tris.size() / 3;
  const std::vector<glm::dvec3> floor = Sheet(24, 24, -1.6, 1.6, -1.6, 1.6, [](double, double) { return 0.0; });
  m.tris.insert(m.tris.end(), floor.begin(), floor.end());
  AddPixels(m, n, 300, 200, seed);
  return m;
}

// A closed bumpy surface under an open wavy sheet (like an isosurface).
inline Mesh BumpyAndWavy()
{
  std::vector<glm::dvec3> t = BumpySphere({ 0.3, 0.1, 1.0 }, 0.45, 4);
  const std::vector<glm::dvec3> sheet = Sheet(40, 40, -1.2, 1.2, -1.2, 1.2, [](double x, double y) {
    return 1.8 + 0.25 * std::sin(5.0 * x) * std::cos(4.0 * y) + 0.1 * std::sin(13.0 * x * y);
  });
  t.insert(t.end(), sheet.begin(), sheet.end());
  return WithFloor(t, 7);
}

// A torus cutting through a closed bumpy surface.
inline Mesh TorusThroughSphere()
{
  std::vector<glm::dvec3> t = Torus({ 0.0, 0.0, 1.1 }, 0.6, 0.2, 48, 16);
  const std::vector<glm::dvec3> s = BumpySphere({ 0.55, 0.0, 1.1 }, 0.3, 3, 0.1, 0.05);
  t.insert(t.end(), s.begin(), s.end());
  return WithFloor(t, 11);
}

// A wavy sheet with defects: flipped triangles, an edge held by three
// triangles (a fin), an unwelded seam (one half shifted by a hair), a
// duplicated triangle, and a strip of slivers (the winding counts' tests).
inline Mesh BrokenSheet()
{
  const auto wave = [](double x, double y) { return 1.5 + 0.2 * std::sin(6.0 * x + 2.0 * y); };
  std::vector<glm::dvec3> t = Sheet(30, 30, -1.2, 0.0, -1.2, 1.2, wave);
  const std::vector<glm::dvec3> right = Sheet(30, 30, 1e-7, 1.2, -1.2, 1.2, wave);
  t.insert(t.end(), right.begin(), right.end());
  for (std::size_t f = 5; f < t.size() / 3; f += 17)
  {
    std::swap(t[3 * f + 1], t[3 * f + 2]); // flipped
  }
  const glm::dvec3 a = t[3 * 100], b = t[3 * 100 + 1];
  t.insert(t.end(), { a, b, 0.5 * (a + b) + glm::dvec3(0.0, 0.0, 0.3) }); // a fin on an edge
  t.insert(t.end(), { t[3 * 200], t[3 * 200 + 1], t[3 * 200 + 2] });     // duplicated
  for (int i = 0; i < 40; ++i)
  {
    // slivers: a fan of needles sharing edges
    const double y = -1.0 + 0.05 * i;
    t.insert(t.end(), { glm::dvec3(-0.8, y, 2.2), glm::dvec3(0.8, y + 1e-6, 2.2), glm::dvec3(0.8, y + 0.05, 2.2) });
    t.insert(t.end(), { glm::dvec3(-0.8, y, 2.2), glm::dvec3(0.8, y + 0.05, 2.2), glm::dvec3(-0.8, y + 0.05, 2.2) });
  }
  return WithFloor(t, 13);
}

// The closed pieces of tris, as the render pass finds them.
inline ss::GearsPieces PiecesOf(const std::vector<glm::dvec3>& tris)
{
  ss::GearsPieces p;
  p.piece.assign(tris.size() / 3, 0);
  std::vector<std::uint32_t> all(tris.size() / 3);
  for (std::size_t i = 0; i < all.size(); ++i)
  {
    all[i] = static_cast<std::uint32_t>(i);
  }
  ss::FindGearsPieces(tris, all, true, p);
  return p;
}

// Lights with an area: tilted rects (one small) and a directional light;
// positions and sizes scaled by s about o.
inline std::vector<ss::LightFrame> AreaLights(const glm::dvec3& o, double s)
{
  using namespace ss;
  return { MakeRectLightFrame(
             o + s * glm::dvec3(0.3, -0.2, 3.2), { -0.1, 0.05, -1 }, { 0, 1, 0 }, { 1.2 * s, 0.7 * s }),
    MakeRectLightFrame(o + s * glm::dvec3(-2.5, 0.5, 2.6), { 0.7, -0.2, -0.6 }, { 0, 0, 1 }, { 0.9 * s, 0.9 * s }),
    MakeRectLightFrame(o + s * glm::dvec3(0.1, 0.0, 4.0), { 0, 0, -1 }, { 0, 1, 0 }, { 0.15 * s, 0.15 * s }),
    MakeDirectionalLightFrame({ 0.2, 0.1, -1 }, 0.15) };
}
}

#endif
