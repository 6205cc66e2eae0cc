// VPCSS: volumetric percentage-closer soft shadows (Klein, Tappert,
// Nischwitz, Obermeier; ../shared/papers/vpcss-volumetric-pcss.md) over the
// light's adaptive volumetric shadow map (§4): per pixel, the blocker search
// over the AVSM's transmittance functions with one replacement blocker per
// translucent layer (eq. 6, sign corrected), their weighted mean per texel
// (eqs. 7-8) and over the search window (eq. 13, with the early exit when
// nothing in the window blocks), the penumbra by parallel planes (eq. 14),
// and the transmittance filtered over the kernel by the texel-as-quad
// coverage integral on the AVSM's mean-function pyramid
// (glsl/ssAVSMLookup.glsl; the formulas in Rendering/Core ssVPCSS,
// unit-tested). The AVSM build and the pass are TranslucentSolver's; the
// planner gives it the lights with translucent casters (opacity < 1, RGBA
// textures, volumes) in their view (PlannerRule::TranslucentCasters).
#ifndef ssVPCSSSolver_h
#define ssVPCSSSolver_h

#include "ssTranslucentSolver.h"

namespace ss
{
class VPCSSSolver : public TranslucentSolver
{
public:
  explicit VPCSSSolver(Method method)
    : TranslucentSolver(method, false)
  {
  }
};
}

#endif
