// Hard AVSM (Salvi, Vidimce, Lauritzen, Lefohn 2010): the transmittance of
// each pixel's light from its texel of the light's adaptive volumetric
// shadow map, no filtering -- the hard shadows of translucent casters and
// volumes that VPCSS softens (issue 20: "hard AVSM as its own method, for
// comparison"). The AVSM and the pass it runs are TranslucentSolver's.
#ifndef ssAVSMSolver_h
#define ssAVSMSolver_h

#include "ssTranslucentSolver.h"

namespace ss
{
class AVSMSolver : public TranslucentSolver
{
public:
  explicit AVSMSolver(Method method)
    : TranslucentSolver(method, true)
  {
  }
};
}

#endif
