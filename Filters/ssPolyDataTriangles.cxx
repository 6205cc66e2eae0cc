#include "ssPolyDataTriangles.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSmartPointer.h"

namespace ssf
{
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
