#include "ssClusterTable.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkPolyData.h"

namespace ssf
{
bool ReadClusterTable(vtkPolyData* pd, ClusterTable& table, std::string& why)
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
    table.ranges.emplace_back(static_cast<std::size_t>(first), static_cast<std::size_t>(count));
    ss::ClusterBounds b;
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
  return true;
}
}
