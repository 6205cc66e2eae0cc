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
  const double T = dir ? 2.0 * std::tan(0.5 * light.angularDiameter) : 0.0;
  const double W = dir ? T : light.width, H = dir ? T : light.height;
  if (light.type == LightType::Point || k < 2 || k > 32 || !(W > 0.0) || !(H > 0.0))
  {
    return decline("not an area light with k >= 2 (the triangle raster's 3-D path)");
  }
  const LightSpace l = MakeLightSpace(ToLight(light, start), W, H, dir, k);
  const glm::dvec3 S = l.S;
  // Every vertex strictly between S and the light (the raster's `projected`
  // test, SetupBatch / RasterizeTriangle): then every face's bits are its
  // three edge planes', and S lies outside the piece. Per vertex its row in
  // sample-index units (the projection from S onto the light, as the LUT
  // path projects it).
  std::vector<glm::dvec3> B(piece.vertices.size());
  std::vector<double> row(piece.vertices.size());
  for (std::size_t v = 0; v < B.size(); ++v)
  {
    B[v] = ToLight(light, piece.vertices[v]);
    if (!(S.z - B[v].z > 0.0 && (dir || B[v].z > 0.0)))
    {
      return decline("a vertex is not strictly between the start and the light");
    }
    const double den = S.z - B[v].z;
    const double g = dir ? 1.0 / den : S.z / den;
    const double sv = ((dir ? 0.0 : S.y) + (B[v].y - S.y) * g) / H;
    row[v] = ClampRange((sv + 0.5) * k - 0.5, k);
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
        return decline("a face's plane passes within eps of the start (the start rule)");
      }
    }
  }
  // Per row: +-1 from the first sample on the crossing's far side on
  // (a difference array over i = 0..k), and the balance of the crossings.
  int diff[32][33] = {};
  int balance[32] = {};
  for (const auto& e : piece.edges)
  {
    if (side[e.f0] == side[e.f1])
    {
      continue; // interior edge: its two faces' contributions cancel
    }
    ++st.silhouetteEdges;
    // A silhouette vertex exactly on a sample row: the half-open rule below
    // would treat that row as lying just above the vertex, while the raster's
    // closed triangles hide samples on a horizontal silhouette edge too.
    for (const double y : { row[e.a], row[e.b] })
    {
      if (y >= 0.0 && y <= k - 1.0 && y == FloorSmall(y))
      {
        return decline("a silhouette vertex projects exactly onto a sample row");
      }
    }
    const double ylo = std::min(row[e.a], row[e.b]), yhi = std::max(row[e.a], row[e.b]);
    // rows j with ylo <= j < yhi (half-open per vertex: every closed
    // silhouette loop crosses each row as often upwards as downwards)
    const int j0 = std::max(0, static_cast<int>(CeilSmall(ylo)));
    const int j1 = std::min(k - 1, static_cast<int>(CeilSmall(yhi)) - 1);
    if (j0 > j1)
    {
      continue;
    }
    // The edge's function as SetupTriangle gives it in face f0 (a -> b is
    // one of f0's edges; f1 gives the same values on a silhouette edge).
    const double sg = side[e.f0] > 0 ? 1.0 : -1.0;
    const Affine F = MakeAffine(l.s, sg * Cross3(B[e.a] - S, B[e.b] - S));
    if (F.B == 0.0)
    {
      return decline("a straddling silhouette edge is parallel to the rows");
    }
    ++st.stripEdges;
    bool inRect = false;
    for (int j = j0; j <= j1; ++j)
    {
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
    st.rectEdges += inRect ? 1 : 0;
  }
  std::uint32_t out[32] = {};
  for (int j = 0; j < k; ++j)
  {
    if (balance[j] != 0)
    {
      return decline("a row's silhouette crossings do not balance");
    }
    int w = 0;
    for (int i = 0; i < k; ++i)
    {
      w += diff[j][i];
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
