#include "ssClippingRange.h"
#include "ssVisibleBlocks.h"

#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkCamera.h"
#include "vtkDataSet.h"
#include "vtkMapper.h"
#include "vtkMatrix4x4.h"
#include "vtkOpenGLPolyDataMapper.h"
#include "vtkOpenGLVertexBufferObject.h"
#include "vtkPropCollection.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

namespace ss
{
namespace
{
/// Linear function L = (a, b, c, d) at a box's corner: a x + b y + c z + d.
double AtCorner(const double L[4], const double b[6], int corner)
{
  return L[0] * b[corner & 1] + L[1] * b[2 + ((corner >> 1) & 1)] + L[2] * b[4 + (corner >> 2)] + L[3];
}

/// Whether box b lies wholly outside one of the frustum's four side planes
/// (`planes`: vtkCamera::GetFrustumPlanes, inward normals, or those planes in
/// an actor's model coordinates).
bool OutsideTheSides(const double planes[24], const double b[6])
{
  for (int q = 0; q < 4; ++q)
  {
    bool allOut = true;
    for (int corner = 0; corner < 8 && allOut; ++corner)
    {
      allOut = AtCorner(planes + 4 * q, b, corner) < 0.0;
    }
    if (allOut)
    {
      return true;
    }
  }
  return false;
}

/// The least value of the linear function `depth` over box b: its nearest
/// depth along the view direction (`depth` = (dir, -dir . eye), or that in
/// an actor's model coordinates).
double NearestDepth(const double depth[4], const double b[6])
{
  double d = DBL_MAX;
  for (int corner = 0; corner < 8; ++corner)
  {
    d = std::min(d, AtCorner(depth, b, corner));
  }
  return d;
}

/// Whether box b lies wholly inside all four side planes: then so does every
/// box within it.
bool InsideTheSides(const double planes[24], const double b[6])
{
  for (int q = 0; q < 4; ++q)
  {
    for (int corner = 0; corner < 8; ++corner)
    {
      if (!(AtCorner(planes + 4 * q, b, corner) >= 0.0))
      {
        return false;
      }
    }
  }
  return true;
}

/// A cell's bounds that count at all: finite and not empty.
bool UsableBox(const double b[6])
{
  return std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && std::isfinite(b[3]) &&
    std::isfinite(b[4]) && std::isfinite(b[5]) && b[0] <= b[1];
}

void Include(double into[6], const double b[6])
{
  for (int a = 0; a < 3; ++a)
  {
    into[2 * a] = std::min(into[2 * a], b[2 * a]);
    into[2 * a + 1] = std::max(into[2 * a + 1], b[2 * a + 1]);
  }
}

/// A dataset's cells in runs of kRun, each with the box of its usable cells'
/// bounds (empty: none), kept while the dataset is unchanged. A view resets
/// its range every frame: from these boxes a frame walks only the runs that
/// straddle a side plane of the view or may hold the nearest cell (stop 51:
/// a walk over every cell took 1.2 s on 5M triangles).
constexpr vtkIdType kRun = 256;
struct CellRuns
{
  vtkWeakPointer<vtkDataSet> data;
  vtkMTimeType mtime = 0;
  std::vector<double> boxes; // 6 per run
};

const CellRuns& RunsOf(vtkDataSet* ds)
{
  static std::vector<CellRuns> cache;
  cache.erase(std::remove_if(cache.begin(), cache.end(), [](const CellRuns& r) { return !r.data; }), cache.end());
  for (CellRuns& r : cache)
  {
    if (r.data == ds && r.mtime == ds->GetMTime())
    {
      return r;
    }
  }
  cache.erase(std::remove_if(cache.begin(), cache.end(), [ds](const CellRuns& r) { return r.data == ds; }),
    cache.end());
  CellRuns runs;
  runs.data = ds;
  runs.mtime = ds->GetMTime();
  const vtkIdType n = ds->GetNumberOfCells();
  runs.boxes.assign(6 * static_cast<std::size_t>((n + kRun - 1) / kRun), 0.0);
  double cb[6];
  for (vtkIdType r = 0; r * kRun < n; ++r)
  {
    double* box = runs.boxes.data() + 6 * r;
    const double empty[6] = { DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX };
    std::copy(empty, empty + 6, box);
    for (vtkIdType c = r * kRun; c < std::min(n, (r + 1) * kRun); ++c)
    {
      ds->GetCellBounds(c, cb);
      if (UsableBox(cb))
      {
        Include(box, cb);
      }
    }
  }
  cache.push_back(std::move(runs));
  return cache.back();
}

/// Over a dataset's cells in the coordinates of `planes` and `depth`: the
/// box of those not wholly outside a side plane into `into`, and the least
/// nearest depth of those wholly in front of the camera into `nearest`. The
/// same as a walk over every cell's bounds: a run inside every side plane
/// adds its box (its cells' union); the runs that may hold a nearer cell are
/// walked in order of their boxes' nearest depth until none can.
void WalkCells(vtkDataSet* ds, const double planes[24], const double depth[4], double into[6], double& nearest)
{
  const CellRuns& runs = RunsOf(ds);
  const vtkIdType n = ds->GetNumberOfCells();
  std::vector<std::pair<double, vtkIdType>> order; // (box's nearest depth, run) of the runs in view
  std::vector<char> straddles(runs.boxes.size() / 6, 0);
  for (vtkIdType r = 0; r < static_cast<vtkIdType>(straddles.size()); ++r)
  {
    const double* box = runs.boxes.data() + 6 * r;
    if (!UsableBox(box) || OutsideTheSides(planes, box))
    {
      continue;
    }
    if (InsideTheSides(planes, box))
    {
      Include(into, box);
    }
    else
    {
      straddles[r] = 1;
    }
    order.emplace_back(NearestDepth(depth, box), r);
  }
  std::sort(order.begin(), order.end());
  double cb[6];
  auto walk = [&](vtkIdType r, bool forBox, bool forNearest) {
    for (vtkIdType c = r * kRun; c < std::min(n, (r + 1) * kRun); ++c)
    {
      ds->GetCellBounds(c, cb);
      if (!UsableBox(cb) || OutsideTheSides(planes, cb))
      {
        continue;
      }
      if (forBox)
      {
        Include(into, cb);
      }
      const double d = forNearest ? NearestDepth(depth, cb) : 0.0;
      if (d > 0.0)
      {
        nearest = std::min(nearest, d);
      }
    }
  };
  for (const auto& [boxNearest, r] : order)
  {
    // a run whose box lies wholly in front and beyond the nearest so far
    // holds no nearer cell (a box's cells lie within it)
    const bool mayBeNearer = !(boxNearest > 0.0 && boxNearest >= nearest);
    if (straddles[r] || mayBeNearer)
    {
      walk(r, straddles[r] != 0, mayBeNearer);
    }
  }
}

/// The view-direction depth from the camera as a linear function of world
/// points.
void DepthFunction(vtkCamera* cam, double depth[4])
{
  double eye[3], dir[3];
  cam->GetPosition(eye);
  cam->GetDirectionOfProjection(dir);
  depth[0] = dir[0];
  depth[1] = dir[1];
  depth[2] = dir[2];
  depth[3] = -(dir[0] * eye[0] + dir[1] * eye[1] + dir[2] * eye[2]);
}

/// Linear function L of world points as a function of model points, for the
/// model-to-world matrix m: L (m x) = (L m) x.
void ToModel(const double L[4], const vtkMatrix4x4* m, double out[4])
{
  for (int j = 0; j < 4; ++j)
  {
    out[j] = L[0] * m->GetElement(0, j) + L[1] * m->GetElement(1, j) + L[2] * m->GetElement(2, j) +
      L[3] * m->GetElement(3, j);
  }
}

/// The world bounds of model box b under matrix m (its eight corners).
void ToWorld(const double b[6], vtkMatrix4x4* m, double out[6])
{
  out[0] = out[2] = out[4] = DBL_MAX;
  out[1] = out[3] = out[5] = -DBL_MAX;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double p[4] = { b[corner & 1], b[2 + ((corner >> 1) & 1)], b[4 + (corner >> 2)], 1.0 };
    double w[4];
    m->MultiplyPoint(p, w);
    for (int a = 0; a < 3; ++a)
    {
      out[2 * a] = std::min(out[2 * a], w[a]);
      out[2 * a + 1] = std::max(out[2 * a + 1], w[a]);
    }
  }
}
}

// VTK's automatic shift moves a mapper's float coordinates to the centre of
// its bounds. A mesh reaching from the view far out (a needle to a lost
// vertex at 1e10) has that centre far from what is seen, whose vertices then
// lie on a coarse grid: a strip from the scene to 1e10 vanished from the
// picture, its bottom on a 512-unit grid (stop 50). Such a mapper shifts to
// the camera's focal point instead: its centre lies more than 100 camera
// distances from the focal point and its bounds come within 100 of it. The
// others keep VTK's rule, so ordinary scenes are drawn as before.
void ShiftFarReachingMappersToTheFocalPoint(vtkRenderer* renderer)
{
  vtkCamera* cam = renderer->GetActiveCamera();
  const double reach = 100.0 * cam->GetDistance();
  const double* fp = cam->GetFocalPoint();
  vtkActorCollection* actors = renderer->GetActors();
  vtkCollectionSimpleIterator it;
  actors->InitTraversal(it);
  while (vtkActor* actor = actors->GetNextActor(it))
  {
    auto* mapper = vtkOpenGLPolyDataMapper::SafeDownCast(actor->GetMapper());
    const double* b = actor->GetBounds();
    if (!mapper || !b || !(b[0] <= b[1]))
    {
      continue;
    }
    double centre = 0.0, nearest = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double c = 0.5 * (b[2 * a] + b[2 * a + 1]) - fp[a];
      const double n = std::max({ b[2 * a] - fp[a], fp[a] - b[2 * a + 1], 0.0 });
      centre += c * c;
      nearest += n * n;
    }
    if (std::sqrt(centre) > reach && std::sqrt(nearest) < reach)
    {
      mapper->SetVBOShiftScaleMethod(vtkOpenGLVertexBufferObject::FOCAL_POINT_SHIFT_SCALE);
    }
  }
}

// The camera's clipping range from the cells it can see, not from every
// prop's bounds. VTK's ResetCameraClippingRange() spans all bounds and keeps
// the near plane at least 1/1000 of the far one: one stray triangle 1e5
// units away (a lost vertex, an exporter's marker) put the near plane
// hundreds of units out and the picture came out empty (issue 17). A cell
// counts when its bounds are not wholly outside one of the frustum's four
// side planes; what lies outside the view cannot be drawn and does not set
// the range. An actor with a transform (every ParaView representation has a
// user transform) is walked in its model coordinates: the planes and the
// depth are linear, so they are taken there (stop 51; before, such an actor
// counted by its bounds, and a lost vertex in a mesh around the camera kept
// the picture empty). A volume counts by its bounds.
void ResetClippingRangeToVisible(vtkRenderer* renderer, double aspect)
{
  vtkCamera* cam = renderer->GetActiveCamera();
  double planes[24], depth[4];
  cam->GetFrustumPlanes(aspect, planes); // inward normals
  DepthFunction(cam, depth);
  double box[6] = { DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX };
  // the nearest depth (along the view direction) of a cell wholly in front
  // of the camera: the near plane must not pass it
  double nearest = DBL_MAX;
  // a prop's bounds, where finite and not outside the view
  auto grow = [&](const double b[6]) {
    if (!UsableBox(b) || OutsideTheSides(planes, b))
    {
      return;
    }
    Include(box, b);
    const double d = NearestDepth(depth, b);
    if (d > 0.0)
    {
      nearest = std::min(nearest, d);
    }
  };
  vtkPropCollection* props = renderer->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    if (!prop->GetVisibility())
    {
      continue;
    }
    vtkActor* actor = vtkActor::SafeDownCast(prop);
    vtkDataObject* input =
      (actor && actor->GetMapper()) ? actor->GetMapper()->GetInputDataObject(0, 0) : nullptr;
    std::vector<vtkDataSet*> pieces; // a dataset, or a composite's visible leaves (ParaView's representations)
    if (input)
    {
      ForEachVisibleLeaf(actor->GetMapper(), input, [&pieces](vtkDataSet* ds) { pieces.push_back(ds); });
    }
    if (pieces.empty())
    {
      if (const double* b = prop->GetBounds())
      {
        grow(b);
      }
      continue;
    }
    // the planes and the depth in the actor's model coordinates
    // (GetMatrix first: it brings IsIdentity up to date with a transform set
    // since the last render)
    vtkMatrix4x4* matrix = actor->GetMatrix();
    vtkMatrix4x4* m = actor->GetIsIdentity() ? nullptr : matrix;
    double mPlanes[24], mDepth[4];
    for (int q = 0; q < 6 && m; ++q)
    {
      ToModel(planes + 4 * q, m, mPlanes + 4 * q);
    }
    if (m)
    {
      ToModel(depth, m, mDepth);
    }
    double modelBox[6] = { DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX };
    for (vtkDataSet* ds : pieces)
    {
      WalkCells(ds, m ? mPlanes : planes, m ? mDepth : depth, m ? modelBox : box, nearest);
    }
    if (m && modelBox[0] <= modelBox[1])
    {
      // the counted cells' model box in world coordinates (its corners)
      double wb[6];
      ToWorld(modelBox, m, wb);
      Include(box, wb);
    }
  }
  if (box[0] <= box[1])
  {
    renderer->ResetCameraClippingRange(box);
    // A cell in view that reaches far out (a broken mesh's sliver running to
    // a vertex at 1e10) sets the far plane, and VTK keeps the near plane at
    // its ratio of the far one (1/1000 here): the near plane passed every
    // ordinary cell and the picture came out empty (stop 49). Where the near
    // plane lies beyond the nearest cell wholly in front, it moves to that
    // cell and the far plane to the ratio from it: the far-out parts are
    // clipped, the scene is drawn. Ordinary scenes keep VTK's range (their
    // near plane lies in front of every cell).
    double range[2];
    cam->GetClippingRange(range);
    const double ratio = renderer->GetNearClippingPlaneTolerance() > 0.0 ? renderer->GetNearClippingPlaneTolerance()
                                                                          : 1e-3;
    if (nearest < DBL_MAX && range[0] > nearest)
    {
      const double n = 0.99 * nearest;
      cam->SetClippingRange(n, std::min(range[1], n / ratio));
    }
  }
  else
  {
    renderer->ResetCameraClippingRange(); // nothing in view
  }
}

bool NearPlaneMayPassVisibleCells(vtkRenderer* renderer, double aspect)
{
  vtkCamera* cam = renderer->GetActiveCamera();
  double planes[24], depth[4], range[2];
  cam->GetFrustumPlanes(aspect, planes);
  DepthFunction(cam, depth);
  cam->GetClippingRange(range);
  vtkPropCollection* props = renderer->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    const double* b = prop->GetVisibility() ? prop->GetBounds() : nullptr;
    if (!b || !(b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5]) || OutsideTheSides(planes, b))
    {
      continue;
    }
    const double d = NearestDepth(depth, b);
    // a prop wholly in front that the near plane passes; or, where the
    // camera is among a prop's bounds (its cells may lie on both sides of
    // the near plane), a near plane beyond the focal point
    if ((d > 0.0 && range[0] > d) || (d <= 0.0 && range[0] > cam->GetDistance()))
    {
      return true;
    }
  }
  return false;
}
}
