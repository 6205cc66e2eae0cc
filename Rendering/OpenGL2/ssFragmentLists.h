// The translucent receivers' V once per fragment, not once per depth peel
// (issue 20). With depth peeling, VTK draws every translucent prop once per
// peel and once more to blend what is left, and llvmpipe runs a fragment's
// whole shader in each of those draws where any fragment of its block is
// still live: VPCSS's per-fragment filter of a translucent receiver
// (ssTranslucentReceivers) ran 9 to 17 times per fragment, at a fraction
// of the lanes; without peeling once, but at those lanes (2.6x the
// full-screen pass below on particles.json). So:
//   1. the record draw: the translucent receivers once, with the G-buffer's
//      depth test against the opaque props (early fragment tests), a short
//      shader that appends each fragment's depth, position, shading normal
//      and facet normal to its pixel's list (no filter);
//   2. the filter pass: a full-screen pass with one fragment per listed
//      entry runs the lookup of each light slot on it and stores V in the
//      entry: every lane busy, each fragment filtered once;
//   3. the shading's shaders (every peel's) hold no lookup: each reads its
//      fragment's V from its pixel's list, the entry nearest in depth (the
//      same triangles through the same vertex shader give the same depth:
//      VTK's peeling itself compares depths across its draws within 1e-7).
//
// One shader storage buffer of uints: [0] entries appended, [1] lookups that
// found no entry within kListDepthTolerance (counted only with the capture
// on, a test hook), [4, 4 + W H) each pixel's first entry + 1 (0: none), then
// the entries of `Stride()` uints: depth bits, next entry + 1, position,
// shading normal, facet normal (3 floats each), then per slot 1 or 3
// channels of V. A frame whose fragments do not fit is recorded again into
// a buffer grown to hold them, up to the budget and the GL's largest storage
// block; beyond it the pass falls back to the filter in the peels' shaders
// (with a warning).
#ifndef ssFragmentLists_h
#define ssFragmentLists_h

#include "vtkSmartPointer.h"

#include <functional>
#include <memory>
#include <string>

class vtkOpenGLFramebufferObject;
class vtkOpenGLQuadHelper;
class vtkOpenGLRenderWindow;
class vtkShaderProgram;
class vtkTextureObject;
class vtkWindow;

namespace ss
{
/// Lookups whose nearest entry differs in depth by more than this count as
/// misses (capture only).
constexpr float kListDepthTolerance = 1e-6f;

class FragmentLists
{
public:
  FragmentLists();
  ~FragmentLists();
  FragmentLists(const FragmentLists&) = delete;
  FragmentLists& operator=(const FragmentLists&) = delete;

  /// The record draw's code: the buffer's declaration and
  /// ssRecordFragment(p, nrm, ng), which appends this fragment's depth,
  /// position and normals to its pixel's list.
  static std::string RecordCode();
  /// The filter pass's code: the buffer's declaration and the entry
  /// reads: ssListEntryAt(), ssListPoint(at, p, nrm, ng), ssListStore(at,
  /// slot, V); the caller's main() filters every entry.
  static std::string FilterCode();
  /// The peels' code: ssListedVisibility(int slot) (vec3) reads the V of this
  /// fragment's entry, ssListedPoint(p, nPlane) the point its filter took;
  /// with `countMisses`, a fragment with no entry within the tolerance is
  /// counted.
  static std::string LookupCode(bool countMisses);

  /// Before the record draw: a buffer for `width` x `height` pixels and
  /// entries of `slots` slots of `channels` channels, with room for the
  /// last frame's fragments (at least 2 per pixel), heads and counters
  /// cleared, bound. False (with `error`) when GL has no storage buffers in
  /// fragment shaders or none of that size can be made.
  bool Begin(vtkOpenGLRenderWindow* win, int width, int height, int slots, int channels, std::string& error);
  /// Around the record draw: `fbo` drawing to `color` (no colour written)
  /// with the depth test against `depth` (the G-buffer's: fragments behind
  /// opaque props, which the peels discard, are not listed; early fragment
  /// tests), no depth writes, no blending, over the lists' pixels. The
  /// caller keeps the colour mask and depth function it had (scoped).
  void BindRecordTarget(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, vtkTextureObject* color,
    vtkTextureObject* depth) const;
  void UnbindRecordTarget(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo) const;
  /// After the record draw: true when every fragment got its entry; false
  /// when the buffer was too small, after growing it for a second record
  /// (`retry` true) or, past the budget, leaving the lists unusable
  /// (`retry` false, `error` says why).
  bool End(bool& retry, std::string& error);

  /// After a complete record: the filter pass `fragmentShader` (a
  /// full-screen pass's, FilterCode() in it) over every entry, its uniforms
  /// set by `setUniforms`, into `fbo`. False (with `error`) when it cannot
  /// be built or drawn.
  bool Filter(vtkOpenGLRenderWindow* win, vtkOpenGLFramebufferObject* fbo, const std::string& fragmentShader,
    const std::function<void(vtkShaderProgram*)>& setUniforms, std::string& error);

  /// The uniforms of the record and of the peels' code.
  void SetUniforms(vtkShaderProgram* program) const;
  /// Bind and unbind the buffer around the shading stage.
  void Bind() const;
  void Unbind() const;

  /// Lookups with no entry since the last Begin (reads the counter).
  long long ReadMisses() const;
  long long Fragments() const { return this->Count; }
  int Stride() const { return kEntryHeader + this->Slots * this->Channels; }
  long long Bytes() const { return this->Allocated; }
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources(vtkWindow* w);

  static constexpr int kEntryHeader = 11; ///< uints before V: depth, link, position, two normals

private:
  unsigned int Buffer = 0;
  std::unique_ptr<vtkOpenGLQuadHelper> Quad; ///< the filter pass
  std::string QuadSource;                    ///< ... its fragment shader
  vtkSmartPointer<vtkTextureObject> Target;  ///< ... its target: one texel per entry
  long long Allocated = 0; ///< bytes
  long long Capacity = 0;  ///< entries the buffer holds
  long long Count = 0;     ///< entries the last record appended
  long long Wanted = 0;    ///< entries the next Begin makes room for
  int Width = 0, Height = 0, Slots = 1, Channels = 1;
};
}

#endif
