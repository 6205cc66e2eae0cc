#ifndef ssPVSM_h
#define ssPVSM_h

// Predicted virtual soft shadow maps (Shen, Guennebaud, Yang, Feng 2011; the
// paper in ../shared/papers/pvsm-predicted-virtual-soft-shadow-maps.md): the
// numerics of §4.2 (kernel convolution), §5.1 (perceptual resolution
// prediction) and §5.2 (shadow-map tile grid, kd-tree tiling, tile merging)
// without OpenGL. The shaders in Rendering/OpenGL2/glsl/ssPVSM*.glsl compute
// the same formulas per pixel; they are unit-tested here.
//
// Units: "shadow-map space" is the projected plane of a shadow view (the unit
// plane X = (x/z, y/z) of a perspective view, (x, y) of an orthographic one).
// Kernels are parallelograms given by half axes: {c + a u + b v : a, b in [-1, 1]}.

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace ss
{
/// A parallelogram kernel by its half axes. After ConvolveKernels, v is
/// vertical (v.x == 0): the "semi axis aligned" parallelogram of §4.2.
struct KernelAxes
{
  glm::dvec2 u{ 0.0 };
  glm::dvec2 v{ 0.0 };
  double Area() const; ///< full area, 4 |det[u v]|
};

/// PVSM §4.2 / Fig. 6: the two parallelograms (u0, v0) and (u1, v1) read as
/// Gaussians of variance M M^T, summed, and turned back into the bounding
/// parallelogram whose v axis is vertical by the Cholesky factor L of the sum
/// (u_h, v_h the columns of L). This is the appendix's shader with its typo
/// fixed: it reads `v_out.y = sqrt(m11 - u2.y*u2.y)`, but u2 does not exist;
/// the lower-right entry of L is sqrt(m11 - l10^2) with l10 = u_out.y. The
/// square root's argument is clamped at 0 (rounding can make it negative for
/// nearly singular sums) and a zero m00 (both kernels vertical lines) gives
/// u_out = 0 rather than a division by zero.
KernelAxes ConvolveKernels(const glm::dvec2& u0, const glm::dvec2& v0, const glm::dvec2& u1, const glm::dvec2& v1);

/// Which fit of the user study (§5.1) drives the prediction.
enum class PerceptualMetric
{
  Dynamic = 0, ///< occluders or light moved: flicker must not show (the paper's default)
  Static = 1   ///< only the camera moved: the more aggressive fit
};
const char* PerceptualMetricName(PerceptualMetric m);

/// PVSM §5.1: rho(n) = P(log2 n), the minimal number of texels the kernel h
/// must span when it covers n pixels on screen, with the paper's cubic fits
///   P_d(x) = 0.667 + 0.7794 x + 0.3967 x^2 - 0.02716 x^3
///   P_s(x) = 0.5477 + 1.406 x - 0.04687 x^2 - 0.003944 x^3.
/// The fits came from penumbrae of 1 to 256 pixels and turn down past their
/// maximum (P_s at x = 7.64, n = 200; P_d at x = 10.6). Extrapolating them
/// would ask fewer texels of a wider penumbra, so x is clamped to
/// [0, min(8, argmax P)]: sub-pixel kernels are treated as one pixel (the
/// 1:1 hard-shadow rule of Giegl & Wimmer) and very wide ones keep the
/// largest measured rho. Non-finite or non-positive n gives rho(1).
double PerceptualRho(double n, PerceptualMetric m);
/// The cubic's coefficients (c0..c3) and the end of its clamp range, for shaders.
void PerceptualRhoCubic(PerceptualMetric m, double coeffs[4], double& xEnd);

/// Static metric automatically when only the camera moved since the last frame
/// (mode 0), or forced: mode 1 dynamic, mode 2 static.
PerceptualMetric ChooseMetric(int mode, bool castersOrLightsChanged);

/// PVSM eq. 4-5 for one pixel. h is its kernel (ConvolveKernels of the
/// light filter and the footprint), (uPhi, vPhi) the half axes of the warped
/// pixel footprint phi' (a half pixel step each, in shadow-map space):
///   n0 = |M_phi'^-1 (u_h.x, 0)|, n1 = |M_phi'^-1 (0, v_h.y)| (pixels),
///   texel_d = 2 e_d^T h_d / (quality * rho(n_d)) (shadow-map units).
/// The paper calls r_d a resolution; it is the texel size that resolution
/// must reach. quality scales rho (the user's knob: 2 asks twice as many
/// texels per kernel). A singular footprint (grazing view) takes n = 1.
struct TexelPrediction
{
  double n0 = 0.0, n1 = 0.0;         ///< kernel size on screen (pixels)
  double texel0 = 0.0, texel1 = 0.0; ///< largest acceptable texel (shadow-map units)
};
TexelPrediction PredictTexelSize(const KernelAxes& h, const glm::dvec2& uPhi, const glm::dvec2& vPhi,
  PerceptualMetric metric, double quality);

/// The shadow map tile grid (SMTG, §5.2): G x G cells over the view's extent
/// [x0,x1]x[y0,y1] of shadow-map space; each cell holds the smallest predicted
/// texel size of the pixels that project into it, per axis (min-blended;
/// +inf where no pixel needs shadowing). Level l of the pyramid holds the
/// minimum over 2^l x 2^l cells.
class TileGridPyramid
{
public:
  /// texels: G*G*2 floats (texel0, texel1 per cell, row-major, y up); G a
  /// power of two. Non-finite or non-positive values count as empty.
  TileGridPyramid(const float* texels, int G);
  /// All levels given, as the GPU builds them (§5.2 step 5): levels[l] holds
  /// (G>>l)^2 x 2 floats; values that are not finite and positive, or are
  /// >= 1e38 (the GPU's stand-in for +inf), count as empty. G = 0 (an empty
  /// pyramid) when the level count or any level's size does not match G.
  TileGridPyramid(const std::vector<std::vector<float>>& levels, int G);
  int Size() const { return this->G; }
  int Levels() const { return static_cast<int>(this->Level.size()); }
  /// min texel size along axis d over cells [x0,x1) x [y0,y1), any rectangle.
  double MinTexel(int d, int x0, int y0, int x1, int y1) const;

private:
  int G = 0;
  std::vector<std::vector<glm::dvec2>> Level;
};

/// A leaf of the kd-tree over the SMTG: cells [x0,x1) x [y0,y1) rendered as one
/// shadow map of resX x resY texels covering `rect` in shadow-map space.
struct ShadowTile
{
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int resX = 0, resY = 0;
  double rect[4] = { 0, 0, 0, 0 }; ///< x0 y0 x1 y1, shadow-map units
  bool clamped = false;            ///< one cell needing more than the maximum texture (capped)
};

/// PVSM §5.2 steps 5-6 after Giegl & Wimmer [GW07]: top-down over the SMTG
/// pyramid, a node's resolution per axis is ceil(node extent / its smallest
/// predicted texel); the node is a leaf when both fit maxTexture, otherwise it
/// is halved across the axis that exceeds the limit most (a single-cell node
/// is capped at maxTexture and flagged). Nodes without a prediction produce no
/// tile. Every non-empty cell ends in exactly one tile.
std::vector<ShadowTile> BuildShadowTiles(const TileGridPyramid& grid, const double extent[4], int maxTexture);

/// A tile's depth map for the CPU filter (row-major, y up, linear light-space
/// depth, +inf where nothing was drawn).
struct TileDepthMap
{
  const float* depth = nullptr;
  int w = 0, h = 0;
  double rect[4] = { 0, 0, 0, 0 }; ///< shadow-map extent of the tile
};

/// Running sums of the V·A / A merge (§5.2 "Kernels overlapping multiple
/// tiles"): each tile adds its lit area VA and the kernel area A it covers.
/// The paper writes V_dst = V_dst A_dst + V_src A_src, which is the lit area,
/// not a visibility; V is VA / A once every tile has been added.
struct CoverageAccum
{
  double litArea = 0.0;       ///< V·A (with a ReachParams: blocked texels count within their reach)
  double area = 0.0;          ///< A
  double backProjected = 0.0; ///< back-projected hidden fraction of the light (with a ReachParams)
  void Merge(const CoverageAccum& o);
  /// min(VA / A, 1 - backProjected), clamped to [0, 1]; VA / A is 1 when no
  /// tile saw the kernel (nothing was drawn there: lit).
  double Visibility() const;
};

/// What the per-texel reach needs (beyond the paper; pvsm.md "Streaks on a
/// concave wall"). A blocked texel of depth z_b can hide light from the
/// receiver (depth z_r) only within its reach: the light filter of §4 eq. 1
/// at z_b instead of z_avg, convolved with the pixel footprint as in §4.2.
/// With it, FilterKernelInTile accumulates two estimates of the hidden
/// fraction and Visibility() keeps the larger:
///  - PCSS over the kernel, where a blocked texel counts if it is at least
///    nearFraction of z_avg's height above the receiver (z_r - z_b >=
///    nearFraction (z_r - z_avg): the blockers PCSS sizes its kernel by) and
///    otherwise only within its own reach;
///  - back-projection (Guennebaud et al. 2006): every blocked texel within its
///    reach adds its area over the reach's area, exact for a blocker plane
///    at any depth.
/// A curved receiver's own surface rises slightly above its tangent plane
/// (z_b just below z_r) but lies beyond its tiny reach, so neither estimate
/// counts it; plain PCSS counted it across the whole kernel (facet streaks on
/// a lit concave wall).
struct ReachParams
{
  glm::dvec2 lightHalfSize{ 0.0 }; ///< rect: half width/height (world); directional: tan of the half angles
  bool orthographic = false;
  double zAvg = 0.0;                            ///< the blocker average the kernel was sized with
  glm::dvec2 viewSpan{ HUGE_VAL, HUGE_VAL };    ///< the view's extent: no light filter is wider
  double nearFraction = 0.5;
};

/// §4 eq. 1: the light filter's half axes (shadow-map units) through blockers
/// at zb for a receiver at zr, clamped to the view's extent (as the kernel
/// pass does: it grows without bound as zb -> 0).
glm::dvec2 LightFilterHalfAxes(const ReachParams& p, double zr, double zb);

/// The reach of a blocker at zb: the pixel footprint (the kernel h's
/// covariance minus the light filter at z_avg's) convolved with the light
/// filter at zb, as a semi-axis-aligned parallelogram (ConvolveKernels' form).
KernelAxes ReachAt(const KernelAxes& h, const ReachParams& p, double zr, double zb);

/// PVSM §4.1 eq. 2 along the semi-axis-aligned kernel h centred at c (both in
/// shadow-map space), restricted to one tile: the kernel is cut into vertical
/// panels one texel wide, each approximated by the axis-aligned box of the
/// parallelogram's height at the panel's centre (§4.2, last paragraph); each
/// texel adds its overlap with the box, times 1 when the receiver is lit
/// (receiverDepth(X) - bias <= texel depth, X the texel centre in shadow-map
/// space). Kernels wider than maxQuads texels use panels and rows of 2^l
/// texels whose (min, max) depth decides them when it can and whose centre
/// texel decides them otherwise, as the shader does; the bias of a test on a
/// quad of s texels is s * bias. (The shader's receiverDepth is the tangent
/// plane lowered by 0.05 of the lateral distance from the kernel centre; a
/// caller passes whatever receiverDepth it wants.) A kernel below 1e-3
/// texel in either direction is widened to that (an exact point has no area).
/// With reach (what the shader does), blocked texels are weighed by their
/// reach as ReachParams says, z_r being receiverDepth at c; without, every
/// blocked texel in the kernel counts (plain §4.1).
CoverageAccum FilterKernelInTile(const TileDepthMap& tile, const glm::dvec2& c, const KernelAxes& h,
  const std::function<double(double, double)>& receiverDepth, double bias, int maxQuads,
  const ReachParams* reach = nullptr);

/// PVSM stats in the layout of the paper's Table 1 (ms per stage) plus the
/// tiles, the texels rendered and the shadow memory.
struct PVSMStats
{
  double msGBuffer = 0, msLowResSM = 0, msKernel = 0, msTiling = 0, msTileSM = 0, msFiltering = 0, msTotal = 0;
  std::size_t tiles = 0, clampedTiles = 0;
  std::vector<std::pair<int, int>> tileResolutions;
  double texelsRendered = 0; ///< texels cleared, drawn and reduced (the read regions' with pvsm_tile_regions)
  double tileTexels = 0;     ///< texels of the tiles at their predicted resolutions, summed
  std::size_t tilesSkipped = 0; ///< tiles no pixel's kernel reaches: neither drawn nor filtered
  double filterPixels = 0;   ///< fragments of the filter passes' rectangles, summed over tiles
  double tileTrianglesDrawn = 0; ///< caster triangles drawn into the tiles, summed
  double shadowMemoryBytes = 0;
  std::string metric;
  double quality = 1.0;
};
std::string PVSMStatsToJSON(const PVSMStats& st);
}

#endif
