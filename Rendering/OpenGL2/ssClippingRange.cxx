#include "ssClippingRange.h"

#include "vtkActor.h"
#include "vtkActorCollection.h"
#include "vtkCamera.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSet.h"
#include "vtkMapper.h"
#include "vtkOpenGLPolyDataMapper.h"
#include "vtkOpenGLVertexBufferObject.h"
#include "vtkPropCollection.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

namespace ss
{
namespace
{
/// Whether box b lies wholly outside one of the frustum's four side planes
/// (`planes`: vtkCamera::GetFrustumPlanes, inward normals).
bool OutsideTheSides(const double planes[24], const double b[6])
{
  for (int q = 0; q < 4; ++q)
  {
    const double* P = planes + 4 * q;
    bool allOut = true;
    for (int corner = 0; corner < 8 && allOut; ++corner)
    {
      const double x = b[corner & 1], y = b[2 + ((corner >> 1) & 1)], z = b[4 + (corner >> 2)];
      allOut = P[0] * x + P[1] * y + P[2] * z + P[3] < 0.0;
    }
    if (allOut)
    {
      return true;
    }
  }
  return false;
}

/// The nearest depth of box b along the view direction `dir` from `eye`.
double NearestDepth(const double eye[3], const double dir[3], const double b[6])
{
  double d = DBL_MAX;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double x = b[corner & 1], y = b[2 + ((corner >> 1) & 1)], z = b[4 + (corner >> 2)];
    d = std::min(d, (x - eye[0]) * dir[0] + (y - eye[1]) * dir[1] + (z - eye[2]) * dir[2]);
  }
  return d;
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
// the range. A volume, or an actor with a transform, counts by its bounds.
void ResetClippingRangeToVisible(vtkRenderer* renderer, double aspect)
{
  double planes[24];
  renderer->GetActiveCamera()->GetFrustumPlanes(aspect, planes); // inward normals
  double box[6] = { DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX };
  // the nearest depth (along the view direction) of a cell wholly in front
  // of the camera: the near plane must not pass it
  vtkCamera* cam = renderer->GetActiveCamera();
  double eye[3], dir[3];
  cam->GetPosition(eye);
  cam->GetDirectionOfProjection(dir);
  double nearest = DBL_MAX;
  auto grow = [&](const double b[6]) {
    if (!(std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && std::isfinite(b[3]) &&
          std::isfinite(b[4]) && std::isfinite(b[5])) || b[0] > b[1] || OutsideTheSides(planes, b))
    {
      return;
    }
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = std::min(box[2 * a], b[2 * a]);
      box[2 * a + 1] = std::max(box[2 * a + 1], b[2 * a + 1]);
    }
    const double d = NearestDepth(eye, dir, b);
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
    std::vector<vtkDataSet*> pieces; // a polydata, or a composite's leaves (ParaView's representations)
    if (auto* ds = vtkDataSet::SafeDownCast(input))
    {
      pieces.push_back(ds);
    }
    else if (auto* tree = vtkDataObjectTree::SafeDownCast(input))
    {
      vtkSmartPointer<vtkDataObjectTreeIterator> leaves;
      leaves.TakeReference(tree->NewTreeIterator());
      leaves->VisitOnlyLeavesOn();
      leaves->SkipEmptyNodesOn();
      for (leaves->InitTraversal(); !leaves->IsDoneWithTraversal(); leaves->GoToNextItem())
      {
        if (auto* leaf = vtkDataSet::SafeDownCast(leaves->GetCurrentDataObject()))
        {
          pieces.push_back(leaf);
        }
      }
    }
    if (pieces.empty() || !actor->GetIsIdentity())
    {
      if (const double* b = prop->GetBounds())
      {
        grow(b);
      }
      continue;
    }
    double cb[6];
    for (vtkDataSet* ds : pieces)
    {
      for (vtkIdType c = 0; c < ds->GetNumberOfCells(); ++c)
      {
        ds->GetCellBounds(c, cb);
        grow(cb);
      }
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

bool NearPlanePassesAVisibleProp(vtkRenderer* renderer, double aspect)
{
  vtkCamera* cam = renderer->GetActiveCamera();
  double planes[24], eye[3], dir[3], range[2];
  cam->GetFrustumPlanes(aspect, planes);
  cam->GetPosition(eye);
  cam->GetDirectionOfProjection(dir);
  cam->GetClippingRange(range);
  vtkPropCollection* props = renderer->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    const double* b = prop->GetVisibility() ? prop->GetBounds() : nullptr;
    if (!b || !(b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5]))
    {
      continue;
    }
    const double d = NearestDepth(eye, dir, b);
    if (d > 0.0 && range[0] > d && !OutsideTheSides(planes, b))
    {
      return true;
    }
  }
  return false;
}
}
