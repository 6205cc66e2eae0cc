#ifndef ssClippingRange_h
#define ssClippingRange_h

class vtkRenderer;

namespace ss
{
/// The camera's clipping range from the cells it can see, not from every
/// prop's bounds (issue 17, stop 49). VTK's ResetCameraClippingRange() spans
/// all bounds and keeps the near plane at least 1/1000 of the far one: one
/// stray triangle 1e5 units away put the near plane hundreds of units out,
/// and a sliver in view reaching 1e10 put it past the whole scene; the
/// picture came out empty. A cell counts when its bounds are not wholly
/// outside one of the frustum's four side planes; where the near plane would
/// pass the nearest cell wholly in front, it moves to that cell and the far
/// plane to 1000 times it. A polydata's cells, a composite's leaves' cells
/// (ParaView's representations), walked in the actor's model coordinates
/// where it has a transform (stop 51); a volume counts by its bounds.
/// `aspect`: the viewport's width over height.
void ResetClippingRangeToVisible(vtkRenderer* renderer, double aspect);

/// Whether the camera's near plane may pass visible cells, from the props'
/// bounds alone: the cheap test of whether ResetClippingRangeToVisible (one
/// pass over every cell) is needed, for a view that resets its range every
/// frame. True when a visible prop whose bounds are wholly in front of the
/// camera, and not outside the frustum's side planes, lies nearer than the
/// near plane; or when the camera is among a visible prop's bounds and the
/// near plane lies beyond the focal point (a mesh around the camera with a
/// lost vertex far out: its bounds cannot say where its cells are).
bool NearPlaneMayPassVisibleCells(vtkRenderer* renderer, double aspect);

/// A mesh reaching from the view far out (a needle to a lost vertex) is drawn
/// with its float coordinates shifted to the camera's focal point, not to its
/// bounds' centre (VTK's automatic rule): its bounds' centre lies more than
/// 100 camera distances from the focal point while its bounds come within 100
/// of it. Other mappers keep their method.
void ShiftFarReachingMappersToTheFocalPoint(vtkRenderer* renderer);
}

#endif
