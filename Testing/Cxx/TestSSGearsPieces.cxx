// ss::FindGearsPieces (ssGearsPieces.h): the closed pieces GEARS' closed-mesh
// rule may trust. Closed and consistently oriented pieces get the sign of
// their volume; anything else (a hole, a vertex off by one ulp, a pinched
// vertex, an edge with three faces, a flipped face, a projective matrix) is
// open, and a triangle with a NaN or two equal corners is a piece of its own.
#include "ssGearsPieces.h"
#include "ssGearsTestScenes.h"

#include <gtest/gtest.h>

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
