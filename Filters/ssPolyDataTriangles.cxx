#include "ssPolyDataTriangles.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSmartPointer.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace ssf
{
namespace
{
// When every cell has 3 corners: the triangles whose corners are all finite,
// in cell order, found in parallel. False (and `out` untouched) otherwise.
template <typename Id>
bool TrianglesOnly(const Id* offsets, const Id* conn, vtkIdType cells, vtkIdType cellBase,
  const std::vector<char>& finite, PolyTriangles& out)
{
  bool all3 = true;
  for (vtkIdType c = 0; c < cells && all3; ++c)
  {
    all3 = offsets[c + 1] - offsets[c] == 3;
  }
  if (!all3)
  {
    return false;
  }
  const auto keep = [&](vtkIdType c) {
    return finite.empty() ||
      (finite[conn[3 * c]] && finite[conn[3 * c + 1]] && finite[conn[3 * c + 2]]);
  };
  // kept triangles per block, then each block writes from its prefix
  const vtkIdType block = 65536;
  const vtkIdType blocks = (cells + block - 1) / block;
  std::vector<std::size_t> first(static_cast<std::size_t>(blocks) + 1, 0);
  tbb::parallel_for(vtkIdType(0), blocks, [&](vtkIdType b) {
    std::size_t n = 0;
    for (vtkIdType c = b * block; c < std::min(cells, (b + 1) * block); ++c)
    {
      n += keep(c) ? 1 : 0;
    }
    first[static_cast<std::size_t>(b) + 1] = n;
  });
  for (std::size_t b = 0; b < static_cast<std::size_t>(blocks); ++b)
  {
    first[b + 1] += first[b];
  }
  out.tris.resize(first.back());
  out.cell.resize(first.back());
  out.nonFiniteCells = static_cast<std::size_t>(cells) - first.back();
  tbb::parallel_for(vtkIdType(0), blocks, [&](vtkIdType b) {
    std::size_t o = first[static_cast<std::size_t>(b)];
    for (vtkIdType c = b * block; c < std::min(cells, (b + 1) * block); ++c)
    {
      if (keep(c))
      {
        out.tris[o] = { static_cast<std::int64_t>(conn[3 * c]), static_cast<std::int64_t>(conn[3 * c + 1]),
          static_cast<std::int64_t>(conn[3 * c + 2]) };
        out.cell[o] = cellBase + c;
        ++o;
      }
    }
  });
  return true;
}
}

PolyTriangles Triangulate(vtkPolyData* in, const std::vector<char>& finite)
{
  PolyTriangles out;
  if (!in || in->GetNumberOfPoints() == 0)
  {
    return out;
  }
  const vtkIdType cellBase = in->GetNumberOfVerts() + in->GetNumberOfLines();
  const auto allFinite = [&](vtkIdType n, const vtkIdType* ids) {
    for (vtkIdType k = 0; k < n; ++k)
    {
      if (!finite.empty() && !finite[ids[k]])
      {
        return false;
      }
    }
    return true;
  };
  // Each cell of `cells` with 3 or more corners, all finite, goes to `f`.
  const auto forEachCell = [&](vtkCellArray* cells, vtkIdType base, auto&& f) {
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    vtkIdType c = 0;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++c)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      if (n < 3)
      {
        continue;
      }
      if (!allFinite(n, ids))
      {
        ++out.nonFiniteCells;
        continue;
      }
      f(n, ids, base + c);
    }
  };
  // The common case, a surface of triangles only: read the cell array's
  // storage directly, in parallel. Same triangles, order and counts as below.
  if (in->GetNumberOfStrips() == 0 && in->GetNumberOfPolys() > 0 &&
    (in->GetPolys()->IsStorage64Bit()
        ? TrianglesOnly(in->GetPolys()->GetOffsetsArray64()->GetPointer(0),
            in->GetPolys()->GetConnectivityArray64()->GetPointer(0), in->GetNumberOfPolys(), cellBase, finite, out)
        : TrianglesOnly(in->GetPolys()->GetOffsetsArray32()->GetPointer(0),
            in->GetPolys()->GetConnectivityArray32()->GetPointer(0), in->GetNumberOfPolys(), cellBase, finite, out)))
  {
    return out;
  }
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> triIds;
  forEachCell(in->GetPolys(), cellBase, [&](vtkIdType n, const vtkIdType* ids, vtkIdType cell) {
    if (n == 3)
    {
      out.tris.push_back({ ids[0], ids[1], ids[2] });
      out.cell.push_back(cell);
      return;
    }
    // concave polygons too: VTK's ear-cut triangulation
    ++out.polygons;
    polygon->Initialize(static_cast<int>(n), ids, in->GetPoints());
    triIds->Reset();
    if (!polygon->Triangulate(triIds))
    {
      // a polygon VTK cannot cut (self-overlapping, degenerate): a fan
      // keeps its area in the caster set
      for (vtkIdType k = 1; k + 1 < n; ++k)
      {
        out.tris.push_back({ ids[0], ids[k], ids[k + 1] });
        out.cell.push_back(cell);
      }
      return;
    }
    for (vtkIdType k = 0; k + 2 < triIds->GetNumberOfIds(); k += 3)
    {
      // Triangulate returns local corner indices
      out.tris.push_back({ ids[triIds->GetId(k)], ids[triIds->GetId(k + 1)], ids[triIds->GetId(k + 2)] });
      out.cell.push_back(cell);
    }
  });
  forEachCell(in->GetStrips(), cellBase + in->GetNumberOfPolys(),
    [&](vtkIdType n, const vtkIdType* ids, vtkIdType cell) {
      ++out.strips;
      for (vtkIdType k = 0; k + 2 < n; ++k)
      {
        // every other triangle of a strip runs the other way round
        if (k % 2 == 0)
        {
          out.tris.push_back({ ids[k], ids[k + 1], ids[k + 2] });
        }
        else
        {
          out.tris.push_back({ ids[k + 1], ids[k], ids[k + 2] });
        }
        out.cell.push_back(cell);
      }
    });
  return out;
}
}
