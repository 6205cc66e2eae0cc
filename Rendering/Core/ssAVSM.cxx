#include "ssAVSM.h"

#include <algorithm>
#include <cmath>

namespace ss
{
namespace
{
// Transmittance factor of a blocker [a, b] of transmittance tau at depth d
// (Salvi 2010 §4.1: a segment's factor falls linearly from 1 at its entry to
// tau at its exit; a thin layer, a == b, multiplies everything at and behind
// it).
glm::vec3 Factor(float d, float a, float b, const glm::vec3& tau)
{
  if (d < a)
  {
    return glm::vec3(1.0f);
  }
  if (d >= b)
  {
    return tau;
  }
  const float s = (d - a) / (b - a);
  return glm::vec3(1.0f) + (tau - glm::vec3(1.0f)) * s;
}

bool AllZero(const glm::vec3& t, int channels)
{
  return channels == 1 ? t.x <= 0.0f : (t.x <= 0.0f && t.y <= 0.0f && t.z <= 0.0f);
}

glm::vec3 Lerp(const AVSMNode& p, const AVSMNode& q, float z)
{
  const float s = (z - p.depth) / (q.depth - p.depth);
  return p.t + (q.t - p.t) * s;
}
}

bool AVSMFragmentBefore(const AVSMFragment& a, const AVSMFragment& b)
{
  if (a.depth != b.depth)
  {
    return a.depth < b.depth;
  }
  if (a.t.x != b.t.x)
  {
    return a.t.x < b.t.x;
  }
  if (a.t.y != b.t.y)
  {
    return a.t.y < b.t.y;
  }
  return a.t.z < b.t.z;
}

AVSMFunction::AVSMFunction(int maxNodes, int channels)
  : N(std::clamp(maxNodes, 4, kAVSMMaxNodes))
  , C(channels == 3 ? 3 : 1)
{
}

void AVSMFunction::SetNodes(const std::vector<AVSMNode>& nodes)
{
  this->Node = nodes;
  this->Compress();
}

glm::vec3 AVSMFunction::Evaluate(float z) const
{
  // the last node at or in front of z, then linear towards the next one
  const std::size_t n = this->Node.size();
  std::size_t i = n;
  for (std::size_t k = 0; k < n; ++k)
  {
    i = (this->Node[k].depth <= z) ? k : i;
  }
  if (i == n)
  {
    return glm::vec3(1.0f);
  }
  if (i + 1 == n)
  {
    return this->Node[i].t;
  }
  return Lerp(this->Node[i], this->Node[i + 1], z);
}

glm::vec3 AVSMFunction::EvaluateFront(float z) const
{
  const std::size_t n = this->Node.size();
  std::size_t i = n;
  for (std::size_t k = 0; k < n; ++k)
  {
    i = (this->Node[k].depth < z) ? k : i;
  }
  if (i == n)
  {
    return glm::vec3(1.0f);
  }
  if (i + 1 == n)
  {
    return this->Node[i].t;
  }
  return Lerp(this->Node[i], this->Node[i + 1], z);
}

float AVSMFunction::RemovalArea(std::size_t i) const
{
  const AVSMNode& p = this->Node[i - 1];
  const AVSMNode& q = this->Node[i];
  const AVSMNode& r = this->Node[i + 1];
  float area = 0.0f;
  for (int c = 0; c < this->C; ++c)
  {
    area += 0.5f * std::abs((q.depth - p.depth) * (r.t[c] - p.t[c]) - (r.depth - p.depth) * (q.t[c] - p.t[c]));
  }
  return area;
}

void AVSMFunction::Compress()
{
  // Salvi §4.2: remove the interior node of least area until N are left
  // (the first removal on ties, as the GPU does)
  while (static_cast<int>(this->Node.size()) > this->N)
  {
    std::size_t best = 1;
    float bestArea = this->RemovalArea(1);
    for (std::size_t i = 2; i + 1 < this->Node.size(); ++i)
    {
      const float a = this->RemovalArea(i);
      if (a < bestArea)
      {
        bestArea = a;
        best = i;
      }
    }
    this->Node.erase(this->Node.begin() + static_cast<std::ptrdiff_t>(best));
  }
}

void AVSMFunction::Insert(float a, float b, const glm::vec3& tauIn)
{
  glm::vec3 tau = glm::clamp(tauIn, 0.0f, 1.0f);
  if (this->C == 1)
  {
    tau = glm::vec3(tau.x);
  }
  if (!(a == a) || !(b == b) || (this->C == 1 ? tau.x >= 1.0f : (tau.x >= 1.0f && tau.y >= 1.0f && tau.z >= 1.0f)))
  {
    return; // nothing blocks (or no depth)
  }
  const bool thin = !(b > a);
  b = thin ? a : b;
  // the new nodes take the values of the function before the insertion: a
  // layer the value just in front of it (then that times tau), a segment
  // its value in front of the entry and its value at the exit times tau
  const glm::vec3 front = this->EvaluateFront(a);
  const AVSMNode A{ a, front };
  const AVSMNode B{ b, thin ? front * tau : this->Evaluate(b) * tau };
  std::vector<AVSMNode> out;
  out.reserve(this->Node.size() + 2);
  bool haveA = false, haveB = false;
  for (const AVSMNode& n : this->Node)
  {
    if (!haveA && n.depth >= a)
    {
      out.push_back(A);
      haveA = true;
      if (thin)
      {
        out.push_back(B); // in front of the nodes at the same depth: they are behind the new layer
        haveB = true;
      }
    }
    if (!haveB && n.depth > b)
    {
      out.push_back(B); // behind the nodes at the exit: they are inside the segment
      haveB = true;
    }
    out.push_back(AVSMNode{ n.depth, n.t * Factor(n.depth, a, b, tau) });
  }
  if (!haveA)
  {
    out.push_back(A);
  }
  if (!haveB)
  {
    out.push_back(B);
  }
  // nothing passes behind the first node without transmittance
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    if (AllZero(out[i].t, this->C))
    {
      out.resize(i + 1);
      break;
    }
  }
  this->Node = std::move(out);
  this->Compress();
}

void AVSMFunction::InsertLayer(float depth, const glm::vec3& tau)
{
  this->Insert(depth, depth, tau);
}

void AVSMFunction::InsertSegment(float entry, float exit, const glm::vec3& tau)
{
  this->Insert(entry, std::max(entry, exit), tau);
}

AVSMFunction BuildAVSM(std::vector<AVSMFragment> fragments, const std::vector<AVSMSegment>& segments,
  float opaqueDepth, int maxNodes, int channels)
{
  AVSMFunction f(maxNodes, channels);
  const bool opaque = std::isfinite(opaqueDepth) && opaqueDepth < 1e38f;
  if (opaque)
  {
    fragments.erase(std::remove_if(fragments.begin(), fragments.end(),
                      [&](const AVSMFragment& g) { return !(g.depth < opaqueDepth); }),
      fragments.end());
  }
  std::sort(fragments.begin(), fragments.end(), AVSMFragmentBefore);
  // merge the two depth-ordered streams: a fragment goes first when it is
  // not behind the next segment's entry
  std::size_t i = 0, j = 0;
  while (i < fragments.size() || j < segments.size())
  {
    if (j >= segments.size() || (i < fragments.size() && fragments[i].depth <= segments[j].entry))
    {
      f.InsertLayer(fragments[i].depth, fragments[i].t);
      ++i;
    }
    else
    {
      f.InsertSegment(segments[j].entry, segments[j].exit, segments[j].t);
      ++j;
    }
  }
  if (opaque)
  {
    f.InsertOpaque(opaqueDepth);
  }
  return f;
}

glm::vec3 ExactTransmittance(const std::vector<AVSMFragment>& fragments, const std::vector<AVSMSegment>& segments,
  float opaqueDepth, float z)
{
  if (std::isfinite(opaqueDepth) && opaqueDepth < 1e38f && z >= opaqueDepth)
  {
    return glm::vec3(0.0f);
  }
  glm::vec3 t(1.0f);
  for (const auto& g : fragments)
  {
    if (g.depth <= z && (!std::isfinite(opaqueDepth) || g.depth < opaqueDepth))
    {
      t *= glm::clamp(g.t, 0.0f, 1.0f);
    }
  }
  for (const auto& s : segments)
  {
    t *= Factor(z, s.entry, std::max(s.entry, s.exit), glm::clamp(s.t, 0.0f, 1.0f));
  }
  return t;
}

AVSMFunction MeanAVSM(const AVSMFunction* const* functions, int count, int maxNodes, int channels)
{
  AVSMFunction mean(maxNodes, channels);
  bool same = count > 0;
  for (int k = 1; k < count && same; ++k)
  {
    const auto& a = functions[0]->Nodes();
    const auto& b = functions[k]->Nodes();
    same = a.size() == b.size();
    for (std::size_t j = 0; j < a.size() && same; ++j)
    {
      same = a[j].depth == b[j].depth && a[j].t == b[j].t;
    }
  }
  if (same)
  {
    mean.SetNodes(functions[0]->Nodes()); // equal functions: the mean is one of them
    return mean;
  }
  std::vector<float> depths;
  for (int k = 0; k < count; ++k)
  {
    for (const auto& n : functions[k]->Nodes())
    {
      depths.push_back(n.depth);
    }
  }
  std::sort(depths.begin(), depths.end());
  depths.erase(std::unique(depths.begin(), depths.end()), depths.end());
  // at each breakpoint the mean in front of it and at it: between two
  // breakpoints every child is linear, so the mean is exactly these nodes
  std::vector<AVSMNode> nodes;
  const float w = 1.0f / static_cast<float>(std::max(count, 1));
  for (float d : depths)
  {
    glm::vec3 front(0.0f), at(0.0f);
    for (int k = 0; k < count; ++k)
    {
      front += functions[k]->EvaluateFront(d);
      at += functions[k]->Evaluate(d);
    }
    front *= w;
    at *= w;
    nodes.push_back(AVSMNode{ d, front });
    if (at != front)
    {
      nodes.push_back(AVSMNode{ d, at });
    }
  }
  mean.SetNodes(nodes);
  return mean;
}

glm::vec3 ColoredTransmittance(const glm::vec3& color, float alpha)
{
  const float a = std::clamp(alpha, 0.0f, 1.0f);
  const glm::vec3 c = glm::clamp(color, 0.0f, 1.0f);
  const float m = std::max(c.x, std::max(c.y, c.z));
  const glm::vec3 k = m > 1e-6f ? c / m : glm::vec3(1.0f);
  return (1.0f - a) * (glm::vec3(1.0f) - a * (glm::vec3(1.0f) - k));
}
}
