// VPCSS: volumetric percentage-closer soft shadows (Klein, Tappert,
// Nischwitz, Obermeier), the blocker depth of translucent blockers for the
// PCSS penumbra estimate, on the transmittance functions of an AVSM
// (ssAVSM.h). The full-screen filter (glsl/ssAVSMVisibilityFS.glsl, ssAVSMLookup.glsl)
// computes the same formulas per pixel; they are unit-tested here.
//
// Two errors of the paper are fixed here (Documentation/vpcss.md):
// - eq. 6 has the wrong sign: from eqs. 4 and 5, z_RB = z0 - (1/b) ln((I_E +
//   I_0) / (2 I_0)) with b = -ln(1 - alpha) / (zE - z0) gives
//   z_RB = z0 + (zE - z0) ln(1 - alpha/2) / ln(1 - alpha), a point inside the
//   blocker (the paper's minus puts it in front of the blocker's entry); its
//   limits are z0 + (zE - z0)/2 as alpha -> 0 and z0 at alpha = 1;
// - eq. 12 weighs the replacement blocker by sum_i alpha_i, which exceeds 1
//   for several layers; the total absorption is 1 - prod_i (1 - alpha_i) =
//   sum_i Delta_i (eq. 8), which is what eqs. 7 and 13 weigh with.
#ifndef ssVPCSS_h
#define ssVPCSS_h

#include "ssAVSM.h"

namespace ss
{
/// ln(1 - alpha/2) / ln(1 - alpha): where inside a blocker of opacity alpha
/// its replacement blocker sits, as a fraction of its thickness (eq. 6,
/// corrected). 1/2 for alpha <= 0 (the limit), 0 for alpha >= 1, never NaN.
double ReplacementBlockerFraction(double alpha);

/// Eq. 6 (sign corrected): the depth of the infinitely thin blocker that
/// replaces a homogeneous blocker from z0 to zE of opacity alpha: where the
/// light has lost half of what the blocker takes (eqs. 3-5).
double ReplacementBlockerDepth(double z0, double zE, double alpha);

/// Eqs. 7-8 on one transmittance function, restricted to what lies in front
/// of the receiver depth zR: each pair of consecutive nodes (the first node
/// paired with the value 1 in front of it) is a blocker from z0 to zE with
/// alpha_i = 1 - t_i / t_(i-1), whose weight Delta_i = alpha_i prod_(j<i)
/// (1 - alpha_j) = t_(i-1) - t_i (eq. 8) is the light it takes; the pair
/// that reaches past zR is cut at zR. `depth` is z_TF = sum Delta_i z_RB,i /
/// sum Delta_i (eq. 7), `weight` the sum of the Delta_i, 1 - T(zR) (summed
/// over the channels of a coloured function: one blocker for every
/// wavelength, each layer weighted by the light it takes of all of them).
/// A function with nothing in front of zR has weight 0 (depth 0).
struct BlockerEstimate
{
  double depth = 0.0;
  double weight = 0.0;
};
BlockerEstimate TransmittanceFunctionBlocker(const AVSMFunction& f, float zR);

/// Eq. 13: the blocker depth of the search window, the mean of the texels'
/// z_TF weighted by their Delta (BlockerEstimate::weight) and by `coverage`,
/// the part of each texel inside the window (1 for whole texels, as the
/// paper's sum has it). Negative when no texel has transmittance < 1 in front
/// of the receiver: the paper's early exit (the pixel is lit).
double WindowBlockerDepth(const BlockerEstimate* texels, const double* coverage, std::size_t count);
}

#endif
