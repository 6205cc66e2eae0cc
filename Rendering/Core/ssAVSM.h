// Adaptive volumetric shadow maps (Salvi, Vidimce, Lauritzen, Lefohn 2010),
// the transmittance representation VPCSS builds on (VPCSS §4): per shadow-map
// texel, the light's transmittance along the texel's ray as a piecewise
// linear function of light-space depth with at most N nodes.
//
// This is the CPU build of the function the GPU builds (glsl/ssAVSMNodes.glsl
// mirrors every step in the same order and in float), used by the unit tests
// and as the specification of the GPU code:
// - a node is (depth, transmittance); between two nodes the function is
//   linear, before the first node it is 1, after the last it keeps the last
//   value. Two nodes at the same depth are a vertical drop: a thin surface.
// - a translucent surface (layer) of transmittance tau at depth d multiplies
//   the function behind d by tau (two nodes: the value before and after);
//   an extended blocker [entry, exit] (a volume's march step, Salvi's
//   "segment") multiplies it by a factor falling linearly from 1 at the
//   entry to tau at the exit; an opaque surface is a layer of tau 0 -- the
//   step to 0 -- after which no node is kept.
// - when more than N nodes remain, the interior node whose removal changes
//   the area under the curve least (the triangle it forms with its two
//   neighbours) is removed (Salvi §4.2); the first and the last node stay, so
//   where shadowing starts and the transmittance behind everything are kept.
// Transmittance has one channel, or three (coloured shadows, RGB); the
// removal area of three channels is the sum of theirs.
#ifndef ssAVSM_h
#define ssAVSM_h

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace ss
{
/// The largest number of nodes per texel (a multiple of 4: the GPU stores
/// nodes four to an RGBA texel).
constexpr int kAVSMMaxNodes = 16;

struct AVSMNode
{
  float depth = 0.0f;
  glm::vec3 t{ 1.0f }; ///< transmittance at and behind `depth` (channels beyond the function's are unused)
};

/// One fragment of a translucent surface as the GPU's fragment lists hold
/// it: its light-space depth and its transmittance.
struct AVSMFragment
{
  float depth = 0.0f;
  glm::vec3 t{ 1.0f };
};

/// Order of fragments before insertion (the GPU sorts the same way): by
/// depth, then by transmittance, so equal inputs build equal functions.
bool AVSMFragmentBefore(const AVSMFragment& a, const AVSMFragment& b);

class AVSMFunction
{
public:
  /// `maxNodes` is clamped to [4, kAVSMMaxNodes]; `channels` is 1 or 3.
  explicit AVSMFunction(int maxNodes = 8, int channels = 1);

  int MaxNodes() const { return this->N; }
  int Channels() const { return this->C; }
  const std::vector<AVSMNode>& Nodes() const { return this->Node; }
  /// Replaces the nodes (sorted by depth, transmittance not increasing);
  /// compresses to MaxNodes.
  void SetNodes(const std::vector<AVSMNode>& nodes);

  /// A thin translucent surface at `depth` with transmittance `tau`.
  void InsertLayer(float depth, const glm::vec3& tau);
  /// An extended blocker from `entry` to `exit` (>= entry) of total
  /// transmittance `tau` (Salvi's segment: the factor falls linearly inside).
  void InsertSegment(float entry, float exit, const glm::vec3& tau);
  /// An opaque surface: the step to 0.
  void InsertOpaque(float depth) { this->InsertLayer(depth, glm::vec3(0.0f)); }

  /// T(z): the value at z, behind a drop at exactly z.
  glm::vec3 Evaluate(float z) const;
  /// T just in front of z (a drop at exactly z is not included).
  glm::vec3 EvaluateFront(float z) const;
  float Evaluate1(float z) const { return this->Evaluate(z).x; }

  /// The area the curve would lose or gain without interior node i (the
  /// triangle it forms with its neighbours; three channels summed).
  float RemovalArea(std::size_t i) const;

private:
  void Insert(float a, float b, const glm::vec3& tau);
  void Compress();
  int N, C;
  std::vector<AVSMNode> Node;
};

/// Builds a texel's function as the GPU's resolve pass does: the translucent
/// fragments in front of `opaqueDepth` sorted (AVSMFragmentBefore) and merged
/// by depth with the volume march `segments` (entry, exit, tau; sorted by
/// entry), each inserted in that order, then the opaque step at
/// `opaqueDepth` (none when it is not finite or >= 1e38).
struct AVSMSegment
{
  float entry = 0.0f, exit = 0.0f;
  glm::vec3 t{ 1.0f };
};
AVSMFunction BuildAVSM(std::vector<AVSMFragment> fragments, const std::vector<AVSMSegment>& segments,
  float opaqueDepth, int maxNodes, int channels);

/// The exact transmittance the fragments, segments and opaque depth describe
/// at depth z (the product of every layer at or in front of z, the segments
/// with their linear falls, 0 behind the opaque depth): what an AVSM with
/// enough nodes equals.
glm::vec3 ExactTransmittance(const std::vector<AVSMFragment>& fragments, const std::vector<AVSMSegment>& segments,
  float opaqueDepth, float z);

/// One level of the AVSM pyramid: the mean of `count` (1..4) functions (the
/// 2x2 texels below a coarser texel), exact as a piecewise-linear function
/// (breakpoints at every child node, a drop where a child drops), then
/// compressed to `maxNodes` the same way. The filters read a coarse texel as
/// the mean transmittance of the texels it covers.
AVSMFunction MeanAVSM(const AVSMFunction* const* functions, int count, int maxNodes, int channels);

/// Transmittance of one translucent surface of colour `color` (RGB in [0, 1])
/// and opacity `alpha` for coloured shadows (SoftShadows' model; VPCSS §6
/// leaves wavelength-dependent blockers to future work): channel c passes
/// (1 - alpha) * (1 - alpha * (1 - k_c)), k = color / max(color) (black counts as
/// grey). A grey or white surface passes 1 - alpha in every channel (the
/// scalar model), an opaque one nothing; a coloured one passes its own hue
/// best: red glass of alpha 0.5 passes (0.5, 0.25, 0.25).
glm::vec3 ColoredTransmittance(const glm::vec3& color, float alpha);
}

#endif
