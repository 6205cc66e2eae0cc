/**
 * @class   vtkShadowCasterPreparation
 * @brief   Repairs a surface for shadow casting and cuts it into clusters with conservative bounds.
 *
 * Meant for large CAD exports and simulation surfaces: duplicated vertices,
 * slivers, T-junctions, NaNs, non-manifold edges and self-intersections. The
 * output is a clean triangle mesh whose cells come in clusters (meshlets) of
 * at most MaximumClusterTriangles triangles, each with bounds a visibility
 * solver can cull with (Rendering/Core ssClusterBounds.h).
 *
 * Steps, in order (the counts of each go into field data and GetReport()):
 * 1. Polygons and triangle strips are triangulated (polygons by
 *    vtkPolygon::Triangulate, so concave ones too); vertices and lines are
 *    dropped (they cast no shadow). Points with a NaN or infinite coordinate
 *    are dropped with every cell that uses them.
 * 2. Points closer than WeldTolerance times the bounding-box diagonal are
 *    welded (vtkStaticPointLocator::MergePoints); triangles whose corners
 *    weld together are dropped.
 * 3. Each vertex-connected piece goes into OpenMesh's half-edge structure
 *    through CGAL's polygon-soup orientation, which cuts non-manifold edges and
 *    vertices apart instead of dropping faces; zero-area faces are removed by
 *    CGAL (collapses and flips, the surface stays closed); with
 *    SnapTJunctions, slivers (a corner within the weld tolerance of the
 *    opposite edge) are removed too, and border vertices within the weld
 *    tolerance of a border edge (T-junctions, and the cracks slivers leave)
 *    split that edge and the borders are stitched (CGAL,
 *    experimental::snap_borders and stitch_borders).
 * 4. Each edge-connected component (a "piece") is classified with CGAL
 *    Polygon Mesh Processing: closed or open, self-intersecting (closed pieces
 *    only), and outward-oriented; a closed, self-intersection-free piece that
 *    faces inwards is reversed (OrientClosedPieces). Normals come from OpenMesh.
 * 5. Triangles are clustered along a Morton curve of their centroids, closed
 *    outward pieces apart from the rest and by their normal's dominant axis,
 *    so that a closed cluster's normal cone is narrower than a hemisphere.
 *    Each cluster gets its AABB, a tight oriented box (OrientedBoxes: by
 *    default the mean normal and CGAL::min_rectangle_2 in its plane, or
 *    CGAL::oriented_bounding_box; extents refitted to hold every vertex) and
 *    a normal cone.
 *
 * Output cells are triangles ordered by cluster: cluster c is the cells
 * [ClusterRange(c,0), ClusterRange(c,0) + ClusterRange(c,1)).
 *
 * Cell data: `Normals` (unit face normals, float), `PieceId`, `ClusterId`,
 * `ClosedOutward` (1 when the triangle's piece is closed, manifold, free of
 * self-intersections and oriented outwards), `InputCellId` (the input cell it
 * came from) and the input's cell data.
 * Point data: `Normals` (unit, smooth across the welded mesh), `InputPointId`
 * (-1 for a point made by T-junction snapping; its other arrays are zero)
 * and the input's point data. Point coordinates keep the input's precision.
 *
 * Field data, one tuple per cluster:
 * - `ClusterRange` (vtkIdType, 2): first cell, number of cells;
 * - `ClusterAABB` (double, 6): xmin, xmax, ymin, ymax, zmin, zmax;
 * - `ClusterOBB` (double, 15): centre, axis 0, axis 1, axis 2 (unit,
 *   right-handed), half extents along the three axes;
 * - `ClusterNormalCone` (double, 4): unit axis and the cosine of the half
 *   angle; a cosine of -1 means no bound (never cull);
 * - `ClusterClosedOutward` (unsigned char): all its triangles are ClosedOutward;
 * - `ClusterPieceBounds` (double, 6): bounds of the pieces its triangles belong to.
 * Field data, one tuple each (the report): `InputCells`, `InputPoints`,
 * `NonFinitePoints`, `NonFiniteCells`, `DroppedVertsAndLines`,
 * `TriangulatedPolygons`, `TriangulatedStrips`, `WeldedPoints`,
 * `CollapsedTriangles`, `DegenerateTriangles`, `NonManifoldEdges`,
 * `NonManifoldVertices`, `FlippedForConsistency`, `TJunctionsSnapped`,
 * `Pieces`, `ClosedPieces`, `OpenPieces`, `SelfIntersectingPieces`,
 * `ReorientedPieces`, `ClosedOutwardPieces`, `Clusters`, `OutputTriangles`,
 * and `WeldToleranceAbsolute` (double).
 *
 * Progress events are fired through every stage; AbortExecute stops between
 * batches of pieces and clusters (the output is then empty).
 */
#ifndef vtkShadowCasterPreparation_h
#define vtkShadowCasterPreparation_h

#include "SoftShadowsFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <string>

class SOFTSHADOWSFILTERS_EXPORT vtkShadowCasterPreparation : public vtkPolyDataAlgorithm
{
public:
  static vtkShadowCasterPreparation* New();
  vtkTypeMacro(vtkShadowCasterPreparation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Weld and T-junction tolerance as a fraction of the diagonal of the
   * input's (finite) bounds. Default 1e-6; 0 welds only identical points and
   * snaps no T-junctions.
   */
  vtkSetClampMacro(WeldTolerance, double, 0.0, 0.01);
  vtkGetMacro(WeldTolerance, double);
  ///@}

  ///@{
  /**
   * Snap border vertices onto border edges within the weld tolerance and stitch
   * the borders (repairs T-junctions). Default on.
   */
  vtkSetMacro(SnapTJunctions, bool);
  vtkGetMacro(SnapTJunctions, bool);
  vtkBooleanMacro(SnapTJunctions, bool);
  ///@}

  ///@{
  /**
   * Test closed pieces for self-intersections (CGAL). Off saves time on huge
   * meshes, but then no piece is marked ClosedOutward (a self-intersecting
   * piece could have regions where culling back faces is wrong). Default on.
   */
  vtkSetMacro(CheckSelfIntersections, bool);
  vtkGetMacro(CheckSelfIntersections, bool);
  vtkBooleanMacro(CheckSelfIntersections, bool);
  ///@}

  ///@{
  /**
   * Reverse closed, self-intersection-free pieces that face inwards. Default on.
   */
  vtkSetMacro(OrientClosedPieces, bool);
  vtkGetMacro(OrientClosedPieces, bool);
  vtkBooleanMacro(OrientClosedPieces, bool);
  ///@}

  ///@{
  /**
   * Largest number of triangles in a cluster. Default 256.
   */
  vtkSetClampMacro(MaximumClusterTriangles, int, 1, 1 << 20);
  vtkGetMacro(MaximumClusterTriangles, int);
  ///@}

  enum
  {
    BOXES_AXIS_ALIGNED = 0, ///< the oriented box is the AABB
    BOXES_PLANE = 1,        ///< mean normal + CGAL::min_rectangle_2 (default)
    BOXES_OPTIMAL = 2       ///< CGAL::oriented_bounding_box (slow)
  };

  ///@{
  /**
   * How each cluster's oriented box is fitted. BOXES_PLANE (default): one
   * axis along the cluster's mean face normal (the least-squares plane's
   * normal when the normals cancel), the others along the smallest rectangle
   * holding the points projected onto that plane (CGAL::min_rectangle_2);
   * the AABB instead when it is smaller. BOXES_OPTIMAL: the axes of
   * CGAL::oriented_bounding_box, the smallest box (or the AABB when CGAL's
   * search ends larger), at tens of milliseconds per cluster. In every case
   * the extents are refitted to hold every vertex.
   */
  vtkSetClampMacro(OrientedBoxes, int, BOXES_AXIS_ALIGNED, BOXES_OPTIMAL);
  vtkGetMacro(OrientedBoxes, int);
  ///@}

  /**
   * What the last run did, one "name: value" per line (the field-data counts
   * and the time of each stage in milliseconds).
   */
  const char* GetReport() { return this->Report.c_str(); }

  /**
   * The report as JSON (counts and stage times).
   */
  const char* GetReportJSON() { return this->ReportJSON.c_str(); }

protected:
  vtkShadowCasterPreparation();
  ~vtkShadowCasterPreparation() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double WeldTolerance = 1e-6;
  bool SnapTJunctions = true;
  bool CheckSelfIntersections = true;
  bool OrientClosedPieces = true;
  int MaximumClusterTriangles = 256;
  int OrientedBoxes = BOXES_PLANE;
  std::string Report;
  std::string ReportJSON;

private:
  vtkShadowCasterPreparation(const vtkShadowCasterPreparation&) = delete;
  void operator=(const vtkShadowCasterPreparation&) = delete;
};

#endif
