// ss::FindGearsPieces (ssGearsPieces.h): the closed pieces GEARS' closed-mesh
// rule may trust. Closed and consistently oriented pieces get the sign of
// their volume; anything else (a hole, a vertex off by one ulp, a pinched
// vertex, an edge with three faces, a flipped face, a projective matrix) is
// open, and a triangle with a NaN or two equal corners is a piece of its own.
#include "ssGearsPieces.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <numeric>

using namespace ss;

namespace
{
std::vector<std::uint32_t> All(const std::vector<glm::dvec3>& v)
{
  std::vector<std::uint32_t> t(v.size() / 3);
  std::iota(t.begin(), t.end(), 0u);
  return t;
}

GearsPieces Find(const std::vector<glm::dvec3>& v, GearsPieceCounts* counts = nullptr, bool mayClose = true)
{
  GearsPieces p;
  p.piece.assign(v.size() / 3, ~0u);
  const GearsPieceCounts c = FindGearsPieces(v, All(v), mayClose, p);
  if (counts)
  {
    *counts = c;
  }
  return p;
}

// The closed tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1) + `at`, outward.
std::vector<glm::dvec3> Tetrahedron(const glm::dvec3& at)
{
  const glm::dvec3 o = at, x = at + glm::dvec3(1, 0, 0), y = at + glm::dvec3(0, 1, 0), z = at + glm::dvec3(0, 0, 1);
  return { o, y, x, o, x, z, o, z, y, x, y, z };
}

void Append(std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b)
{
  a.insert(a.end(), b.begin(), b.end());
}
}

TEST(GearsPieces, ClosedSurfacesAreOutwardAndMirrorsInward)
{
  // far from the origin: the volume is taken relative to the piece
  const std::vector<glm::dvec3> sphere = sstest::BumpySphere(glm::dvec3(1e5, -2e5, 3e4), 2.0, 3);
  GearsPieceCounts c;
  const GearsPieces p = Find(sphere, &c);
  ASSERT_EQ(p.orientation.size(), 1u);
  EXPECT_EQ(p.orientation[0], 1);
  EXPECT_EQ(c.closedPieces, 1u);
  EXPECT_EQ(c.closedTriangles, sphere.size() / 3);
  for (auto q : p.piece)
  {
    EXPECT_EQ(q, 0u);
  }
  // a mirrored copy (x -> -x, vertex order kept) turns inward; reversed winding too
  std::vector<glm::dvec3> mirrored = sphere, reversed = sphere;
  for (auto& v : mirrored)
  {
    v.x = -v.x;
  }
  for (std::size_t t = 0; t < reversed.size(); t += 3)
  {
    std::swap(reversed[t + 1], reversed[t + 2]);
  }
  EXPECT_EQ(Find(mirrored).orientation, std::vector<std::int8_t>{ -1 });
  EXPECT_EQ(Find(reversed).orientation, std::vector<std::int8_t>{ -1 });
  // under a projective matrix nothing is closed
  EXPECT_EQ(Find(sphere, &c, false).orientation, std::vector<std::int8_t>{ 0 });
  EXPECT_EQ(c.closedPieces, 0u);
}

TEST(GearsPieces, PiecesOfABlockAreItsEdgeConnectedComponents)
{
  std::vector<glm::dvec3> v = Tetrahedron(glm::dvec3(0.0));
  Append(v, Tetrahedron(glm::dvec3(3.0, 0, 0)));
  // a tetrahedron without its last face: open
  Append(v, Tetrahedron(glm::dvec3(6.0, 0, 0)));
  v.resize(v.size() - 3);
  GearsPieceCounts c;
  GearsPieces p;
  p.orientation = { 0 }; // a piece before this block's
  p.piece.assign(v.size() / 3 + 2, 0u);
  std::vector<std::uint32_t> tris(v.size() / 3);
  std::iota(tris.begin(), tris.end(), 0u);
  c = FindGearsPieces(v, tris, true, p);
  EXPECT_EQ(p.orientation, (std::vector<std::int8_t>{ 0, 1, 1, 0 }));
  EXPECT_EQ(c.pieces, 3u);
  EXPECT_EQ(c.closedPieces, 2u);
  EXPECT_EQ(c.closedTriangles, 8u);
  for (std::size_t t = 0; t < tris.size(); ++t)
  {
    EXPECT_EQ(p.piece[t], 1u + t / 4) << t;
  }
}

TEST(GearsPieces, OnlyExactWeldsCloseAPiece)
{
  // one corner of one face off by one ulp: that face no longer shares its edges
  std::vector<glm::dvec3> v = Tetrahedron(glm::dvec3(0.25));
  v[3].x = std::nextafter(v[3].x, 1.0);
  EXPECT_EQ(Find(v).orientation, std::vector<std::int8_t>{ 0 });
}

TEST(GearsPieces, InconsistentOrNonManifoldPiecesAreOpen)
{
  // one face flipped: its edges run the same way as their neighbours'
  std::vector<glm::dvec3> flipped = Tetrahedron(glm::dvec3(0.0));
  std::swap(flipped[1], flipped[2]);
  EXPECT_EQ(Find(flipped).orientation, std::vector<std::int8_t>{ 0 });
  // two tetrahedra sharing one vertex: every edge paired, the vertex pinched
  // (the second is the first reflected through the origin, its winding
  // reversed to stay outward)
  std::vector<glm::dvec3> pinched = Tetrahedron(glm::dvec3(0.0)), second = pinched;
  for (std::size_t t = 0; t < second.size(); t += 3)
  {
    for (int j = 0; j < 3; ++j)
    {
      second[t + j] = -second[t + j];
    }
    std::swap(second[t + 1], second[t + 2]);
  }
  EXPECT_EQ(Find(second).orientation, std::vector<std::int8_t>{ 1 });
  Append(pinched, second);
  // two pieces (edge-connected components), both open
  EXPECT_EQ(Find(pinched).orientation, (std::vector<std::int8_t>{ 0, 0 }));
  // a closed tetrahedron with a fin on one edge (three faces on it)
  std::vector<glm::dvec3> fin = Tetrahedron(glm::dvec3(0.0));
  Append(fin, { glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0.5, -1, 0.5) });
  EXPECT_EQ(Find(fin).orientation, std::vector<std::int8_t>{ 0 });
  // a doubled face sheet (two faces, opposite): closed edges, no volume
  const std::vector<glm::dvec3> sheet = { glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
    glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0) };
  EXPECT_EQ(Find(sheet).orientation, std::vector<std::int8_t>{ 0 });
}

TEST(GearsPieces, DegenerateAndNonFiniteTrianglesArePiecesOfTheirOwn)
{
  std::vector<glm::dvec3> v = Tetrahedron(glm::dvec3(0.0));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Append(v, { glm::dvec3(nan, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0) });
  Append(v, { glm::dvec3(2, 2, 2), glm::dvec3(2, 2, 2), glm::dvec3(3, 2, 2) });
  GearsPieceCounts c;
  const GearsPieces p = Find(v, &c);
  // the tetrahedron stays closed: neither touches it by an edge
  EXPECT_EQ(p.orientation, (std::vector<std::int8_t>{ 1, 0, 0 }));
  EXPECT_EQ(p.piece[4], 1u);
  EXPECT_EQ(p.piece[5], 2u);
  EXPECT_EQ(c.closedTriangles, 4u);
  EXPECT_EQ(c.pieces, 3u);
}

namespace
{
// Many pieces at once, each of a known kind, in shuffled triangle order: 24
// bumpy spheres (every third mirrored, so inward; every fifth with one face
// dropped, so open), 40 tetrahedra (every fourth with one face flipped, so
// open), pairs of tetrahedra pinched at a vertex, and NaN triangles. Returns
// the soup and, per triangle, the orientation its piece must get.
struct Assembly
{
  std::vector<glm::dvec3> v;
  std::vector<int> expected;
};

Assembly MixedAssembly()
{
  Assembly a;
  const auto add = [&](const std::vector<glm::dvec3>& tris, int orientation) {
    a.v.insert(a.v.end(), tris.begin(), tris.end());
    a.expected.insert(a.expected.end(), tris.size() / 3, orientation);
  };
  for (int s = 0; s < 24; ++s)
  {
    std::vector<glm::dvec3> sphere = sstest::BumpySphere(glm::dvec3(7.0 * s, 1e3, -2e2), 2.0, 3);
    int o = 1;
    if (s % 3 == 0)
    {
      for (auto& p : sphere)
      {
        p.y = -p.y;
      }
      o = -1;
    }
    if (s % 5 == 0)
    {
      sphere.erase(sphere.begin() + 3 * 17, sphere.begin() + 3 * 18);
      o = 0;
    }
    add(sphere, o);
  }
  for (int t = 0; t < 40; ++t)
  {
    std::vector<glm::dvec3> tet = Tetrahedron(glm::dvec3(3.0 * t, -50.0, 0.0));
    if (t % 4 == 0)
    {
      std::swap(tet[4], tet[5]);
    }
    add(tet, t % 4 == 0 ? 0 : 1);
  }
  for (int p = 0; p < 5; ++p)
  {
    const glm::dvec3 at(4.0 * p, 80.0, 0.0);
    std::vector<glm::dvec3> first = Tetrahedron(at), second = first;
    for (std::size_t t = 0; t < second.size(); t += 3)
    {
      for (int j = 0; j < 3; ++j)
      {
        second[t + j] = 2.0 * at - second[t + j];
      }
      std::swap(second[t + 1], second[t + 2]);
    }
    add(first, 0);
    add(second, 0);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  add({ glm::dvec3(nan, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0) }, 0);
  // shuffle the triangles (a fixed permutation): pieces are not runs of the soup
  const std::size_t n = a.v.size() / 3;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::uint64_t state = 12345;
  for (std::size_t i = n - 1; i > 0; --i)
  {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    std::swap(order[i], order[(state >> 33) % (i + 1)]);
  }
  Assembly s;
  for (std::size_t i : order)
  {
    s.v.insert(s.v.end(), a.v.begin() + 3 * i, a.v.begin() + 3 * i + 3);
    s.expected.push_back(a.expected[i]);
  }
  return s;
}

GearsPieces FindMasked(const std::vector<glm::dvec3>& v, std::uint64_t mask, GearsPieceCounts& c)
{
  GearsPieces p;
  p.piece.assign(v.size() / 3, ~0u);
  c = detail::FindGearsPieces(v, All(v), true, p, {}, mask);
  return p;
}
}

TEST(GearsPieces, ManyPiecesOfKnownKindsInAShuffledSoup)
{
  const Assembly a = MixedAssembly();
  GearsPieceCounts c;
  const GearsPieces p = Find(a.v, &c);
  std::size_t closed = 0;
  for (std::size_t t = 0; t < a.expected.size(); ++t)
  {
    ASSERT_LT(p.piece[t], p.orientation.size());
    EXPECT_EQ(int(p.orientation[p.piece[t]]), a.expected[t]) << "triangle " << t;
    closed += a.expected[t] != 0;
  }
  EXPECT_EQ(c.closedTriangles, closed);
  EXPECT_EQ(c.closedPieces, 24u - 5u + 30u); // spheres without the dropped faces; unflipped tetrahedra
  // 24 spheres, 40 tetrahedra, 10 pinched ones, 1 NaN triangle
  EXPECT_EQ(c.pieces, 24u + 40u + 10u + 1u);
}

// The weld trusts a hash only after checking that every corner equals its
// vertex's first one; when hashes collide (forced here by masking them) it
// welds by the exact sort of the points, with the same pieces.
TEST(GearsPieces, HashCollisionsGiveTheSamePieces)
{
  const Assembly a = MixedAssembly();
  GearsPieceCounts c0;
  const GearsPieces full = FindMasked(a.v, ~std::uint64_t(0), c0);
  for (std::uint64_t mask : { std::uint64_t(0), std::uint64_t(0xF), std::uint64_t(0xF) << 60,
         std::uint64_t(0xFFF) << 52 | std::uint64_t(0x3) })
  {
    GearsPieceCounts c;
    const GearsPieces p = FindMasked(a.v, mask, c);
    EXPECT_EQ(p.piece, full.piece) << std::hex << mask;
    EXPECT_EQ(p.orientation, full.orientation) << std::hex << mask;
    EXPECT_EQ(c.closedTriangles, c0.closedTriangles) << std::hex << mask;
  }
}

TEST(GearsPieces, TheSameOnAnyNumberOfThreads)
{
  std::vector<glm::dvec3> v = MixedAssembly().v;
  Append(v, sstest::BumpySphere(glm::dvec3(-40.0, 0, 0), 3.0, 6)); // 32,768 more triangles
  // workers beyond the machine's cores (2 here), so the larger arenas get them
  tbb::global_control workers(tbb::global_control::max_allowed_parallelism, 8);
  GearsPieces reference;
  tbb::task_arena one(1);
  one.execute([&] { reference = Find(v); });
  for (int threads : { 2, 3, 8 })
  {
    tbb::task_arena arena(threads);
    GearsPieces p;
    arena.execute([&] { p = Find(v); });
    EXPECT_EQ(p.piece, reference.piece) << threads << " threads";
    EXPECT_EQ(p.orientation, reference.orientation) << threads << " threads";
  }
}

// A render abort (the progress callback returning false) stops the search at
// any of its stages and leaves the output as it was; progress runs from 0 to
// 1 without going back.
TEST(GearsPieces, ProgressAndAbort)
{
  const std::vector<glm::dvec3> v = MixedAssembly().v;
  const GearsPieces plain = Find(v);
  std::vector<double> seen;
  GearsPieces p;
  p.piece.assign(v.size() / 3, ~0u);
  GearsPieceCounts c = FindGearsPieces(v, All(v), true, p, [&](double f) {
    seen.push_back(f);
    return true;
  });
  EXPECT_FALSE(c.aborted);
  EXPECT_EQ(p.piece, plain.piece);
  EXPECT_EQ(p.orientation, plain.orientation);
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i)
  {
    EXPECT_GE(seen[i], seen[i - 1]);
  }
  for (std::size_t stop = 0; stop < seen.size(); ++stop)
  {
    GearsPieces q;
    q.piece.assign(v.size() / 3, 7u);
    q.orientation = { 0, 1 };
    std::size_t calls = 0;
    c = FindGearsPieces(v, All(v), true, q, [&](double) { return calls++ < stop; });
    EXPECT_TRUE(c.aborted) << stop;
    EXPECT_EQ(calls, stop + 1) << "no call after the one that stopped it";
    EXPECT_EQ(q.orientation, (std::vector<std::int8_t>{ 0, 1 })) << stop;
    EXPECT_EQ(q.piece, std::vector<std::uint32_t>(v.size() / 3, 7u)) << stop;
    EXPECT_EQ(c.pieces + c.closedPieces + c.closedTriangles, 0u) << stop;
  }
}

// Collapsed triangles (two equal corners) on a closed piece's vertices,
// before it in the soup: each vertex's first corner is then on a triangle
// that is dropped after the weld, and the vertex must still be checked and
// its edges still join the piece (else the sphere falls apart into "closed"
// bits whose volumes have any sign).
TEST(GearsPieces, CollapsedTrianglesFirstDoNotHideTheirVertices)
{
  const std::vector<glm::dvec3> sphere = sstest::BumpySphere(glm::dvec3(0.5, -2.0, 1.0), 2.0, 2);
  std::vector<glm::dvec3> v;
  for (std::size_t t = 0; t < sphere.size(); t += 3)
  {
    Append(v, { sphere[t], sphere[t], sphere[t + 1] });
  }
  const std::size_t collapsed = v.size() / 3;
  Append(v, sphere);
  GearsPieceCounts c;
  const GearsPieces p = Find(v, &c);
  EXPECT_EQ(c.closedPieces, 1u);
  EXPECT_EQ(c.closedTriangles, sphere.size() / 3);
  for (std::size_t t = collapsed; t < v.size() / 3; ++t)
  {
    ASSERT_EQ(p.piece[t], p.piece[collapsed]) << t;
  }
  EXPECT_EQ(p.orientation[p.piece[collapsed]], 1);
  // and a pinched vertex behind a collapsed triangle is still found
  std::vector<glm::dvec3> pinched = { glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(1, 0, 0) };
  std::vector<glm::dvec3> first = Tetrahedron(glm::dvec3(0.0)), second = first;
  for (std::size_t t = 0; t < second.size(); t += 3)
  {
    for (int j = 0; j < 3; ++j)
    {
      second[t + j] = -second[t + j];
    }
    std::swap(second[t + 1], second[t + 2]);
  }
  Append(pinched, first);
  Append(pinched, second);
  EXPECT_EQ(Find(pinched).orientation, (std::vector<std::int8_t>{ 0, 0, 0 }));
}

TEST(GearsPieces, OnlyNonFiniteTriangles)
{
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<glm::dvec3> v = { glm::dvec3(nan, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
    glm::dvec3(0, 0, 0), glm::dvec3(inf, 0, 0), glm::dvec3(0, 1, 0) };
  GearsPieceCounts c;
  const GearsPieces p = Find(v, &c);
  EXPECT_EQ(p.orientation, (std::vector<std::int8_t>{ 0, 0 }));
  EXPECT_EQ(p.piece, (std::vector<std::uint32_t>{ 0, 1 }));
  EXPECT_EQ(c.closedPieces, 0u);
  GearsPieces empty;
  c = FindGearsPieces({}, {}, true, empty);
  EXPECT_EQ(c.pieces, 0u);
  EXPECT_TRUE(empty.orientation.empty());
}

// A pinched torus (a tube coned at both ends to one apex; every edge paired,
// two fans at the apex) is open, also when an open triangle elsewhere touches
// the apex (found by a review: the unpaired edges there skipped the fan check).
TEST(GearsPieces, APinchStaysOpenWhenAnOpenTriangleTouchesIt)
{
  const glm::dvec3 k(0.0);
  std::vector<glm::dvec3> v;
  glm::dvec3 r1[3], r2[3];
  for (int i = 0; i < 3; ++i)
  {
    const double a = 2.0 * M_PI * i / 3.0;
    r1[i] = k + glm::dvec3(1, 0.3 * std::cos(a), 0.3 * std::sin(a));
    r2[i] = k + glm::dvec3(0.3 * std::cos(a), 1, 0.3 * std::sin(a));
  }
  for (int i = 0; i < 3; ++i)
  {
    const int j = (i + 1) % 3;
    Append(v, { k, r1[j], r1[i], r1[i], r1[j], r2[j], r1[i], r2[j], r2[i], k, r2[i], r2[j] });
  }
  EXPECT_EQ(Find(v).orientation, std::vector<std::int8_t>{ 0 });
  Append(v, { k, glm::dvec3(-1, -1, 0), glm::dvec3(-1, -2, 0) });
  EXPECT_EQ(Find(v).orientation, (std::vector<std::int8_t>{ 0, 0 }));
}
