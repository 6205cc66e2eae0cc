#ifndef ssPCSS_h
#define ssPCSS_h

#include "ssLightFrame.h"

#include <glm/glm.hpp>

// PCSS (Fernando 2005) in the notation of the PVSM paper §4. Light space has
// its origin at the light centre and axes (u, v, n); a point's light-space
// depth is z = dot(p - c, n). Perspective views (rect and point lights)
// project X = (x/z, y/z) onto the unit plane; orthographic views
// (directional lights) project X = (x, y).
//
// The visibility shader (Rendering/OpenGL2/glsl/ssVisibilityFS.glsl) computes
// the same formulas per pixel; they are unit-tested here.
namespace ss
{
/// PVSM §4 eq. 1: through blockers at depth zb, a light offset l (world
/// units on the light) maps to the unit-plane offset alpha * l with
/// alpha = (zr - zb) / (zr * zb). 0 when zb >= zr or zb <= 0.
double PerspectiveKernelScale(double zReceiver, double zBlocker);

/// Directional light of angular diameter theta: kernel half-width
/// (zr - zb) * tan(theta / 2) in orthographic units (0 when zb >= zr).
double DirectionalKernelHalfWidth(double zReceiver, double zBlocker, double angularDiameter);

/// PCSS step 1, the blocker-search region: the light's footprint seen from
/// the receiver on the plane of the nearest possible blocker zNear
/// (half-extent 0.5 * size * PerspectiveKernelScale(zr, zNear), unit plane).
glm::dvec2 BlockerSearchHalfExtent(const LightFrame& light, double zReceiver, double zNear);

/// Slope-scaled depth bias (world units): texelWorld * (constant + slope *
/// tan(theta)) with cosTheta = dot(normal, direction to the light); tan is
/// clamped to 10 so grazing receivers stay finite (cosTheta <= 1e-4 uses 10).
double SlopeScaledBias(double texelWorld, double cosTheta, double constantTexels, double slopeTexels);

/// Normal-offset distance (Holbert 2011; Filament, shaders/src/
/// common_shadowing.fs, computeLightSpacePosition): how far a shadow-map
/// lookup is moved along the receiver's geometric (facet) normal, in world
/// units: offsetTexels texels of the view's world texel size at the receiver
/// times sin(theta), theta the angle between that normal and the direction
/// to the light (cosTheta clamped to [0, 1]). Zero at normal incidence, where
/// the receiver's own texels are at its depth; one texel-scaled step at
/// grazing light, where a texel spans the most depth. ssShadowCommon.glsl
/// (selectReceiverView) computes the same.
double NormalOffsetDistance(double texelWorld, double cosTheta, double offsetTexels);

/// Receiver-plane depth: the depth, along the projection ray through X, of
/// the plane through the receiver point pLS (light space) with normal nLS,
/// clamped to pLS.z +- maxDelta (grazing planes are unbounded).
double ReceiverPlaneDepth(
  const glm::dvec3& pLS, const glm::dvec3& nLS, const glm::dvec2& X, bool orthographic, double maxDelta);

/// Fraction of a rect light's area above the tangent plane of a surface
/// point p with normal nrm (light points below it cannot be seen from the
/// surface): the rectangle clipped by a half-plane. Point lights give 0 or 1.
double LightFractionAboveTangentPlane(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& nrm);

/// Fraction of a rect light's area above both the tangent plane of the
/// shading normal `shading` and the plane of the surface's own triangle
/// (`geometric`) at p: what the exact visibility of a faceted surface with
/// interpolated normals sees of the light, before any other caster (a light
/// point below the triangle's plane is hidden by the triangle or its
/// neighbours; the shading normal's plane is the reference's clip). The
/// rectangle is clipped by both half-planes in coordinates scaled by its
/// half sizes, so the area stays finite for any light size (a 1e30 light
/// overflowed float's w * h). Point lights give 0 or 1.
double LightFractionAboveSurface(
  const LightFrame& light, const glm::dvec3& p, const glm::dvec3& shading, const glm::dvec3& geometric);

/// The fraction of the square [-1,1]^2 where f1 = (a, b, c) and f2 both
/// give a + b s + c t > 0 (the light in units of its half sizes above two
/// planes, as LightFractionAboveSurface clips it): the square clipped by
/// both half-planes (Sutherland-Hodgman), then the shoelace area.
double SquareFractionAbovePlanesByClipping(const glm::dvec3& f1, const glm::dvec3& f2);

/// The same fraction by the boundary integral instead of a clipped polygon:
/// the area is half the sum of cross(P0, P1) over the boundary's segments
/// P0 -> P1 (counter-clockwise), which are the parts of the square's four
/// edges on the positive side of both planes and the parts of each plane's
/// line inside the square on the positive side of the other (Liang-Barsky
/// intervals). No array indexed per point, so llvmpipe runs it in
/// registers: ssShadowCommon.glsl's lightAboveSurface is this code in float
/// (the polygon clip it replaced read and wrote local arrays lane by lane;
/// issue 20). Same result as the clip up to rounding, for any planes:
/// equal, parallel, facing each other, on an edge, constant (TestSSPCSS).
template <typename T>
T SquareFractionAbovePlanes(const glm::vec<3, T>& f1, const glm::vec<3, T>& f2);
}

#endif
