#include "ssShadowView.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ss
{
namespace
{
// Largest |X| = tan(angle) a single perspective view covers: tan(76 deg) ~ 4.
constexpr double kMaxTan = 4.0;

void ExpandRect(Rect& r, double margin, double pad)
{
  const double mx = (r.x1 - r.x0) * margin + pad;
  const double my = (r.y1 - r.y0) * margin + pad;
  r.x0 -= mx;
  r.x1 += mx;
  r.y0 -= my;
  r.y1 += my;
}

// Clamps r to |X| <= tMax; true when that cut it.
bool ClampExtent(Rect& r, double tMax)
{
  const bool cut = r.x0 < -tMax || r.y0 < -tMax || r.x1 > tMax || r.y1 > tMax;
  r.x0 = std::max(r.x0, -tMax);
  r.y0 = std::max(r.y0, -tMax);
  r.x1 = std::min(r.x1, tMax);
  r.y1 = std::min(r.y1, tMax);
  return cut;
}

void MakeNonDegenerate(Rect& r)
{
  // A view must have a positive size even for a flat or point-like box.
  const double w = r.x1 - r.x0, h = r.y1 - r.y0;
  const double s = std::max({ w, h, 1e-6 });
  if (w < 1e-3 * s)
  {
    r.x0 -= 0.5e-3 * s;
    r.x1 += 0.5e-3 * s;
  }
  if (h < 1e-3 * s)
  {
    r.y0 -= 0.5e-3 * s;
    r.y1 += 0.5e-3 * s;
  }
}
}

bool FitPerspectiveExtent(
  const ShadowView& view, const Box& box, double zMin, double tMax, double margin, Rect& out, bool& clamped)
{
  clamped = false;
  if (box.Empty())
  {
    return false;
  }
  glm::dvec3 c[8];
  for (int i = 0; i < 8; ++i)
  {
    c[i] = view.ToLightSpace(box.Corner(i));
  }
  Rect r{ 1e300, 1e300, -1e300, -1e300 };
  bool any = false;
  auto add = [&](const glm::dvec3& p) {
    glm::dvec2 X(p.x / p.z, p.y / p.z);
    r.x0 = std::min(r.x0, X.x);
    r.y0 = std::min(r.y0, X.y);
    r.x1 = std::max(r.x1, X.x);
    r.y1 = std::max(r.y1, X.y);
    any = true;
  };
  for (const auto& p : c)
  {
    if (p.z > zMin)
    {
      add(p);
    }
  }
  // Box edges crossing the plane z = zMin: the clipped polyhedron's new vertices.
  for (int i = 0; i < 8; ++i)
  {
    for (int bit = 1; bit < 8; bit <<= 1)
    {
      const int j = i | bit;
      if (j == i)
      {
        continue;
      }
      const glm::dvec3 &a = c[i], &b = c[j];
      if ((a.z > zMin) != (b.z > zMin))
      {
        const double t = (zMin - a.z) / (b.z - a.z);
        glm::dvec3 p = a + t * (b - a);
        p.z = zMin;
        add(p);
      }
    }
  }
  if (!any)
  {
    return false;
  }
  ExpandRect(r, margin, 0.0);
  clamped = ClampExtent(r, tMax);
  MakeNonDegenerate(r);
  out = r;
  return true;
}

Rect FitOrthographicExtent(const ShadowView& view, const Box& box, double margin, double pad)
{
  Rect r{ 1e300, 1e300, -1e300, -1e300 };
  for (int i = 0; i < 8; ++i)
  {
    const glm::dvec3 p = view.ToLightSpace(box.Corner(i));
    r.x0 = std::min(r.x0, p.x);
    r.y0 = std::min(r.y0, p.y);
    r.x1 = std::max(r.x1, p.x);
    r.y1 = std::max(r.y1, p.y);
  }
  ExpandRect(r, margin, pad);
  MakeNonDegenerate(r);
  return r;
}

VisibleReceivers CollectVisibleReceivers(
  const float* positions, std::size_t pixels, std::size_t stride, const Box& receivers)
{
  VisibleReceivers r;
  r.known = true;
  if (receivers.Empty() || !positions)
  {
    return r;
  }
  const glm::dvec3 tol(1e-5 * receivers.Diagonal() + 1e-30);
  const glm::dvec3 lo = receivers.min - tol, hi = receivers.max + tol;
  for (std::size_t i = 0; i < pixels; ++i)
  {
    const float* p = positions + stride * i;
    if (stride >= 4 && !(p[3] > 0.0f))
    {
      continue; // background
    }
    // NaN fails every comparison
    if (p[0] >= lo.x && p[0] <= hi.x && p[1] >= lo.y && p[1] <= hi.y && p[2] >= lo.z && p[2] <= hi.z)
    {
      r.xyz.insert(r.xyz.end(), p, p + 3);
    }
  }
  return r;
}

namespace
{
/// `r` widened about its centre to at least `width` on each axis.
void AtLeastWide(Rect& r, const glm::dvec2& width)
{
  for (int axis = 0; axis < 2; ++axis)
  {
    double& lo = axis == 0 ? r.x0 : r.y0;
    double& hi = axis == 0 ? r.x1 : r.y1;
    const double need = width[axis] - (hi - lo);
    if (need > 0.0)
    {
      lo -= 0.5 * need;
      hi += 0.5 * need;
    }
  }
}
}

bool FitPerspectiveExtentToPoints(const ShadowView& view, const VisibleReceivers& points, double zMin,
  double tMax, const glm::dvec2& halfSize, double nearest, double margin, Rect& out, bool& beyond)
{
  beyond = false;
  Rect r{ 1e300, 1e300, -1e300, -1e300 };
  glm::dvec2 maxReach(0.0);
  bool any = false;
  const std::size_t n = points.Count();
  for (std::size_t i = 0; i < n; ++i)
  {
    const float* p = points.xyz.data() + 3 * i;
    const glm::dvec3 q = view.ToLightSpace(glm::dvec3(p[0], p[1], p[2]));
    if (!(q.z > zMin))
    {
      continue;
    }
    const glm::dvec2 X(q.x / q.z, q.y / q.z);
    if (std::abs(X.x) > tMax || std::abs(X.y) > tMax)
    {
      beyond = true;
    }
    // PVSM §4 eq. 1: blockers between zb >= nearest and the receiver
    const double reach = (nearest > 0.0 && nearest < q.z) ? 1.0 / nearest - 1.0 / q.z : 0.0;
    maxReach = glm::max(maxReach, halfSize * reach);
    r.x0 = std::min(r.x0, X.x - halfSize.x * reach);
    r.x1 = std::max(r.x1, X.x + halfSize.x * reach);
    r.y0 = std::min(r.y0, X.y - halfSize.y * reach);
    r.y1 = std::max(r.y1, X.y + halfSize.y * reach);
    any = true;
  }
  if (!any)
  {
    return false;
  }
  ExpandRect(r, margin, 0.0);
  // The blocker search reads at most a quarter of the map on each side of a
  // receiver (ssShadowCommon.glsl, blockerSearch): the extent is at least 4
  // reaches wide, so a close-up of a small area under a large light does not
  // cut the search short.
  AtLeastWide(r, 4.0 * maxReach);
  ClampExtent(r, tMax);
  MakeNonDegenerate(r);
  out = r;
  return true;
}

Rect IntersectExtent(const Rect& a, const Rect& b)
{
  const Rect r{ std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1) };
  return (r.x0 < r.x1 && r.y0 < r.y1) ? r : a;
}

std::vector<ShadowView> MakeCubeViews(const glm::dvec3& origin)
{
  const glm::dvec3 axes[6] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
    { 0, 0, -1 } };
  std::vector<ShadowView> views;
  for (const auto& n : axes)
  {
    ShadowView v;
    v.origin = origin;
    v.n = n;
    v.v = FallbackUp(n);
    v.u = glm::normalize(glm::cross(v.v, n));
    v.extent = Rect{ -1.02, -1.02, 1.02, 1.02 };
    views.push_back(v);
  }
  return views;
}

std::vector<ShadowView> MakeLightViews(const LightFrame& light, const Box& receivers, const Box& casters,
  LightViewInfo& info, const VisibleReceivers* visible, double nearestCaster)
{
  info = LightViewInfo{};
  std::vector<ShadowView> views;
  Box all = receivers;
  all.Add(casters);
  const double diag = std::max(all.Diagonal(), 1e-12);
  const bool fit = visible && visible->known;
  Box seen; // the visible receivers' box (empty without them)
  if (fit)
  {
    for (std::size_t i = 0; i < visible->Count(); ++i)
    {
      const float* p = visible->xyz.data() + 3 * i;
      seen.Add(glm::dvec3(p[0], p[1], p[2]));
    }
  }

  if (light.type == LightType::Directional)
  {
    ShadowView v;
    v.orthographic = true;
    v.n = light.n;
    v.v = FallbackUp(light.n);
    v.u = glm::normalize(glm::cross(v.v, v.n));
    // Light-space depths are floats from the origin: it lies behind the
    // casters and the visible receivers, at their size. From the receivers'
    // whole bounds, a receiver sliver to a vertex at 1e10 put it 1e10 away,
    // and the depths kept 1e3 a step (stop 50).
    Box near = casters;
    near.Add(seen.Empty() ? receivers : seen);
    const double nearDiag = std::max(near.Diagonal(), 1e-12);
    v.origin = near.Center() - light.n * nearDiag;
    // Kernels reach at most nearDiag * tan(angle/2) beyond a visible
    // receiver: every caster of the bulk lies within nearDiag of it.
    const double pad = nearDiag * std::tan(0.5 * light.angularDiameter);
    // Fitted to the receivers' bounds, cut to the visible receivers' box
    // widened by the reach of what can shadow them and at least 4 reaches
    // wide: cut to the visible receivers alone, the wide PCSS kernels of a
    // large angular size outgrew the quarter of the map the search reads
    // (ParaView's SoftShadowViewLights lost penumbra); not cut, a receiver
    // sliver running sideways to 1e10 spread the map over it (stop 50).
    v.extent = FitOrthographicExtent(v, receivers.Empty() ? all : receivers, 0.02, pad);
    if (!seen.Empty())
    {
      Rect p = FitOrthographicExtent(v, seen, 0.02, pad);
      AtLeastWide(p, glm::dvec2(4.0 * pad));
      v.extent = IntersectExtent(v.extent, p);
      info.fitted = true;
    }
    views.push_back(v);
    return views;
  }

  ShadowView v;
  v.origin = light.center;
  if (light.type == LightType::Rect)
  {
    v.u = light.u;
    v.v = light.v;
    v.n = light.n;
  }
  else
  {
    glm::dvec3 dir = receivers.Center() - light.center;
    if (receivers.Empty() || glm::length(dir) < 1e-12 * diag || receivers.Contains(light.center))
    {
      info.cube = true;
      return MakeCubeViews(light.center);
    }
    v.n = glm::normalize(dir);
    v.v = FallbackUp(v.n);
    v.u = glm::normalize(glm::cross(v.v, v.n));
  }
  // the depth floor in front of the light, from the casters' and the visible
  // receivers' size where those are known: a receiver reaching far out of
  // view (a sliver to a vertex at 1e10) set it to 1e4 from the receivers'
  // whole bounds, and every visible receiver lay behind it (stop 49)
  // Without visible receivers (a tiled frame: ParaView's SaveScreenshot
  // larger than the view), from the casters' (stop 50).
  double scale = diag;
  Box near = casters;
  near.Add(seen);
  if (!near.Empty())
  {
    scale = std::min(diag, std::max(near.Diagonal(), 1e-12));
  }
  const double zMin = 1e-6 * scale;
  Rect r;
  bool clamped = false;
  if (!FitPerspectiveExtent(v, receivers, zMin, kMaxTan, 0.05, r, clamped))
  {
    if (light.type == LightType::Rect)
    {
      info.nothingInFront = true;
      v.extent = Rect{ -1, -1, 1, 1 };
      views.push_back(v);
      return views;
    }
    info.cube = true;
    return MakeCubeViews(light.center);
  }
  if (fit)
  {
    // the box's extent cut to the visible receivers and what can shadow them;
    // the clamp is decided on the points themselves, not on the box's corners
    // (none visible: nothing needs more than the box's extent)
    const glm::dvec2 half = light.type == LightType::Rect ? 0.5 * glm::dvec2(light.width, light.height)
                                                          : glm::dvec2(0.0);
    Rect p;
    bool beyond = false;
    if (FitPerspectiveExtentToPoints(v, *visible, zMin, kMaxTan, half, nearestCaster, 0.05, p, beyond))
    {
      r = IntersectExtent(r, p);
      info.fitted = true;
    }
    // a point light with a visible receiver behind its view or beyond it
    bool behind = false;
    if (light.type == LightType::Point)
    {
      for (std::size_t i = 0; i < visible->Count() && !behind; ++i)
      {
        const float* q = visible->xyz.data() + 3 * i;
        behind = !(v.ToLightSpace(glm::dvec3(q[0], q[1], q[2])).z > zMin);
      }
    }
    clamped = beyond || behind;
  }
  if (clamped && light.type == LightType::Point)
  {
    info.cube = true;
    return MakeCubeViews(light.center);
  }
  info.clamped = clamped;
  v.extent = r;
  views.push_back(v);
  if (clamped && light.type == LightType::Rect)
  {
    // Receivers beyond the widest angle the light's view covers: four side
    // views, half cube faces along +-u and +-v of the light in front of its
    // plane, hold them (the view above is selected first where both hold a
    // point). Before, those receivers were left unshadowed: a light inside a
    // closed sphere lit 1,623 ground pixels GEARS has dark (issue 17).
    for (const glm::dvec3& side : { light.u, -light.u, light.v, -light.v })
    {
      ShadowView s;
      s.origin = light.center;
      s.n = side;
      s.v = light.n; // y: height above the light's plane
      s.u = glm::normalize(glm::cross(s.v, s.n));
      s.extent = Rect{ -1.02, 0.0, 1.02, 1.02 };
      views.push_back(s);
    }
    info.sideViews = true;
  }
  return views;
}

double BlockerSearchDepth(
  const ShadowView& view, const float* xyz, std::size_t count, const glm::dvec3& offset, double diagonal)
{
  double zMin = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i + 2 < count; i += 3)
  {
    const glm::dvec3 p = offset + glm::dvec3(xyz[i], xyz[i + 1], xyz[i + 2]);
    const double z = view.ToLightSpace(p).z;
    if (z > 0.0 && z < zMin)
    {
      zMin = z;
    }
  }
  return (zMin == std::numeric_limits<double>::max()) ? diagonal : std::max(zMin, 1e-4 * diagonal);
}
}
