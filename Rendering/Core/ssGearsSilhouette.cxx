// GEARS on closed meshes: the silhouette-edge winding count of one closed
// piece (Laine et al. 2005, §3; see ssGearsSilhouette.h for why the bits
// equal the triangle raster's and when a piece is declined).
#include "ssGearsSilhouette.h"

#include "ssGearsInternal.h"

#include <map>
#include <unordered_map>

namespace ss
{
namespace
{
struct VertexKey
{
  double x, y, z;
  bool operator<(const VertexKey& o) const
  {
    return x < o.x || (x == o.x && (y < o.y || (y == o.y && z < o.z)));
  }
};

// The light frame of GearsRasterizeTriangle: shared vertices map to
// bit-identical light-frame points, as in the solver.
glm::dvec3 ToLight(const LightFrame& L, const glm::dvec3& X)
{
  const glm::dvec3 r = X - L.center;
  return { glm::dot(r, L.u), glm::dot(r, L.v), glm::dot(r, L.n) };
}
}

bool GearsSilhouettePiece::Build(const std::vector<glm::dvec3>& tris, std::string* why)
{
  auto fail = [&](const std::string& w) {
    if (why)
    {
      *why = w;
    }
    vertices.clear();
    faces.clear();
    edges.clear();
    return false;
  };
  vertices.clear();
  faces.clear();
  edges.clear();
  if (tris.size() % 3 != 0 || tris.empty())
  {
    return fail("the triangle list is empty or not a multiple of 3 points");
  }
  std::map<VertexKey, std::uint32_t> ids;
  for (std::size_t t = 0; t < tris.size(); t += 3)
  {
    std::array<std::uint32_t, 3> f{};
    for (int q = 0; q < 3; ++q)
    {
      const glm::dvec3& p = tris[t + q];
      const auto it = ids.emplace(VertexKey{ p.x, p.y, p.z }, static_cast<std::uint32_t>(vertices.size()));
      if (it.second)
      {
        vertices.push_back(p);
      }
      f[q] = it.first->second;
    }
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0])
    {
      return fail("triangle " + std::to_string(t / 3) + " has two equal vertices");
    }
    faces.push_back(f);
  }
  // directed edge (a, b) -> its face; each undirected edge must appear once
  // in each direction
  std::unordered_map<std::uint64_t, std::uint32_t> directed;
  directed.reserve(3 * faces.size());
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (std::uint32_t f = 0; f < faces.size(); ++f)
  {
    for (int q = 0; q < 3; ++q)
    {
      const std::uint32_t a = faces[f][q], b = faces[f][(q + 1) % 3];
      if (!directed.emplace(key(a, b), f).second)
      {
        return fail("edge run twice in one direction (not consistently oriented or not 2-manifold) at face " +
          std::to_string(f));
      }
    }
  }
  for (const auto& d : directed)
  {
    const std::uint32_t a = static_cast<std::uint32_t>(d.first >> 32), b = static_cast<std::uint32_t>(d.first);
    const auto other = directed.find(key(b, a));
    if (other == directed.end())
    {
      return fail("boundary edge at face " + std::to_string(d.second) + " (the piece is not closed)");
    }
    if (a < b)
    {
      edges.push_back({ a, b, d.second, other->second });
    }
  }
  // a deterministic order (the hash map's is not)
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
  return true;
}

bool GearsSilhouetteMask(const LightFrame& light, const glm::dvec3& start, const GearsSilhouettePiece& piece, int k,
  double eps, GearsMask& mask, GearsSilhouetteStats* stats)
{
  using namespace gears;
  GearsSilhouetteStats local;
  GearsSilhouetteStats& st = stats ? *stats : local;
  st = GearsSilhouetteStats();
  auto decline = [&](const char* why) {
    st.declined = why;
    return false;
  };
  const bool dir = light.type == LightType::Directional;
  const glm::dvec2 sides = SampleSides(light);
  const double W = sides.x, H = sides.y;
  if (light.type == LightType::Point || k < 2 || k > 32 || !(W > 0.0) || !(H > 0.0))
  {
    return decline("not an area light with k >= 2 (the triangle raster's 3-D path)");
  }
  const LightSpace l = MakeLightSpace(ToLight(light, start), W, H, dir, k);
  const glm::dvec3 S = l.S;
  // Every vertex in front of a finite light (then a ray through a face
  // reaches it before the light, so the raster's plane test adds nothing).
  std::vector<glm::dvec3> B(piece.vertices.size());
  bool behind = false; // a vertex at or beyond the start's depth
  for (std::size_t v = 0; v < B.size(); ++v)
  {
    B[v] = ToLight(light, piece.vertices[v]);
    if (!(dir || B[v].z > 0.0))
    {
      return decline("a vertex is not in front of the light");
    }
    behind = behind || !(S.z - B[v].z > 0.0);
  }
  // Per face: which side S is on (SetupTriangle's det, same operations), and
  // the start rule's test (SetupBatch: |sigma| < eps |nT|).
  std::vector<signed char> side(piece.faces.size());
  for (std::size_t f = 0; f < piece.faces.size(); ++f)
  {
    const glm::dvec3 a = B[piece.faces[f][0]] - S, b = B[piece.faces[f][1]] - S, c = B[piece.faces[f][2]] - S;
    const glm::dvec3 nT = Cross3(b - a, c - a);
    const double det = Dot3(nT, a);
    if (!(det != 0.0))
    {
      return decline("the start lies in a face's plane");
    }
    side[f] = det > 0.0 ? 1 : -1;
    if (eps > 0.0)
    {
      const glm::dvec3 Bf = B[piece.faces[f][0]];
      const glm::dvec3 n = glm::cross(B[piece.faces[f][1]] - Bf, B[piece.faces[f][2]] - Bf);
      const double sigma = ((S.x - Bf.x) * n.x + (S.y - Bf.y) * n.y) + (S.z - Bf.z) * n.z;
      if (std::abs(sigma) < eps * glm::length(n))
      {
        // The raster applies the reference's start rule to this face (hits
        // closer than eps to S do not count). A face farther than 4 eps from
        // S has no such hit, and its bits are its edge planes' again.
        const glm::dvec3 lo = glm::min(glm::min(Bf, B[piece.faces[f][1]]), B[piece.faces[f][2]]);
        const glm::dvec3 hi = glm::max(glm::max(Bf, B[piece.faces[f][1]]), B[piece.faces[f][2]]);
        const glm::dvec3 gap = glm::max(glm::max(lo - S, S - hi), glm::dvec3(0.0));
        if (!(glm::length(gap) > 4.0 * eps))
        {
          return decline("a face within 4 eps of the start has its plane within eps of it (the start rule)");
        }
      }
    }
  }
  // The reference counts: the rays from S along -u and +u (the limits of
  // every row's sample directions) cross the piece 2 L and 2 R times (S
  // outside: each entry has its exit). A piece wholly nearer the light than
  // S lies below that plane: L = R = 0. Otherwise a 2-D test in (y, z) per
  // face that reaches the start's depth; a ray within 1e-9 of an edge, or a
  // hit within 1e-9 of S, is declined (the count would depend on rounding).
  int hitsL = 0, hitsR = 0;
  if (behind)
  {
    for (const auto& f : piece.faces)
    {
      const glm::dvec3 V[3] = { B[f[0]], B[f[1]], B[f[2]] };
      const double zmin = std::min({ V[0].z, V[1].z, V[2].z }), zmax = std::max({ V[0].z, V[1].z, V[2].z });
      if (zmax < S.z || zmin > S.z)
      {
        continue;
      }
      double w[3], sum = 0.0, scale = 0.0;
      for (int m = 0; m < 3; ++m)
      {
        const glm::dvec3& P = V[(m + 1) % 3];
        const glm::dvec3& Q = V[(m + 2) % 3];
        // twice the signed area of (P, Q, S) in the (y, z) plane: vertex m's weight
        w[m] = (Q.y - P.y) * (S.z - P.z) - (Q.z - P.z) * (S.y - P.y);
        sum += w[m];
        scale = std::max(scale, std::abs((Q.y - P.y) * (S.z - P.z)) + std::abs((Q.z - P.z) * (S.y - P.y)));
      }
      const double tol = 1e-9 * scale;
      if (std::abs(w[0]) <= tol || std::abs(w[1]) <= tol || std::abs(w[2]) <= tol)
      {
        const bool outside = (w[0] < -tol || w[1] < -tol || w[2] < -tol) && (w[0] > tol || w[1] > tol || w[2] > tol);
        if (!outside)
        {
          return decline("a reference ray grazes an edge or vertex");
        }
        continue;
      }
      if (!((w[0] > 0.0 && w[1] > 0.0 && w[2] > 0.0) || (w[0] < 0.0 && w[1] < 0.0 && w[2] < 0.0)))
      {
        continue; // (S.y, S.z) outside the face's projection
      }
      const double x = (w[0] * V[0].x + w[1] * V[1].x + w[2] * V[2].x) / sum;
      const double xs = 1e-9 * (std::abs(V[0].x) + std::abs(V[1].x) + std::abs(V[2].x) + std::abs(S.x));
      if (std::abs(x - S.x) <= xs)
      {
        return decline("the start lies on the piece");
      }
      (x < S.x ? hitsL : hitsR) += 1;
    }
    st.referenceHits = static_cast<std::size_t>(hitsL + hitsR);
    if (hitsL % 2 != 0 || hitsR % 2 != 0)
    {
      return decline("the start is inside the piece");
    }
  }
  // Row j's sample directions lie in the plane through S spanned by u and
  // d(0, j); its normal m_j = u x d(0, j) = (0, -D0.z, D0.y + sv_j Dv.y).
  // A silhouette edge crosses the row where its vertices lie on opposite
  // sides of that plane (half-open per vertex, so every closed silhouette
  // loop crosses it as often one way as the other) and the crossing point
  // lies nearer the light than S (else the rays towards the light do not
  // pass it; its edge function changes sign at the opposite direction).
  double rowA[32], rowB[32];
  for (int j = 0; j < k; ++j)
  {
    const double sv = (j + 0.5) / k - 0.5;
    rowA[j] = -l.s.D0.z;
    rowB[j] = l.s.D0.y + sv * l.s.Dv.y;
  }
  // Per row: +-1 from the first sample on the crossing's far side on
  // (a difference array over i = 0..k), and the rows' totals.
  int diff[32][33] = {};
  int balance[32] = {};
  for (const auto& e : piece.edges)
  {
    if (side[e.f0] == side[e.f1])
    {
      continue; // interior edge: its two faces' contributions cancel
    }
    ++st.silhouetteEdges;
    const glm::dvec3 P = B[e.a] - S, Q = B[e.b] - S;
    // The edge's function as SetupTriangle gives it in face f0 (a -> b is
    // one of f0's edges; f1 gives the same values on a silhouette edge).
    const double sg = side[e.f0] > 0 ? 1.0 : -1.0;
    const Affine F = MakeAffine(l.s, sg * Cross3(P, Q));
    bool inRect = false, inStrip = false;
    for (int j = 0; j < k; ++j)
    {
      const double sP = rowA[j] * P.y + rowB[j] * P.z, sQ = rowA[j] * Q.y + rowB[j] * Q.z;
      // A silhouette vertex exactly in a row's plane: the half-open rule
      // would treat the row as lying on one side of it, while the raster's
      // closed triangles also hide samples on an edge along the row.
      if (sP == 0.0 || sQ == 0.0)
      {
        return decline("a silhouette vertex lies exactly in a sample row's plane");
      }
      if ((sP > 0.0) == (sQ > 0.0))
      {
        continue;
      }
      const double t = sP / (sP - sQ);
      const double dz = P.z + t * (Q.z - P.z);
      if (std::abs(dz) <= 1e-9 * (std::abs(P.z) + std::abs(Q.z)))
      {
        return decline("a silhouette edge crosses a row's plane level with the start");
      }
      if (dz > 0.0)
      {
        continue; // beyond the start: not on a ray towards the light
      }
      if (F.B == 0.0)
      {
        return decline("a crossing silhouette edge is parallel to the rows");
      }
      inStrip = true;
      ++st.rowCrossings;
      const double ej = RowValue(F, j);
      // inside (F >= 0, the raster's tie rule) to the right (B > 0): +1 from
      // the first inside sample on; to the left: -1 from the first sample
      // outside on. first: the first i in [0, k] where that holds (k: none).
      const bool right = F.B > 0.0;
      auto holds = [&](double i) { return (ej + F.B * i >= 0.0) == right; };
      const double x = ClampRange(-ej / F.B, k);
      int c = static_cast<int>(std::min(std::max(CeilSmall(x), 0.0), static_cast<double>(k)));
      while (c > 0 && holds(c - 1))
      {
        --c;
      }
      while (c < k && !holds(c))
      {
        ++c;
      }
      diff[j][c] += right ? 1 : -1;
      balance[j] += right ? 1 : -1;
      inRect = inRect || (c > 0 && c < k);
    }
    st.stripEdges += inStrip ? 1 : 0;
    st.rectEdges += inRect ? 1 : 0;
  }
  // W = L + the crossings left of the sample; past the last sample it must
  // reach R (the count along +u), and it never goes below 0.
  std::uint32_t out[32] = {};
  for (int j = 0; j < k; ++j)
  {
    if (hitsL / 2 + balance[j] != hitsR / 2)
    {
      return decline("a row's silhouette crossings do not match the reference rays");
    }
    int w = hitsL / 2;
    for (int i = 0; i < k; ++i)
    {
      w += diff[j][i];
      if (w < 0)
      {
        return decline("a negative layer count");
      }
      if (w > 0)
      {
        out[j] |= 1u << i;
      }
    }
  }
  for (int j = 0; j < k; ++j)
  {
    mask[j] |= out[j];
  }
  return true;
}

bool GearsEdgeMaySilhouette(const GearsSilhouettePiece& piece, std::size_t e, const glm::dvec3& lo, const glm::dvec3& hi)
{
  // The per-pixel test is the sign of det = nT . (B0 - S) per face, in the
  // light frame relative to S; here the same plane in world coordinates,
  // over the box's corners, with a margin far above both roundings.
  const GearsSilhouettePiece::Edge& E = piece.edges[e];
  int sides[2];
  for (int q = 0; q < 2; ++q)
  {
    const auto& f = piece.faces[q == 0 ? E.f0 : E.f1];
    const glm::dvec3 P = piece.vertices[f[0]];
    const glm::dvec3 n = glm::cross(piece.vertices[f[1]] - P, piece.vertices[f[2]] - P);
    const double scale = glm::length(n) *
      (glm::length(hi - lo) + glm::length(glm::abs(lo) + glm::abs(hi)) + glm::length(glm::abs(P)) + 1e-300);
    const double m = 1e-9 * scale;
    double mn = 1e300, mx = -1e300;
    for (int c = 0; c < 8; ++c)
    {
      const glm::dvec3 X((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      const double s = glm::dot(n, X - P);
      mn = std::min(mn, s);
      mx = std::max(mx, s);
    }
    if (mn > m)
    {
      sides[q] = 1;
    }
    else if (mx < -m)
    {
      sides[q] = -1;
    }
    else
    {
      return true; // the box meets the plane (or lies within the margin)
    }
  }
  return sides[0] != sides[1];
}
}
