// The translucent receivers' V once per fragment, not once per depth peel
// (issue 20). With depth peeling, VTK draws every translucent prop once per
// peel and once more to blend what is left, and llvmpipe runs a fragment's
// whole shader in every one of those draws, masked or not (it runs both
// sides of every branch): the per-fragment VPCSS filter of a translucent
// receiver (ssTranslucentReceivers) ran 9 to 17 times per fragment. So,
// when the renderer peels, the pass first draws the translucent receivers
// once with that filter (the "record" draw, the G-buffer's depth test
// against the opaque props, early fragment tests) and stores, per pixel, a
// list of (depth, V per light slot); the peels' shaders then hold no filter
// and read their fragment's V from its pixel's list, the entry nearest in
// depth (the same triangles through the same vertex shader give the same
// depth: VTK's peeling itself compares depths across its draws within
// 1e-7).
//
// One shader storage buffer of uints: [0] entries appended, [1] lookups that
// found no entry within kListDepthTolerance (counted only with the capture
// on, a test hook), [4, 4 + W H) each pixel's first entry + 1 (0: none), then
// the entries of `Stride()` uints: depth bits, next entry + 1, then per slot
// 1 or 3 channels of V. A frame whose fragments do not fit is recorded again
// into a buffer grown to hold them, up to the budget and the GL's largest
// storage block; beyond it the pass falls back to the filter in the peels'
// shaders (and its plan note says so).
#ifndef ssFragmentLists_h
#define ssFragmentLists_h

#include <string>

class vtkOpenGLRenderWindow;
class vtkShaderProgram;

namespace ss
{
/// Lookups whose nearest entry differs in depth by more than this count as
/// misses (capture only).
constexpr float kListDepthTolerance = 1e-6f;

class FragmentLists
{
public:
  ~FragmentLists();

  /// The record draw's code: the buffer's declaration and
  /// ssRecordFragment(), which appends this fragment's depth and its V for
  /// every slot (ssFragmentVisibility(ssFragLayer[k]), which the caller's
  /// code defines).
  static std::string RecordCode();
  /// The peels' code: ssListedVisibility(int slot) (vec3) reads the V of this
  /// fragment's entry; with `countMisses`, a fragment with no entry within
  /// the tolerance is counted.
  static std::string LookupCode(bool countMisses);

  /// Before the record draw: a buffer for `width` x `height` pixels and
  /// entries of `slots` slots of `channels` channels, with room for the
  /// last frame's fragments (at least 2 per pixel), heads and counters
  /// cleared, bound. False (with `error`) when GL has no storage buffers in
  /// fragment shaders or none of that size can be made.
  bool Begin(vtkOpenGLRenderWindow* win, int width, int height, int slots, int channels, std::string& error);
  /// After the record draw: true when every fragment got its entry; false
  /// when the buffer was too small, after growing it for a second record
  /// (`retry` true) or, past the budget, leaving the lists unusable
  /// (`retry` false, `error` says why).
  bool End(bool& retry, std::string& error);

  /// The uniforms of the record and of the peels' code.
  void SetUniforms(vtkShaderProgram* program) const;
  /// Bind and unbind the buffer around the shading stage.
  void Bind() const;
  void Unbind() const;

  /// Lookups with no entry since the last Begin (reads the counter).
  long long ReadMisses() const;
  long long Fragments() const { return this->Count; }
  int Stride() const { return 2 + this->Slots * this->Channels; }
  long long Bytes() const { return this->Allocated; }
  int CountGraphicsResources() const { return this->Buffer != 0 ? 1 : 0; }
  void ReleaseGraphicsResources();

private:
  unsigned int Buffer = 0;
  long long Allocated = 0; ///< bytes
  long long Capacity = 0;  ///< entries the buffer holds
  long long Count = 0;     ///< entries the last record appended
  long long Wanted = 0;    ///< entries the next Begin makes room for
  int Width = 0, Height = 0, Slots = 1, Channels = 1;
};
}

#endif
