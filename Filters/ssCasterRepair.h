// The OpenMesh/CGAL half of vtkShadowCasterPreparation, without VTK: a welded
// triangle soup in, a repaired and classified triangle mesh out.
#ifndef ssCasterRepair_h
#define ssCasterRepair_h

#include "ssShadowView.h" // ss::Box

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace ssf
{
struct RepairInput
{
  std::vector<glm::dvec3> points;                     ///< finite, welded
  std::vector<std::array<std::int64_t, 3>> triangles; ///< indices into points
  std::vector<std::int64_t> sourceCell;               ///< per triangle: the input cell it came from
  std::vector<std::int64_t> sourcePoint;              ///< per point: the input point it came from
};

struct RepairOptions
{
  /// World units: border vertices this close to a border edge are snapped
  /// onto it (T-junctions). 0 switches snapping off.
  double tolerance = 0.0;
  bool snapTJunctions = true;
  bool checkSelfIntersections = true;
  /// Closed, self-intersection-free pieces oriented inwards are reversed.
  bool orientOutward = true;
  /// Pieces are processed in parallel in units of about this many triangles
  /// (small pieces share a unit, so thousands of leaves cost no more than one mesh).
  std::size_t unitTriangles = 8192;
};

/// What the repair did and found; every count is of triangles unless named otherwise.
struct RepairStats
{
  std::size_t collapsed = 0;          ///< two or three corners welded into one: dropped
  std::size_t degenerate = 0;         ///< zero area (CGAL) or a height below the tolerance: removed
  std::size_t nonManifoldEdges = 0;   ///< edges with more than two faces, cut apart
  std::size_t nonManifoldVertices = 0; ///< vertices whose faces form several fans, split
  std::size_t duplicatedPoints = 0;   ///< points added by those cuts and splits
  std::size_t flippedForConsistency = 0; ///< faces reversed to agree with their neighbours
  std::size_t tJunctionsSnapped = 0;  ///< border vertices snapped onto border edges
  std::size_t pieces = 0;             ///< edge-connected components
  std::size_t closedPieces = 0;
  std::size_t openPieces = 0;
  std::size_t selfIntersectingPieces = 0; ///< of the closed pieces (open ones are not tested)
  std::size_t reorientedPieces = 0;   ///< closed pieces reversed to face outwards
  std::size_t closedOutwardPieces = 0;
  /// CPU time (milliseconds) per step, summed over the units (each unit runs
  /// on one thread; a component above 200k faces also tests itself for
  /// self-intersections on helper threads, which this does not count).
  double msOrientSoup = 0, msBuildMesh = 0, msDegenerate = 0, msSnap = 0, msComponents = 0,
         msSelfIntersections = 0, msOrientation = 0, msNormalsOut = 0;
};

struct PieceInfo
{
  std::size_t triangles = 0;
  bool closed = false;
  bool selfIntersecting = false;
  bool reoriented = false;
  bool closedOutward = false; ///< closed, no self-intersection, faces oriented outwards
  ss::Box bounds;
};

struct RepairedMesh
{
  std::vector<glm::dvec3> points;
  std::vector<std::int64_t> sourcePoint; ///< -1: a point the repair made (a snapped T-junction)
  std::vector<glm::dvec3> pointNormals;  ///< unit (OpenMesh: mean of the face normals)
  std::vector<std::array<std::int64_t, 3>> triangles;
  std::vector<std::int64_t> sourceCell;
  std::vector<glm::dvec3> faceNormals;   ///< unit; zero for a face too small to have one
  std::vector<std::int64_t> piece;       ///< per triangle, index into pieces
  std::vector<PieceInfo> pieces;
};

/// Called on the calling thread with the fraction done; return false to stop
/// (RepairMesh then returns what it has, with `aborted` set).
using RepairProgress = std::function<bool(double)>;

/// Imports each vertex-connected piece into an OpenMesh half-edge mesh through
/// CGAL's soup orientation (non-manifold edges and vertices are cut apart, so
/// nothing is dropped), removes degenerate faces, snaps T-junctions and
/// stitches the borders they leave, then classifies each edge-connected
/// component with CGAL Polygon Mesh Processing (is_closed, does_self_intersect,
/// is_outward_oriented, reverse_face_orientations) and computes normals with
/// OpenMesh. Pieces run in parallel (TBB); the result does not depend on the
/// number of threads.
RepairedMesh RepairMesh(const RepairInput& in, const RepairOptions& options, RepairStats& stats,
  const RepairProgress& progress, bool* aborted = nullptr);

}

#endif
