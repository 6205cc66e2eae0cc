// GEARS culling rules beyond the shafts (issue 23), applied while a cell's
// and a sample group's lists are built (ssGearsCells.cxx). Each only removes
// pairs whose exact raster sets no bit that is not set already, so no mask
// changes (tests: core.GEARSCulling.*).
//
// The horizon rule. A pixel's mask starts with the light samples below its
// tangent plane (PixelStart) [the reference's rule; GEARS §4.2 draws only
// what lies between S and the light]. If a point X of a segment from S to
// light sample l lies below that plane, (X - S) . N < 0 with X = S + t (l - S),
// t > 0, so (l - S) . N < 0: l is below the horizon and hidden already. A
// triangle or cluster box wholly below the tangent plane of every open
// sample of a cell or group therefore changes none of their masks. Samples
// whose mask is full already never draw again, and those without a normal
// have no horizon (the rule is off for their cell or group). The per-pixel
// rejection kernel applies the same test to one sample; here it runs once
// per cell (clusters) and per group (triangles) instead of once per pixel.
#include "ssGearsInternal.h"

namespace ss
{
namespace gears
{
void CollectHorizons(const CellScratch& w, const std::uint32_t* ids, std::size_t count, HorizonPlanes& h)
{
  h.p.clear();
  h.usable = true;
  for (std::size_t a = 0; a < count && h.usable; ++a)
  {
    const std::uint32_t q = ids ? ids[a] : static_cast<std::uint32_t>(a);
    if (w.state[q].full)
    {
      continue; // draws nothing more (umbra)
    }
    const glm::dvec3& N = w.N[q];
    const double l = glm::length(N);
    if (!(l > 0.0))
    {
      h.usable = false; // no horizon: every triangle may matter
      break;
    }
    const glm::dvec3 n = N / l;
    h.p.emplace_back(n, glm::dot(n, w.S[q]));
  }
  h.usable = h.usable && !h.p.empty();
}

bool BoxBelowHorizons(const HorizonPlanes& h, const float* b, double margin)
{
  if (!h.usable)
  {
    return false;
  }
  for (const glm::dvec4& P : h.p)
  {
    // the box's highest point along the plane's normal
    const double top = (P.x > 0.0 ? P.x * b[3] : P.x * b[0]) + (P.y > 0.0 ? P.y * b[4] : P.y * b[1]) +
      (P.z > 0.0 ? P.z * b[5] : P.z * b[2]);
    if (!(top < P.w - margin))
    {
      return false;
    }
  }
  return true;
}

int HorizonPlanesFloat(const HorizonPlanes& h, const glm::dvec3& o, double margin, float* planes)
{
  if (!h.usable || h.p.size() > static_cast<std::size_t>(kMaxHorizonPlanes))
  {
    return 0; // (groups hold at most GearsOptions::groupSize samples; a larger set is not filtered)
  }
  // In float the kernel's a x + b y + c z errs by a few float ulps of the
  // coordinates (at most the scene's size and its distance to the light),
  // far below the margin (twice the float culling margin, 1e-5 of those);
  // d is rounded down, so rounding it never drops more.
  int np = 0;
  for (const glm::dvec4& P : h.p)
  {
    const double d = P.w - glm::dot(glm::dvec3(P), o) - margin;
    float df = static_cast<float>(d);
    if (static_cast<double>(df) > d)
    {
      df = std::nextafter(df, -std::numeric_limits<float>::infinity());
    }
    float* q = planes + 4 * np++;
    q[0] = static_cast<float>(P.x);
    q[1] = static_cast<float>(P.y);
    q[2] = static_cast<float>(P.z);
    q[3] = df;
  }
  return np;
}

// The inner-occluder rule (occluder fusion at cluster level). A cell's inner
// occluders (boxes strictly inside closed pieces, ssGearsOccluders.cxx) are
// drawn into every open sample's mask before its list (SolveCells). If every
// segment from a start point S of the cell to a point X of a cluster passes
// through the interior of one such box B, then any light sample l whose
// segment from S crosses a triangle of the cluster at X passes through B
// before X, and B's faces have set l's bit already (a segment through a
// box's interior leaves it through a face that faces l, with S behind its
// plane; the exact raster is watertight at the faces' shared edges). So the
// cluster changes no bit of the cell's masks. Convexity makes this a test of
// 8 segments: the points at parameter t of the segments from the cell's box
// A to the cluster's box C fill the box (1 - t) A + t C, whose corners are
// those of the segments between corresponding corners of A and C, and B
// holds that box iff it holds its corners. A common t in (0, 1) at which all
// 8 lie in B (shrunk by the margin) proves it. A and C are light-frame
// boxes, B is axis-aligned in the solver's frame.
bool SegmentsThroughBox(const FaceTriangles& ft, const glm::dvec3& alo, const glm::dvec3& ahi, const glm::dvec3& clo,
  const glm::dvec3& chi, const double* B, double m)
{
  auto solver = [&](double x, double y, double z) { return ft.Lc + x * ft.u + y * ft.v + z * ft.n; };
  double t0 = 0.0, t1 = 1.0;
  // the centres first: most boxes are missed there
  {
    const glm::dvec3 ac = 0.5 * (alo + ahi), cc = 0.5 * (clo + chi);
    const glm::dvec3 P = solver(ac.x, ac.y, ac.z);
    if (!SlabClip(P, solver(cc.x, cc.y, cc.z) - P, B, m, t0, t1))
    {
      return false;
    }
  }
  for (int q = 0; q < 8; ++q)
  {
    const bool bx = q & 1, by = q & 2, bz = q & 4;
    const glm::dvec3 P = solver(bx ? ahi.x : alo.x, by ? ahi.y : alo.y, bz ? ahi.z : alo.z);
    const glm::dvec3 X = solver(bx ? chi.x : clo.x, by ? chi.y : clo.y, bz ? chi.z : clo.z);
    if (!SlabClip(P, X - P, B, m, t0, t1))
    {
      return false;
    }
  }
  return t0 < t1; // within [0, 1]: t0 starts at 0, t1 at 1
}
}
}
