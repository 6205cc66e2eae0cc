// GEARS on closed meshes: the bitmask of one closed piece seen from one pixel
// sample by a winding count of its silhouette edges (Laine, Aila, Assarsson,
// Lehtinen and Akenine-Moeller 2005, "Soft shadow volumes for ray tracing",
// §3: the depth complexity of a light sample changes only across silhouette
// edges), instead of rasterising every triangle (GEARS §4.2).
//
// Seen from S, the faces that face S cover each ray from S once per layer of
// the piece it crosses (S outside); interior edges cancel, so along a row of
// light samples the layer count changes only where a silhouette edge (between
// a face S is in front of and one S is behind) crosses the plane through S
// and the row, nearer the light than S. Starting from the count along the
// row's limit direction -u (a reference ray from S, the same for every row;
// 0 when the whole piece is nearer the light than S), the count at each
// sample is that plus the signed crossings left of it, and the sample is
// hidden iff it is positive. The count along +u checks every row.
//
// Bit-identical to the triangle raster: each silhouette edge's function is
// the one SetupTriangle gives that edge in either adjacent triangle (the two
// agree exactly on a silhouette edge: sg (a x b) = (-sg) (b x a) bit for bit),
// evaluated per sample as the raster does, F = (A + C j) + B i, with the
// raster's tie rule (F >= 0 is inside). Where the count could depend on
// rounding, or the raster's bits on more than the faces' edge planes, the
// piece is declined (the caller keeps the triangle raster): a vertex not in
// front of a finite light (the raster tests the faces' planes too), S in a
// face's plane, a face within 4 eps of S whose plane passes within eps of it
// (the reference's start rule), a reference ray within 1e-9 (relative) of an
// edge or vertex or hitting the piece at S, S inside the piece (odd reference
// count), a silhouette vertex exactly in a row's plane (rows are crossed
// half-open per vertex; the raster's triangles are closed), a crossing level
// with S (relative 1e-9), a crossing edge parallel to the rows, a row whose
// crossings do not lead from the -u count to the +u count, or a negative
// count. Not covered: a sample within rounding of a projected vertex, where
// the triangle raster itself is not watertight.
//
// Plain C++17 + GLM (Rendering/Core): no VTK, no GL.
#ifndef ssGearsSilhouette_h
#define ssGearsSilhouette_h

#include "ssGEARS.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ss
{
/// One closed, consistently oriented piece with its edge adjacency.
struct GearsSilhouettePiece
{
  struct Edge
  {
    std::uint32_t a, b;   ///< vertices; face f0 runs a -> b, face f1 runs b -> a
    std::uint32_t f0, f1; ///< the two faces
  };
  std::vector<glm::dvec3> vertices;                ///< welded (bit-identical positions merged)
  std::vector<std::array<std::uint32_t, 3>> faces; ///< vertex ids in the input triangles' order
  std::vector<Edge> edges;

  /// From triangles (3 world points each, as given to the solver: shared
  /// vertices bit-identical). False, with `why`, unless every edge has
  /// exactly two faces running it in opposite directions (closed,
  /// 2-manifold at edges, consistently oriented) and no face is degenerate.
  bool Build(const std::vector<glm::dvec3>& triangles, std::string* why = nullptr);
};

/// What one silhouette mask did.
struct GearsSilhouetteStats
{
  std::size_t silhouetteEdges = 0; ///< edges between a face facing S and one facing away
  std::size_t stripEdges = 0;      ///< silhouette edges crossing at least one sample row
  std::size_t rectEdges = 0;       ///< ... and crossing one between two samples of a row (inside the light's samples)
  std::size_t rowCrossings = 0;    ///< (edge, row) crossings counted
  std::size_t referenceHits = 0;   ///< crossings of the reference rays along -u and +u
  const char* declined = nullptr;  ///< why the piece was declined (null: mask written)
};

/// The light samples the piece hides from start (world), ORed into mask, by
/// the silhouette winding count; the same light frame and sample layout as
/// GearsRasterizeTriangle (rect and directional lights, k x k). eps > 0: the
/// solver's start rule distance (faces whose plane passes within eps of the
/// start are declined). Returns false (mask untouched) when declined.
bool GearsSilhouetteMask(const LightFrame& light, const glm::dvec3& start, const GearsSilhouettePiece& piece, int k,
  double eps, GearsMask& mask, GearsSilhouetteStats* stats = nullptr);

/// The per-cell candidate rule: false only if edge e is a silhouette edge
/// for no start point in the world box [lo, hi] (the box lies strictly on
/// one side of both faces' planes, by a margin above the rounding of the
/// per-pixel test).
bool GearsEdgeMaySilhouette(const GearsSilhouettePiece& piece, std::size_t e, const glm::dvec3& lo, const glm::dvec3& hi);
}

#endif
