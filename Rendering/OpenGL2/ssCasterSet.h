// The caster set (DESIGN.md "one data flow"): the world-space triangles of
// every visible shadow-casting actor, rebuilt only when an actor, its data,
// its transform or its property changed; their clusters for culling; their
// GPU copy and the small program that draws them into a light's view.
#ifndef ssCasterSet_h
#define ssCasterSet_h

#include "ssCasterClusters.h"
#include "ssClusterTable.h"
#include "ssGearsPieces.h"
#include "ssShadowView.h"

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

class vtkObject;
class vtkOpenGLBufferObject;
class vtkOpenGLRenderWindow;
class vtkOpenGLVertexArrayObject;
class vtkRenderer;
class vtkShaderProgram;
class vtkTexture;
class vtkVolume;

namespace ss
{
/// What the caster set was built from: rebuilt when any entry changes
/// (actor, data object, its MTime, a hash of the world matrix, the larger of
/// the mapper's and property's MTime). The transform enters by value:
/// assembly paths hand out fresh matrices (new MTimes) at every traversal,
/// which rebuilt the caster set every frame.
using CasterKey = std::tuple<void*, void*, vtkMTimeType, std::uint64_t, vtkMTimeType>;

/// Triangle ranges (first triangle, count) to draw.
using TriangleRanges = std::vector<std::pair<std::size_t, std::size_t>>;

class CasterSet
{
public:
  CasterSet();
  ~CasterSet();
  CasterSet(const CasterSet&) = delete;
  CasterSet& operator=(const CasterSet&) = delete;

  /// Walks the visible actors of `ren` (assemblies included): the bounds of
  /// the receivers every frame, the triangles of the casters when a key
  /// changed. Zero-area, degenerate and non-finite triangles are skipped
  /// (`reporter` warns once per new count).
  void Update(vtkRenderer* ren, vtkObject* reporter);

  // --- receivers (read every frame)
  Box Receivers;                 ///< absolute bounds of the receiving actors
  std::size_t ReceiverProps = 0; ///< how many there are

  // --- the triangles (rebuilt when Keys change)
  std::vector<CasterKey> Keys;
  std::vector<float> Triangles; ///< 9 floats per triangle, relative to Origin
  std::vector<float> Opacity;   ///< per triangle
  std::vector<float> Color;     ///< per triangle, RGB: the actor's colour (coloured shadows)
  /// Casters whose texture has an alpha channel (RGBA or LA with alpha < 1
  /// somewhere) and texture coordinates: per vertex (u, v) in TCoords (6
  /// floats a triangle, 0 for the others) and per triangle its index in
  /// AlphaTextures (-1: none). AVSM solvers multiply opacity by its alpha.
  std::vector<float> TCoords;
  std::vector<int> TextureIndex;
  std::vector<vtkTexture*> AlphaTextures;
  glm::dvec3 Origin{ 0.0 };     ///< world; the centre of the casters' bulk (ssTriangleSet.h BulkOfTriangles)
  double BulkScale = 0.0;       ///< the diagonal of that bulk (0: no casters)
  Box Bounds;                   ///< absolute
  /// absolute; the bulk's bounds (BulkOfTriangles: without stray triangles
  /// and needles to a lost vertex), what the light views are fitted to
  Box BulkBounds;
  bool Translucent = false;     ///< some caster has opacity < 1 or an alpha texture
  Box TranslucentBounds;        ///< absolute bounds of those casters' triangles
  std::string TranslucentWhy;   ///< what makes them translucent ("opacity < 1", "an RGBA texture")

  // --- volumes that cast shadows (vtkVolume props, visible, CastsShadows),
  // read every frame; what they cast is the AVSM solvers' business
  // (ssVolumeCasters)
  std::vector<vtkVolume*> Volumes;
  Box VolumeBounds;                ///< absolute
  unsigned long VolumeVersion = 0; ///< changes with a volume, its data, matrix or property
  std::size_t Skipped = 0;      ///< triangles left out by the last rebuild
  unsigned long Version = 0;    ///< counts rebuilds (EnsureClusters re-orders without a new version)

  std::size_t NumberOfTriangles() const { return this->Triangles.size() / 9; }
  /// What translucent casters (TranslucentWhy, "a volume") can shadow a
  /// receiver of `light` (its frame relative to `origin`), joined; empty: none.
  std::string TranslucentInView(const LightFrame& light, const glm::dvec3& origin) const;
  /// The triangles' vertices in world coordinates (double), 3 per triangle.
  std::vector<glm::dvec3> WorldVertices() const;

  // --- prepared casters: actors whose input is a vtkShadowCasterPreparation
  // output (its cluster table in field data, PieceId and ClosedOutward cell
  // arrays; ssClusterTable). Read when the caster set is rebuilt, i.e. when
  // the input's MTime changed.
  std::size_t PreparedTriangles = 0; ///< triangles of prepared casters
  std::size_t PreparedClusters = 0;  ///< their clusters (from the tables)
  std::string PreparedNote;          ///< why an input with a table was not used (empty: none)
  /// GEARS' closed pieces (GearsSolver::SetPieces), per triangle in the
  /// current order and per piece; empty without prepared casters. Triangles
  /// that are not prepared share one open piece.
  std::vector<std::uint32_t> Piece;
  std::vector<std::int8_t> PieceOrientation;
  /// Per triangle (current order) its actor: an index into ActorAffine,
  /// whose entry is 0 when the actor's matrix is projective.
  std::vector<std::uint32_t> ActorOf;
  std::vector<char> ActorAffine;
  /// GEARS' pieces for every triangle: the prepared ones' (Piece) and, for
  /// the other triangles, those ss::FindGearsPieces finds per actor in
  /// `world` (WorldVertices(), what GEARS is given), exact welds only.
  /// `counts` gets what was found (prepared pieces not included).
  /// `progress` (optional) gets the fraction done over all actors, weighted
  /// by their triangles; when it returns false the search stops, counts say
  /// `aborted` and the pieces returned must not be used.
  GearsPieces FindPieces(
    const std::vector<glm::dvec3>& world, GearsPieceCounts& counts, const SolveProgress& progress = {}) const;

  // --- clusters (tile culling, vtkSoftShadowPass::PVSMTileCulling)
  /// Orders the triangles into clusters when the set changed since the last
  /// call: prepared casters keep their table's clusters (bounds refitted on
  /// the drawn coordinates, with the table's box axes, closed flags and piece
  /// bounds: Clusters.shapes); the other triangles are cut into Morton
  /// clusters of at most 1024 (a few thousand on a 5M-triangle set: the
  /// per-tile test stays well under a millisecond). Only frames that cull need them, so
  /// this runs on their first frame after a change, not on every rebuild. The
  /// bounds come from the float positions the GPU draws. No solver depends on
  /// the order (maps are min-blended, GEARS and the reference take unions),
  /// so nothing else is rebuilt; the vertex buffer is re-uploaded.
  void EnsureClusters();
  /// Whether Clusters describe the current triangles.
  bool HasClusters() const { return this->ClusterVersion == this->Version; }
  TriangleClusters Clusters; ///< bounds relative to Origin
  /// "prepared" (some clusters from cluster tables), "morton", or "none"
  /// (EnsureClusters not run for the current set).
  const char* ClusterSource() const;
  /// {"source": ..., "clusters": n, "drawn": d, "culled": c} for a solver's stats.
  std::string ClusterStatsJSON(const ClusterCounts& counts) const;

  // --- GPU copy
  /// Uploads the triangles when they changed since the last upload and binds
  /// them to the caster program (ssCasterVS/FS); that program, or null with
  /// `error` set.
  vtkShaderProgram* ReadyProgram(vtkOpenGLRenderWindow* win, std::string& error);
  /// The caster program of the last ReadyProgram (made current again).
  vtkShaderProgram* UseProgram(vtkOpenGLRenderWindow* win);
  vtkOpenGLBufferObject* GetVertexBuffer() const;
  vtkOpenGLVertexArrayObject* GetVertexArray() const;
  /// Counts uploads: a program of its own that reads the vertex buffer
  /// re-binds it when this changed.
  unsigned long GetUploads() const { return this->Uploads; }

  /// Draws the triangles with `p` (whose vertex array is `vao`) as seen by
  /// `view` over its window `extent` (the whole view, or one PVSM tile).
  /// `offset` is Origin minus the frame origin. `ranges`, when given, draws
  /// only those triangles.
  void Draw(vtkShaderProgram* p, vtkOpenGLVertexArrayObject* vao, const ShadowView& view, const Rect& extent,
    const glm::dvec3& offset, const TriangleRanges* ranges = nullptr) const;

  long long Bytes() const;
  int CountGraphicsResources() const;
  void ReleaseGraphicsResources();

private:
  void UpdateVolumes(vtkRenderer* ren);
  /// A prepared caster's triangles [first, first + count) (one per cell) and
  /// its table; det: the determinant of its actor's matrix (a mirror turns
  /// outward pieces inward); pieceBase: its first piece in Piece.
  struct PreparedBlock
  {
    std::size_t first = 0, count = 0;
    ClusterTable table;
    double m[16];
    double det = 1.0;
  };
  std::vector<PreparedBlock> Prepared;
  void SetPrepared(std::vector<PreparedBlock> prepared);
  TriangleClusters PreparedClusterOrder(const std::vector<glm::dvec3>& vertices) const;
  std::vector<CasterKey> VolumeKeys;
  unsigned long ClusterVersion = 0;
  vtkSmartPointer<vtkOpenGLBufferObject> VBO;
  vtkSmartPointer<vtkOpenGLVertexArrayObject> VAO;
  vtkShaderProgram* Program = nullptr; ///< owned by the window's shader cache
  bool Uploaded = false;
  unsigned long Uploads = 0;
};
}

#endif
