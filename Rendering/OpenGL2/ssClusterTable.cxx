#include "ssClusterTable.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkCellData.h"
#include "vtkPolyData.h"

namespace ss
{
bool HasClusterTable(vtkPolyData* pd)
{
  return pd && pd->GetFieldData() && pd->GetFieldData()->GetArray("ClusterRange");
}

bool ReadClusterTable(vtkPolyData* pd, ClusterTable& table, std::string& why, bool partition)
{
  table = ClusterTable();
  if (!pd)
  {
    why = "no data";
    return false;
  }
  vtkFieldData* fd = pd->GetFieldData();
  const auto get = [&](const char* name, int comps) -> vtkDataArray* {
    vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
    if (!a || a->GetNumberOfComponents() != comps)
    {
      why = std::string("field array ") + name + (a ? " has the wrong number of components" : " is missing");
      return nullptr;
    }
    return a;
  };
  vtkDataArray* range = get("ClusterRange", 2);
  vtkDataArray* aabb = range ? get("ClusterAABB", 6) : nullptr;
  vtkDataArray* obb = aabb ? get("ClusterOBB", 15) : nullptr;
  vtkDataArray* cone = obb ? get("ClusterNormalCone", 4) : nullptr;
  vtkDataArray* closed = cone ? get("ClusterClosedOutward", 1) : nullptr;
  vtkDataArray* pieces = closed ? get("ClusterPieceBounds", 6) : nullptr;
  if (!pieces)
  {
    return false;
  }
  const vtkIdType n = range->GetNumberOfTuples();
  for (vtkDataArray* a : { aabb, obb, cone, closed, pieces })
  {
    if (a->GetNumberOfTuples() != n)
    {
      why = std::string("field array ") + a->GetName() + " has a different number of clusters";
      return false;
    }
  }
  for (vtkIdType c = 0; c < n; ++c)
  {
    const double first = range->GetComponent(c, 0), count = range->GetComponent(c, 1);
    if (!(first >= 0 && count >= 0 && first + count <= static_cast<double>(pd->GetNumberOfCells())))
    {
      why = "ClusterRange " + std::to_string(c) + " is outside the cells";
      return false;
    }
    if (partition && static_cast<std::size_t>(first) != (c == 0 ? 0 : table.ranges.back().first + table.ranges.back().second))
    {
      why = "ClusterRange " + std::to_string(c) + " does not follow the previous cluster";
      return false;
    }
    table.ranges.emplace_back(static_cast<std::size_t>(first), static_cast<std::size_t>(count));
    ClusterBounds b;
    double v[15];
    aabb->GetTuple(c, v);
    b.aabb.min = { v[0], v[2], v[4] };
    b.aabb.max = { v[1], v[3], v[5] };
    pieces->GetTuple(c, v);
    b.pieceBounds.min = { v[0], v[2], v[4] };
    b.pieceBounds.max = { v[1], v[3], v[5] };
    obb->GetTuple(c, v);
    b.obb.center = { v[0], v[1], v[2] };
    b.obb.axis = { glm::dvec3(v[3], v[4], v[5]), glm::dvec3(v[6], v[7], v[8]), glm::dvec3(v[9], v[10], v[11]) };
    b.obb.half = { v[12], v[13], v[14] };
    cone->GetTuple(c, v);
    b.cone.axis = { v[0], v[1], v[2] };
    b.cone.cosAngle = v[3];
    b.closedOutward = closed->GetComponent(c, 0) != 0;
    table.bounds.push_back(b);
  }
  const std::size_t cells = static_cast<std::size_t>(pd->GetNumberOfCells());
  if (partition && (table.ranges.empty() ? 0 : table.ranges.back().first + table.ranges.back().second) != cells)
  {
    why = "ClusterRange does not cover every cell";
    return false;
  }
  vtkDataArray* piece = pd->GetCellData()->GetArray("PieceId");
  vtkDataArray* closedCells = pd->GetCellData()->GetArray("ClosedOutward");
  if (piece && closedCells && piece->GetNumberOfTuples() == static_cast<vtkIdType>(cells) &&
    closedCells->GetNumberOfTuples() == static_cast<vtkIdType>(cells) && piece->GetNumberOfComponents() == 1 &&
    closedCells->GetNumberOfComponents() == 1)
  {
    table.piece.resize(cells);
    table.closedOutward.resize(cells);
    for (std::size_t i = 0; i < cells; ++i)
    {
      const double p = piece->GetComponent(static_cast<vtkIdType>(i), 0);
      if (!(p >= 0 && p < 4294967295.0))
      {
        why = "cell array PieceId has a value out of range at cell " + std::to_string(i);
        table.piece.clear();
        table.closedOutward.clear();
        return false;
      }
      table.piece[i] = static_cast<std::uint32_t>(p);
      table.closedOutward[i] = closedCells->GetComponent(static_cast<vtkIdType>(i), 0) != 0 ? 1 : 0;
    }
  }
  return true;
}
}
