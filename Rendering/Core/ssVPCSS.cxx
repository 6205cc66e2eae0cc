#include "ssVPCSS.h"

#include <algorithm>
#include <cmath>

namespace ss
{
double ReplacementBlockerFraction(double alpha)
{
  if (!(alpha > 0.0))
  {
    return 0.5; // alpha -> 0: ln(1 - a/2) / ln(1 - a) -> 1/2 (NaN alphas land here too)
  }
  if (alpha >= 1.0)
  {
    return 0.0; // an opaque blocker is replaced by its front
  }
  if (alpha < 1e-3)
  {
    return 0.5 - alpha / 8.0; // series: ln(1-a/2)/ln(1-a) = 1/2 - a/8 + O(a^2)
  }
  return std::log1p(-0.5 * alpha) / std::log1p(-alpha);
}

double ReplacementBlockerDepth(double z0, double zE, double alpha)
{
  // VPCSS eq. 6 with the sign of eqs. 4-5 (the paper prints z0 - ...)
  return z0 + (zE - z0) * ReplacementBlockerFraction(alpha);
}

BlockerEstimate TransmittanceFunctionBlocker(const AVSMFunction& f, float zR)
{
  const auto& nodes = f.Nodes();
  const int channels = f.Channels();
  double sum = 0.0, weight = 0.0;
  glm::vec3 prevT(1.0f);
  float prevDepth = nodes.empty() ? 0.0f : nodes.front().depth;
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    const float z0 = prevDepth;
    if (!(z0 < zR))
    {
      break; // this blocker starts at or behind the receiver
    }
    float zE = nodes[i].depth;
    glm::vec3 t = nodes[i].t;
    if (!(zE < zR))
    {
      // the blocker reaches the receiver: only its part in front counts
      t = f.EvaluateFront(zR);
      zE = zR;
    }
    for (int c = 0; c < channels; ++c)
    {
      const double before = prevT[c], after = t[c];
      const double delta = before - after; // eq. 8: alpha_i prod (1 - alpha_j)
      if (!(before > 0.0) || !(delta > 0.0))
      {
        continue;
      }
      const double alpha = 1.0 - after / before;
      sum += delta * ReplacementBlockerDepth(z0, zE, alpha);
      weight += delta;
    }
    prevT = t;
    prevDepth = nodes[i].depth;
  }
  BlockerEstimate e;
  e.weight = weight;
  e.depth = weight > 0.0 ? sum / weight : 0.0; // eq. 7
  return e;
}

double WindowBlockerDepth(const BlockerEstimate* texels, const double* coverage, std::size_t count)
{
  double sum = 0.0, weight = 0.0;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double w = (coverage ? coverage[i] : 1.0) * texels[i].weight;
    if (w > 0.0)
    {
      sum += w * texels[i].depth;
      weight += w;
    }
  }
  return weight > 0.0 ? sum / weight : -1.0; // eq. 13; -1: the early exit, no blocker
}
}
