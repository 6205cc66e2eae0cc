#ifndef ssLightFrame_h
#define ssLightFrame_h

#include <glm/glm.hpp>

namespace ss
{
enum class LightType
{
  Rect,
  Point,
  Directional
};

/// A light's geometry. DESIGN.md scene format: `n` is the direction the light
/// faces, `v` its height edge ("up" made orthogonal to n), `u` its width edge
/// normalize(cross(up, n)).
struct LightFrame
{
  LightType type = LightType::Point;
  glm::dvec3 center{ 0.0 };
  glm::dvec3 u{ 1, 0, 0 }, v{ 0, 1, 0 };
  glm::dvec3 n{ 0, 0, -1 };
  double width = 0, height = 0;  // rect size (world units)
  double angularDiameter = 0;    // directional: radians
  bool IsSoft() const;
};

LightFrame MakeRectLightFrame(
  const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec3& up, const glm::dvec2& size);
LightFrame MakePointLightFrame(const glm::dvec3& position);
LightFrame MakeDirectionalLightFrame(const glm::dvec3& direction, double angularDiameterRadians);
/// The world axis least aligned with n, made orthogonal to n.
glm::dvec3 FallbackUp(const glm::dvec3& n);
/// The distance from a point to the light, given as `fromCenter` = point -
/// light.center: to its rectangle (a point light: its centre); infinity for a
/// directional light. Caps the ray start offsets (ssTriangleSet.h StartOffset).
double DistanceToLight(const LightFrame& light, const glm::dvec3& fromCenter);
/// Centre of cell (i, j) of a regular k x k grid on a rect light.
glm::dvec3 RegularLightSample(const LightFrame& light, int i, int j, int k);

/// Sample (i, j) of the regular k x k grid over a light, as a light without
/// extent. The brute-force soft shadow PVSM compares against (§6: the average
/// of 64 hard shadow maps) renders one hard map per such light. A rect light
/// gives a zero-size rect at RegularLightSample (same facing and axes); a
/// directional light gives the direction through cell (i, j) of its square of
/// directions (the reference samples it the same way); a point light is itself.
LightFrame LightSampleFrame(const LightFrame& light, int i, int j, int k);

/// Distance, in scene diagonals, beyond which a rect or point light is
/// shadowed as a directional light (FarLightAsDirectional).
constexpr double kFarLightRatio = 1.0e3;

/// A rect or point light farther than kFarLightRatio scene diagonals from
/// the centre of the scene `sceneCenter` (diagonal `sceneDiagonal`), as the
/// directional light it is for the scene: the direction from its centre to
/// the scene's, the angular diameter the larger of its two axes subtends there
/// (a tilted light's foreshortened). Float light
/// space cannot tell the scene's depths apart seen from a light that far
/// (its depths differ in the 8th digit: no shadow at all at 1e6 diagonals,
/// issue 17), while the directions to it across the scene differ by at most
/// 1/kFarLightRatio radians. False (out untouched) when the light is near
/// enough, directional already, or a one-sided rect light facing away.
bool FarLightAsDirectional(
  const LightFrame& light, const glm::dvec3& sceneCenter, double sceneDiagonal, LightFrame& out);

/// Largest rect light side the shadow shaders are given: their float half
/// sizes, areas and kernels overflow beyond it (a light of 1e39, finite in
/// double, gave V = 0 on every pixel under PCSS, PVSM and VPCSS).
constexpr double kMaxRectLightSize = 1.0e30;

/// A rect light with a side beyond kMaxRectLightSize as one whose larger side
/// is kMaxRectLightSize (both sides scaled alike, so its shape is kept). For
/// a scene within the float range the two hide the same fraction to float
/// precision: at 1e30 V is already the light's part above each receiver's
/// tangent plane (stability.md). False (light untouched) otherwise.
bool ClampRectLightSize(LightFrame& light);

/// The factor VTK's diffuse lighting multiplies a light's V with at point p
/// (normal nrm, seen from eye): max(0, n . l), l the unit vector towards the
/// light's centre (against the direction of a directional light), n = nrm
/// normalised and turned towards the eye as VTK's shaders do for back faces.
/// Where it is 0 the picture does not depend on V. NaN for a non-finite or
/// zero normal, or a point at the light's centre.
double DiffuseCosine(const LightFrame& light, const glm::dvec3& p, const glm::dvec3& nrm, const glm::dvec3& eye);
}

#endif
