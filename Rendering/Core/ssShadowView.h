#ifndef ssShadowView_h
#define ssShadowView_h

#include "ssCoverage.h"
#include "ssLightFrame.h"

#include <glm/glm.hpp>
#include <cstddef>
#include <vector>

namespace ss
{
/// One shadow-map view of a light: light space has its origin at `origin` and
/// axes (u, v, n); perspective views project X = (x/z, y/z) onto the unit
/// plane, orthographic views X = (x, y). `extent` is the mapped window of X.
struct ShadowView
{
  glm::dvec3 origin{ 0.0 };
  glm::dvec3 u{ 1, 0, 0 }, v{ 0, 1, 0 }, n{ 0, 0, 1 };
  Rect extent{ -1, -1, 1, 1 };
  bool orthographic = false;

  glm::dvec3 ToLightSpace(const glm::dvec3& p) const
  {
    const glm::dvec3 d = p - origin;
    return { glm::dot(d, u), glm::dot(d, v), glm::dot(d, n) };
  }
  glm::dvec2 Project(const glm::dvec3& pLS) const
  {
    return orthographic ? glm::dvec2(pLS.x, pLS.y) : glm::dvec2(pLS.x, pLS.y) / pLS.z;
  }
};

/// An axis-aligned box (world or relative coordinates). Empty when min > max.
struct Box
{
  glm::dvec3 min{ 1e300 }, max{ -1e300 };
  bool Empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void Add(const glm::dvec3& p)
  {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void Add(const Box& b)
  {
    if (!b.Empty())
    {
      Add(b.min);
      Add(b.max);
    }
  }
  glm::dvec3 Center() const { return 0.5 * (min + max); }
  double Diagonal() const { return Empty() ? 0.0 : glm::length(max - min); }
  glm::dvec3 Corner(int i) const
  {
    return { (i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z };
  }
  bool Contains(const glm::dvec3& p) const
  {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
      p.z <= max.z;
  }
};

/// Fits a perspective view's extent to the part of `box` in front of the
/// plane z = zMin (the box is clipped by that plane, so boxes straddling the
/// light plane are handled), expanded by `margin` (a fraction of the size) and
/// clamped to |X| <= tMax. Returns false when no part of the box is in front.
/// `clamped` tells whether the clamp cut the extent (receivers beyond the
/// widest angle a single view covers).
bool FitPerspectiveExtent(
  const ShadowView& view, const Box& box, double zMin, double tMax, double margin, Rect& out, bool& clamped);

/// Fits an orthographic view's extent to the projection of `box`, expanded
/// by `margin` (fraction) plus `pad` (absolute).
Rect FitOrthographicExtent(const ShadowView& view, const Box& box, double margin, double pad);

/// The six 90-degree faces of a cube around `origin` (extent slightly over
/// [-1,1] so that filters near an edge stay inside one face).
std::vector<ShadowView> MakeCubeViews(const glm::dvec3& origin);

/// What MakeLightViews decided, for the effect plan.
struct LightViewInfo
{
  bool cube = false;     // a point light needed six faces
  bool clamped = false;  // receivers beyond the widest angle a view covers
  bool sideViews = false; // a rect light got four side views for them
  bool nothingInFront = false; // every receiver is behind a one-sided light
  bool fitted = false;   // the extent was fitted to the visible receivers
};

/// The receiver points the frame's camera sees: the G-buffer's pixels, which
/// are the points every solver evaluates, kept when inside the receivers'
/// bounds (relative coordinates, x y z per point). Views fitted to them hold
/// every point a solver looks up; `known` false (a tiled frame, whose tile
/// must not change the light-space data, or no G-buffer) fits to the boxes.
struct VisibleReceivers
{
  bool known = false;
  std::vector<float> xyz;
  std::size_t Count() const { return xyz.size() / 3; }
};

/// The points of `positions` (`stride` floats a pixel: x y z, and with
/// stride 4 the G-buffer's prop id, 0 for the background; NaN positions are
/// dropped too) inside `receivers` (relative coordinates; widened by 1e-5 of
/// its diagonal for the float positions).
VisibleReceivers CollectVisibleReceivers(
  const float* positions, std::size_t pixels, std::size_t stride, const Box& receivers);

/// Fits a perspective view's extent to visible receiver points: each point in
/// front of z = zMin, widened by the reach of what can shadow it. A caster or
/// kernel texel that shadows a receiver at depth zr from a rect light of half
/// sizes `halfSize` lies, seen from the light's centre, within
/// halfSize * (1/zb - 1/zr) of the receiver's projection (PVSM §4 eq. 1, the
/// PCSS kernel), zb >= `nearest` (the nearest caster's depth). Expanded by
/// `margin` (fraction) and clamped to |X| <= tMax. `beyond`: some point lies
/// outside |X| <= tMax. False when no point is in front.
bool FitPerspectiveExtentToPoints(const ShadowView& view, const VisibleReceivers& points, double zMin,
  double tMax, const glm::dvec2& halfSize, double nearest, double margin, Rect& out, bool& beyond);

/// `a` cut to `b`; `a` unchanged when they do not overlap.
Rect IntersectExtent(const Rect& a, const Rect& b);

/// The shadow-map views of a light, fitted to the receivers. The light frame
/// and the boxes must be in the same (relative) coordinates.
/// - rect light: one perspective view from its centre along its normal
///   (one-sided; axes along its edges so PCSS kernels are axis-aligned boxes);
/// - point light: one perspective view towards the receivers when they fit in
///   a cone of about 76 degrees half-angle, else six cube faces;
/// - directional light: one orthographic view placed behind casters and receivers.
/// With `visible` known, a perspective extent is the box-fitted one cut to the
/// visible receivers and the reach of what can shadow them
/// (FitPerspectiveExtentToPoints, `nearestCaster`: the nearest caster's depth
/// along a rect light's normal; at least 4 reaches wide, the blocker search's
/// cap); a directional light's view stays fitted to the bounds;
/// and a rect light gets four side views (half cube faces in front of its
/// plane) only when a visible receiver lies beyond the widest angle its main
/// view covers (issue 17: a light inside a closed sphere). Without it, the
/// side views are decided on the receivers' box corners.
std::vector<ShadowView> MakeLightViews(const LightFrame& light, const Box& receivers, const Box& casters,
  LightViewInfo& info, const VisibleReceivers* visible = nullptr, double nearestCaster = 0.0);

/// The plane PCSS searches for blockers on (a light-space depth of `view`):
/// the nearest caster vertex in front of the view (z > 0), at least
/// 1e-4 * `diagonal`; `diagonal` (the casters' size: the pass gives their
/// bulk's, ssTriangleSet.h) when no vertex is in front. `xyz` holds `count` floats (x, y, z per vertex) relative to
/// `offset`, which is added in double.
double BlockerSearchDepth(
  const ShadowView& view, const float* xyz, std::size_t count, const glm::dvec3& offset, double diagonal);
}

#endif
