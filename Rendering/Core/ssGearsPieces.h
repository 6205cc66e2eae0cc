// The closed pieces GEARS' closed-mesh rule and inner occluders need
// (GearsPieces, gears.md "Closed pieces"), found in a triangle soup as the
// solver sees it: the bench (`softshadows bench --gears`) and the render pass
// (ssCasterSet, for casters that did not come through
// vtkShadowCasterPreparation) both call this, one caster block (actor) at a
// time.
//
// Only exactly equal coordinates are welded: the rule is exact only where a
// shared edge has bit-identical end points in both its triangles (then their
// edge planes are exact negatives and no segment slips between them), and the
// solver sees the same coordinates. Nothing is repaired: a piece that is not
// closed and consistently oriented as given stays open (0), which only
// switches the rule off for it.
//
// Plain C++17 + GLM + TBB (Rendering/Core): no VTK, no GL.
#ifndef ssGearsPieces_h
#define ssGearsPieces_h

#include "ssGEARS.h"
#include "ssSolveProgress.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ss
{
/// What FindGearsPieces added.
struct GearsPieceCounts
{
  std::size_t pieces = 0;          ///< pieces appended (closed or open)
  std::size_t closedPieces = 0;    ///< of those, orientation +1 or -1
  std::size_t closedTriangles = 0; ///< triangles of the closed ones
  bool aborted = false;            ///< `progress` returned false: nothing was added
};

/// Finds the pieces of the triangles `tris` of a soup `v` (3 vertices a
/// triangle; `tris` are triangle indices into it, one caster block) and
/// appends them to `out`: out.piece[t] is set for every t in `tris` (out.piece
/// must already have room for it) and the new pieces' orientations are
/// appended to out.orientation.
///
/// A piece is an edge-connected component after welding equal coordinates.
/// It is closed when every edge of it is used by exactly two of its triangles
/// in opposite directions, every vertex's triangles form one fan (2-manifold,
/// as OpenMesh would accept it) and its signed volume is clearly non-zero;
/// its orientation is the sign of that volume (+1 outward, -1 inward: a
/// mirrored world transform turns an outward piece inward by itself). A
/// triangle with a non-finite coordinate or two equal corners (after
/// welding) gets an open piece of its own. `mayClose` false (a projective
/// transform, under which the world triangles' winding says nothing) makes
/// every piece open.
///
/// `progress` (optional) is called on the calling thread between the
/// search's stages with the fraction done; when it returns false the search
/// stops, `out` is left as it was and the counts say `aborted`. It runs in
/// parallel (TBB); the result does not depend on the number of threads.
GearsPieceCounts FindGearsPieces(const std::vector<glm::dvec3>& v, const std::vector<std::uint32_t>& tris,
  bool mayClose, GearsPieces& out, const SolveProgress& progress = {});

namespace detail
{
/// FindGearsPieces with the coordinates' hash masked by `hashMask`, so that
/// a test can make hashes collide (0: every corner collides) and check that
/// the exact weld they fall back on gives the same pieces.
GearsPieceCounts FindGearsPieces(const std::vector<glm::dvec3>& v, const std::vector<std::uint32_t>& tris,
  bool mayClose, GearsPieces& out, const SolveProgress& progress, std::uint64_t hashMask);
}

/// `mayClose` for a world transform given row-major (vtkMatrix4x4's layout):
/// true unless its last row is projective.
inline bool MayClosePieces(const double* m)
{
  return m[12] == 0.0 && m[13] == 0.0 && m[14] == 0.0 && m[15] == 1.0;
}
}

#endif
