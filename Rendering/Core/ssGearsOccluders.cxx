// Inner occluders of closed pieces (beyond the paper): boxes strictly inside
// a closed piece. A segment that passes through such a box passes through
// the solid, and so crosses the piece's surface where the exact raster finds
// it (the edge planes of triangles that share an edge are exact negatives of
// each other, so no segment slips between them). So when every segment from
// a pixel sample (or from a whole cell's samples) to the light passes through
// one box, its mask is full, and the thousands of small faces behind which
// the light disappears need not be drawn (UmbraBox in ssGearsPixel.cxx). The
// boxes travel through the grid as clusters of 12 triangles (pass 1, pass 2,
// the shaft culling). Where no box hides a whole cell, its faces are drawn
// first into the cell's masks (their bits are the solid's too), with the
// winding count only while that fills masks (SolveCells, occluderProbe).
//
// The boxes come from a voxel grid over the piece: voxels touched by a
// triangle's bounding box are surface; a flood fill from the grid's border
// marks the outside (it cannot cross a closed surface: any 6-connected path
// from inside to outside passes through a voxel the surface touches); what is
// left is inside, and is merged greedily into boxes.
#include "ssGearsInternal.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>

namespace ss
{
namespace gears
{
namespace
{
struct Grid
{
  int nx = 0, ny = 0, nz = 0;
  std::vector<std::uint8_t> v; // 0 unknown, 1 surface, 2 outside, 3 inside, 4 taken by a box
  std::size_t At(int x, int y, int z) const
  {
    return (static_cast<std::size_t>(z) * ny + y) * nx + x;
  }
};

// Outward triangles of the box [lo, hi], 12, as 36 floats.
void EmitBox(const glm::dvec3& lo, const glm::dvec3& hi, std::vector<float>& out)
{
  auto corner = [&](int c) {
    return glm::dvec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
  };
  // faces as corner quads, counter-clockwise seen from outside
  static const int quads[6][4] = { { 0, 4, 6, 2 }, { 1, 3, 7, 5 }, { 0, 1, 5, 4 }, { 2, 6, 7, 3 }, { 0, 2, 3, 1 },
    { 4, 5, 7, 6 } };
  for (const auto& q : quads)
  {
    for (const int tri : { 0, 1 })
    {
      const int ids[3] = { q[0], q[tri + 1], q[tri + 2] };
      for (int id : ids)
      {
        const glm::dvec3 p = corner(id);
        out.push_back(static_cast<float>(p.x));
        out.push_back(static_cast<float>(p.y));
        out.push_back(static_cast<float>(p.z));
      }
    }
  }
}
}

void PieceBoxes(SolverData& D, std::size_t np)
{
  D.pieceBox.assign(6 * np, 0.0);
  for (std::size_t p = 0; p < np; ++p)
  {
    for (int a = 0; a < 3; ++a)
    {
      D.pieceBox[6 * p + a] = std::numeric_limits<double>::max();
      D.pieceBox[6 * p + 3 + a] = -std::numeric_limits<double>::max();
    }
  }
  for (std::size_t t = 0; t < D.real; ++t)
  {
    double* b = &D.pieceBox[6 * D.piece[t]];
    for (int j = 0; j < 3; ++j)
    {
      const glm::dvec3 x = D.Vertex(t, j);
      for (int a = 0; a < 3; ++a)
      {
        b[a] = std::min(b[a], x[a]);
        b[3 + a] = std::max(b[3 + a], x[a]);
      }
    }
  }
}

void BuildOccluders(SolverData& D)
{
  D.occV.clear();
  D.occPiece.clear();
  D.occBox.clear();
  const std::size_t NP = D.pieceBox.size() / 6;
  // the triangles of each usable closed piece
  std::vector<std::vector<std::uint32_t>> members(NP);
  for (std::size_t t = 0; t < D.real; ++t)
  {
    if (D.orient[t] != 0)
    {
      members[D.piece[t]].push_back(static_cast<std::uint32_t>(t));
    }
  }
  // each piece on its own (in parallel), its boxes appended in piece order
  struct PieceBoxes
  {
    std::vector<float> V;
    std::vector<double> box;
  };
  std::vector<PieceBoxes> found(NP);
  tbb::parallel_for(std::size_t(0), NP, [&](std::size_t p) {
    const auto& tris = members[p];
    if (tris.size() < kOccluderMinTriangles)
    {
      return; // a few large faces fill a mask as fast as a box would
    }
    const double* b = &D.pieceBox[6 * p];
    const glm::dvec3 lo(b[0], b[1], b[2]), hi(b[3], b[4], b[5]);
    const glm::dvec3 ext = hi - lo;
    const double side = std::max({ ext.x, ext.y, ext.z }) / kOccluderGrid;
    if (!(side > 0.0))
    {
      return;
    }
    // one voxel of outside margin around the piece
    Grid g;
    g.nx = static_cast<int>(std::ceil(ext.x / side)) + 2;
    g.ny = static_cast<int>(std::ceil(ext.y / side)) + 2;
    g.nz = static_cast<int>(std::ceil(ext.z / side)) + 2;
    g.v.assign(static_cast<std::size_t>(g.nx) * g.ny * g.nz, 0);
    const glm::dvec3 origin = lo - glm::dvec3(side);
    auto cellOf = [&](double c, double o, int n) {
      return std::clamp(static_cast<int>(std::floor((c - o) / side)), 0, n - 1);
    };
    for (std::uint32_t t : tris)
    {
      glm::dvec3 tlo(1e300), thi(-1e300);
      for (int m = 0; m < 3; ++m)
      {
        tlo = glm::min(tlo, D.Vertex(t, m));
        thi = glm::max(thi, D.Vertex(t, m));
      }
      // widened by a tenth of a voxel: rounding never lets the surface slip
      // into a voxel left unmarked
      const double w = 0.1 * side;
      const int x0 = cellOf(tlo.x - w, origin.x, g.nx), x1 = cellOf(thi.x + w, origin.x, g.nx);
      const int y0 = cellOf(tlo.y - w, origin.y, g.ny), y1 = cellOf(thi.y + w, origin.y, g.ny);
      const int z0 = cellOf(tlo.z - w, origin.z, g.nz), z1 = cellOf(thi.z + w, origin.z, g.nz);
      for (int z = z0; z <= z1; ++z)
      {
        for (int y = y0; y <= y1; ++y)
        {
          for (int x = x0; x <= x1; ++x)
          {
            g.v[g.At(x, y, z)] = 1;
          }
        }
      }
    }
    // flood fill of the outside from the border
    std::vector<std::array<int, 3>> stack;
    auto push = [&](int x, int y, int z) {
      if (x >= 0 && y >= 0 && z >= 0 && x < g.nx && y < g.ny && z < g.nz && g.v[g.At(x, y, z)] == 0)
      {
        g.v[g.At(x, y, z)] = 2;
        stack.push_back({ x, y, z });
      }
    };
    for (int z = 0; z < g.nz; ++z)
    {
      for (int y = 0; y < g.ny; ++y)
      {
        for (int x = 0; x < g.nx; ++x)
        {
          if (x == 0 || y == 0 || z == 0 || x == g.nx - 1 || y == g.ny - 1 || z == g.nz - 1)
          {
            push(x, y, z);
          }
        }
      }
    }
    while (!stack.empty())
    {
      const auto c = stack.back();
      stack.pop_back();
      push(c[0] - 1, c[1], c[2]);
      push(c[0] + 1, c[1], c[2]);
      push(c[0], c[1] - 1, c[2]);
      push(c[0], c[1] + 1, c[2]);
      push(c[0], c[1], c[2] - 1);
      push(c[0], c[1], c[2] + 1);
    }
    // the rest is inside: greedy boxes, largest extent in x, then y, then z
    struct VoxBox
    {
      int x0, y0, z0, x1, y1, z1;
      std::size_t volume;
    };
    std::vector<VoxBox> boxes;
    auto inside = [&](int x, int y, int z) { return g.v[g.At(x, y, z)] == 0; };
    for (int z = 0; z < g.nz; ++z)
    {
      for (int y = 0; y < g.ny; ++y)
      {
        for (int x = 0; x < g.nx; ++x)
        {
          if (!inside(x, y, z))
          {
            continue;
          }
          int x1 = x;
          while (x1 + 1 < g.nx && inside(x1 + 1, y, z))
          {
            ++x1;
          }
          int y1 = y;
          for (bool grow = true; grow && y1 + 1 < g.ny;)
          {
            for (int xx = x; xx <= x1 && grow; ++xx)
            {
              grow = inside(xx, y1 + 1, z);
            }
            y1 += grow ? 1 : 0;
          }
          int z1 = z;
          for (bool grow = true; grow && z1 + 1 < g.nz;)
          {
            for (int yy = y; yy <= y1 && grow; ++yy)
            {
              for (int xx = x; xx <= x1 && grow; ++xx)
              {
                grow = inside(xx, yy, z1 + 1);
              }
            }
            z1 += grow ? 1 : 0;
          }
          for (int zz = z; zz <= z1; ++zz)
          {
            for (int yy = y; yy <= y1; ++yy)
            {
              for (int xx = x; xx <= x1; ++xx)
              {
                g.v[g.At(xx, yy, zz)] = 4;
              }
            }
          }
          boxes.push_back({ x, y, z, x1, y1, z1,
            static_cast<std::size_t>(x1 - x + 1) * (y1 - y + 1) * (z1 - z + 1) });
        }
      }
    }
    std::sort(boxes.begin(), boxes.end(), [](const VoxBox& a, const VoxBox& c) { return a.volume > c.volume; });
    if (boxes.size() > kOccluderBoxes)
    {
      boxes.resize(kOccluderBoxes);
    }
    for (const VoxBox& vb : boxes)
    {
      if (vb.volume < kOccluderMinVoxels)
      {
        break;
      }
      // voxel faces, shrunk by a hundredth of a voxel: strictly inside the
      // surface voxels, whatever the rounding to float
      const double s = 0.01 * side;
      const glm::dvec3 blo = origin + side * glm::dvec3(vb.x0, vb.y0, vb.z0) + s;
      const glm::dvec3 bhi = origin + side * glm::dvec3(vb.x1 + 1, vb.y1 + 1, vb.z1 + 1) - s;
      EmitBox(blo, bhi, found[p].V);
      found[p].box.insert(found[p].box.end(), { blo.x, blo.y, blo.z, bhi.x, bhi.y, bhi.z });
    }
  });
  for (std::size_t p = 0; p < NP; ++p)
  {
    D.occV.insert(D.occV.end(), found[p].V.begin(), found[p].V.end());
    D.occBox.insert(D.occBox.end(), found[p].box.begin(), found[p].box.end());
    D.occPiece.insert(D.occPiece.end(), found[p].box.size() / 6, static_cast<std::uint32_t>(p));
  }
}

void AppendOccluders(SolverData& D)
{
  D.V.resize(9 * D.real);
  D.opacity.resize(D.real);
  D.orient.resize(D.real);
  D.piece.resize(D.real);
  while (D.clusterFirst.size() > D.realClusters + 1)
  {
    D.clusterFirst.pop_back();
  }
  for (std::size_t b = 0; b < D.occPiece.size(); ++b)
  {
    D.V.insert(D.V.end(), D.occV.begin() + 108 * b, D.occV.begin() + 108 * (b + 1));
    for (int t = 0; t < 12; ++t)
    {
      D.opacity.push_back(1.0f);
      D.orient.push_back(1);
      D.piece.push_back(D.occPiece[b]);
    }
    D.clusterFirst.push_back(static_cast<std::uint32_t>(D.opacity.size()));
  }
}
}
}
