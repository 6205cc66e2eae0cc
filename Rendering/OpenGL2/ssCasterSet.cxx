#include "ssCasterSet.h"

#include "ssEffectPlanner.h"
#include "ssTriangleSet.h"
#include "ssVisibleBlocks.h"

#include "vtkSoftShadowPass.h"

#include "ssCasterFS.h"
#include "ssCasterVS.h"

#include "vtkActor.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositePolyDataMapper2.h"
#include "vtkMapper.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkOpenGLBufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLVertexArrayObject.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkTexture.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkAbstractVolumeMapper.h"
#include "vtkVolume.h"
#include "vtkVolumeCollection.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ss
{
namespace
{
std::uint64_t MatrixHash(vtkMatrix4x4* m)
{
  // FNV-1a over the 16 doubles
  std::uint64_t h = 1469598103934665603ull;
  const auto* bytes = reinterpret_cast<const unsigned char*>(m->GetData());
  for (std::size_t i = 0; i < 16 * sizeof(double); ++i)
  {
    h = (h ^ bytes[i]) * 1099511628211ull;
  }
  return h;
}

// A Points or Wireframe representation is drawn see-through: it casts no
// shadow (paraview.md), rather than the solid shadow of the surface it shows
// only the points or edges of. An actor whose opacity is not a number is not
// drawn, so it casts nothing either.
// (an opacity of 0 draws nothing, and casts nothing in any method: until stop
// 51 the map methods, which take translucent casters as opaque, drew an
// invisible object's full shadow while GEARS drew none)
bool CastsAsSurface(vtkActor* actor)
{
  return vtkSoftShadowPass::GetCastsShadows(actor) && actor->GetProperty()->GetRepresentation() == VTK_SURFACE &&
    std::isfinite(actor->GetProperty()->GetOpacity()) && actor->GetProperty()->GetOpacity() > 0.0;
}

bool Finite3(const double p[3])
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// The world bounds (matrix m) of the finite points of what `mapper` draws;
// false when there are none.
bool FiniteBounds(vtkMapper* mapper, vtkMatrix4x4* m, double b[6])
{
  vtkMath::UninitializeBounds(b);
  bool any = false;
  ss::ForEachVisibleLeaf(mapper, mapper->GetInputDataObject(0, 0), [&](vtkDataSet* ds) {
    double p[4] = { 0.0, 0.0, 0.0, 1.0 }, w[4];
    for (vtkIdType i = 0; i < ds->GetNumberOfPoints(); ++i)
    {
      ds->GetPoint(i, p);
      m->MultiplyPoint(p, w);
      if (!Finite3(w))
      {
        continue;
      }
      for (int a = 0; a < 3; ++a)
      {
        b[2 * a] = any ? std::min(b[2 * a], w[a]) : w[a];
        b[2 * a + 1] = any ? std::max(b[2 * a + 1], w[a]) : w[a];
      }
      any = true;
    }
  });
  return any;
}

// What a caster's triangles carry besides their positions.
struct Appearance
{
  float opacity = 1.0f;
  glm::vec3 color{ 1.0f };
  int texture = -1; ///< index in CasterSet::AlphaTextures
};

struct Attributes
{
  std::vector<float> opacity, color, tcoords;
  std::vector<int> texture;
};

// The texture of `actor` when its image has an alpha channel with some
// alpha < 1 (RGBA or luminance-alpha unsigned chars): such a caster is
// translucent where its texture is.
vtkTexture* AlphaTexture(vtkActor* actor)
{
  vtkTexture* tex = actor->GetTexture();
  auto* img = tex ? vtkImageData::SafeDownCast(tex->GetInput()) : nullptr;
  if (img && tex->GetInputAlgorithm())
  {
    tex->GetInputAlgorithm()->Update();
    img = vtkImageData::SafeDownCast(tex->GetInput());
  }
  auto* rgba = img ? vtkUnsignedCharArray::SafeDownCast(img->GetPointData()->GetScalars()) : nullptr;
  const int nc = rgba ? rgba->GetNumberOfComponents() : 0;
  if (nc != 2 && nc != 4)
  {
    return nullptr;
  }
  for (vtkIdType i = 0; i < rgba->GetNumberOfTuples(); ++i)
  {
    if (rgba->GetValue(i * nc + nc - 1) < 255)
    {
      return tex;
    }
  }
  return nullptr;
}

void AppendPolyData(vtkPolyData* pd, vtkMatrix4x4* m, const Appearance& look, std::vector<glm::dvec3>& tris,
  Attributes& attr, std::size_t& skipped)
{
  vtkPoints* pts = pd->GetPoints();
  if (!pts || pts->GetNumberOfPoints() == 0)
  {
    return;
  }
  const vtkIdType np = pts->GetNumberOfPoints();
  std::vector<glm::dvec3> world(static_cast<std::size_t>(np));
  std::vector<char> finite(static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i)
  {
    double p[3];
    pts->GetPoint(i, p);
    double in[4] = { p[0], p[1], p[2], 1.0 }, out[4];
    m->MultiplyPoint(in, out);
    const double w = (out[3] != 0.0) ? out[3] : 1.0;
    world[i] = glm::dvec3(out[0] / w, out[1] / w, out[2] / w);
    finite[i] = std::isfinite(world[i].x) && std::isfinite(world[i].y) && std::isfinite(world[i].z);
  }
  vtkDataArray* tc = look.texture >= 0 ? pd->GetPointData()->GetTCoords() : nullptr;
  auto emit = [&](vtkIdType a, vtkIdType b, vtkIdType c) {
    if (a < 0 || b < 0 || c < 0 || a >= np || b >= np || c >= np || !finite[a] || !finite[b] || !finite[c])
    {
      ++skipped;
      return;
    }
    const glm::dvec3 e = glm::cross(world[b] - world[a], world[c] - world[a]);
    if (!(glm::dot(e, e) > 0.0))
    {
      ++skipped; // zero-area triangles cast nothing
      return;
    }
    tris.push_back(world[a]);
    tris.push_back(world[b]);
    tris.push_back(world[c]);
    attr.opacity.push_back(look.opacity);
    attr.color.insert(attr.color.end(), { look.color.x, look.color.y, look.color.z });
    const bool textured = tc && tc->GetNumberOfComponents() >= 2;
    attr.texture.push_back(textured ? look.texture : -1);
    for (vtkIdType v : { a, b, c })
    {
      attr.tcoords.push_back(textured ? static_cast<float>(tc->GetComponent(v, 0)) : 0.0f);
      attr.tcoords.push_back(textured ? static_cast<float>(tc->GetComponent(v, 1)) : 0.0f);
    }
  };
  auto polys = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    polys->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      emit(ids[0], ids[k], ids[k + 1]);
    }
  }
  auto strips = vtk::TakeSmartPointer(pd->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k + 2 < n; ++k)
    {
      if (k % 2 == 0)
      {
        emit(ids[k], ids[k + 1], ids[k + 2]);
      }
      else
      {
        emit(ids[k + 1], ids[k], ids[k + 2]);
      }
    }
  }
}

// Leaves of a prop (assemblies included) with their world matrices.
template <typename F>
void ForEachActor(vtkRenderer* ren, F&& f)
{
  vtkSoftShadowPass::ForEachVisibleActor(ren, f);
}

// The polydata a mapper draws: its input, or the input's visible blocks
// (ss::ForEachVisibleLeaf: a block hidden in ParaView casts nothing).
template <typename F>
void ForEachPolyData(vtkMapper* mapper, F&& f)
{
  ss::ForEachVisibleLeaf(mapper, mapper->GetInputDataObject(0, 0), [&](vtkDataSet* ds) {
    if (auto* pd = vtkPolyData::SafeDownCast(ds))
    {
      f(pd);
    }
  });
}
}

CasterSet::CasterSet() = default;
CasterSet::~CasterSet() = default;

void CasterSet::Update(vtkRenderer* ren, vtkObject* reporter)
{
  std::vector<CasterKey> keys;
  this->Receivers = Box{};
  this->ReceiverProps = 0;
  ForEachActor(ren, [&](vtkActor* actor, vtkMatrix4x4* m) {
    vtkMapper* mapper = actor->GetMapper();
    if (vtkSoftShadowPass::GetReceivesShadows(actor))
    {
      double b[6];
      actor->GetBounds(b);
      if (vtkMath::AreBoundsInitialized(b) && Finite3(b) && Finite3(b + 3))
      {
        this->Receivers.Add(glm::dvec3(b[0], b[2], b[4]));
        this->Receivers.Add(glm::dvec3(b[1], b[3], b[5]));
        ++this->ReceiverProps;
      }
      else if (mapper && FiniteBounds(mapper, m, b))
      {
        // a vertex at +-inf makes VTK's bounds infinite (NaN ones it skips):
        // the finite points' bounds instead. Until stop 51 such a mesh was no
        // receiver at all, and the frame had no shadows (the plan said "no
        // shadow receivers").
        this->Receivers.Add(glm::dvec3(b[0], b[2], b[4]));
        this->Receivers.Add(glm::dvec3(b[1], b[3], b[5]));
        ++this->ReceiverProps;
      }
    }
    if (!CastsAsSurface(actor))
    {
      return;
    }
    mapper->Update();
    vtkDataObject* data = mapper->GetInputDataObject(0, 0);
    vtkMTimeType look = std::max(mapper->GetMTime(), actor->GetProperty()->GetMTime());
    if (auto* composite = vtkCompositePolyDataMapper2::SafeDownCast(mapper))
    {
      // (block visibility: ForEachPolyData)
      vtkCompositeDataDisplayAttributes* cda = composite->GetCompositeDataDisplayAttributes();
      look = std::max(look, cda ? cda->GetMTime() : 0);
    }
    if (vtkTexture* tex = actor->GetTexture())
    {
      look = std::max({ look, tex->GetMTime(), tex->GetInput() ? tex->GetInput()->GetMTime() : 0 });
    }
    keys.emplace_back(actor, data, data ? data->GetMTime() : 0, MatrixHash(m), look);
  });
  this->UpdateVolumes(ren);
  if (keys == this->Keys)
  {
    return;
  }
  std::vector<glm::dvec3> tris;
  Attributes attr;
  std::vector<vtkTexture*> textures;
  std::size_t skipped = 0;
  bool translucent = false;
  Box translucentBounds;
  std::string translucentWhy;
  std::vector<PreparedBlock> prepared;
  std::string preparedNote;
  std::vector<std::uint32_t> actorOf;
  std::vector<char> actorAffine;
  std::size_t nanOpacity = 0;
  ForEachActor(ren, [&](vtkActor* actor, vtkMatrix4x4* m) {
    if (!CastsAsSurface(actor))
    {
      nanOpacity += vtkSoftShadowPass::GetCastsShadows(actor) && !std::isfinite(actor->GetProperty()->GetOpacity());
      return;
    }
    Appearance look;
    look.opacity = static_cast<float>(actor->GetProperty()->GetOpacity());
    double rgb[3];
    actor->GetProperty()->GetColor(rgb);
    look.color = glm::vec3(rgb[0], rgb[1], rgb[2]);
    if (vtkTexture* tex = AlphaTexture(actor))
    {
      const auto it = std::find(textures.begin(), textures.end(), tex);
      look.texture = static_cast<int>(it - textures.begin());
      if (it == textures.end())
      {
        textures.push_back(tex);
      }
    }
    const std::size_t first = tris.size();
    ForEachPolyData(actor->GetMapper(), [&](vtkPolyData* pd) {
      const std::size_t before = tris.size() / 3, skippedBefore = skipped;
      AppendPolyData(pd, m, look, tris, attr, skipped);
      if (HasClusterTable(pd))
      {
        // a vtkShadowCasterPreparation output: its cells must be the
        // triangles just appended, one each, none skipped
        PreparedBlock block;
        std::string why;
        const std::size_t count = tris.size() / 3 - before;
        if (pd->GetNumberOfCells() != pd->GetNumberOfPolys() || pd->GetNumberOfStrips() != 0 ||
          skipped != skippedBefore || count != static_cast<std::size_t>(pd->GetNumberOfCells()))
        {
          why = "its cells are not the triangles it draws (not one triangle per cell, or triangles skipped)";
        }
        else if (ReadClusterTable(pd, block.table, why, true))
        {
          block.first = before;
          block.count = count;
          std::copy_n(m->GetData(), 16, block.m);
          block.det = m->Determinant();
          prepared.push_back(std::move(block));
          why.clear();
        }
        if (!why.empty() && preparedNote.empty())
        {
          preparedNote = "a caster's cluster table was not used: " + why;
        }
      }
    });
    actorOf.resize(tris.size() / 3, static_cast<std::uint32_t>(actorAffine.size()));
    actorAffine.push_back(MayClosePieces(m->GetData()));
    const bool textured = std::any_of(attr.texture.begin() + static_cast<std::ptrdiff_t>(first / 3),
      attr.texture.end(), [](int t) { return t >= 0; });
    if ((look.opacity < 1.0f || textured) && tris.size() > first)
    {
      const char* why = look.opacity < 1.0f ? "opacity < 1" : "an RGBA texture";
      if (translucentWhy.find(why) == std::string::npos)
      {
        translucentWhy += (translucentWhy.empty() ? "" : ", ") + std::string(why);
      }
      translucent = true;
      for (std::size_t i = first; i < tris.size(); ++i)
      {
        translucentBounds.Add(tris[i]);
      }
    }
  });
  if (nanOpacity > 0)
  {
    vtkWarningWithObjectMacro(reporter, "Caster set: " << nanOpacity
      << " object(s) with an opacity that is not a number: not drawn, so they cast no shadow.");
  }
  if (skipped > 0 && skipped != this->Skipped)
  {
    vtkWarningWithObjectMacro(reporter, "Caster set: skipped " << skipped << " zero-area, degenerate or non-finite triangles.");
  }
  this->Skipped = skipped;
  this->Translucent = translucent;
  this->Bounds = Box{};
  for (const auto& p : tris)
  {
    this->Bounds.Add(p);
  }
  // the float origin at the bulk of the casters, not at their bounds' centre:
  // one stray triangle 1e5 away put it 5e4 out, and the scene's vertices on a
  // 0.004 grid (issue 17; ssTriangleSet.h)
  const TriangleBulk bulk = this->Bounds.Empty() ? TriangleBulk{} : BulkOfTriangles(tris);
  this->Origin = bulk.center;
  this->BulkScale = bulk.scale;
  this->BulkBounds = Box{};
  if (!this->Bounds.Empty())
  {
    this->BulkBounds.Add(bulk.lo);
    this->BulkBounds.Add(bulk.hi);
  }
  this->Triangles.resize(tris.size() * 3);
  for (std::size_t i = 0; i < tris.size(); ++i)
  {
    const glm::dvec3 r = tris[i] - this->Origin;
    this->Triangles[3 * i + 0] = static_cast<float>(r.x);
    this->Triangles[3 * i + 1] = static_cast<float>(r.y);
    this->Triangles[3 * i + 2] = static_cast<float>(r.z);
  }
  this->Opacity = std::move(attr.opacity);
  this->Color = std::move(attr.color);
  const bool anyTexture = std::any_of(attr.texture.begin(), attr.texture.end(), [](int t) { return t >= 0; });
  this->TCoords = anyTexture ? std::move(attr.tcoords) : std::vector<float>();
  this->TextureIndex = anyTexture ? std::move(attr.texture) : std::vector<int>();
  this->AlphaTextures = anyTexture ? textures : std::vector<vtkTexture*>();
  this->TranslucentBounds = translucentBounds;
  this->TranslucentWhy = translucentWhy;
  this->ActorOf = std::move(actorOf);
  this->ActorAffine = std::move(actorAffine);
  this->Keys = keys;
  if (!preparedNote.empty() && preparedNote != this->PreparedNote)
  {
    vtkWarningWithObjectMacro(reporter, "Caster set: " << preparedNote << "; its triangles get Morton clusters.");
  }
  this->PreparedNote = preparedNote;
  this->SetPrepared(std::move(prepared));
  this->Uploaded = false;
  ++this->Version;
}

void CasterSet::SetPrepared(std::vector<PreparedBlock> prepared)
{
  this->Prepared = std::move(prepared);
  this->PreparedTriangles = 0;
  this->PreparedClusters = 0;
  this->Piece.clear();
  this->PieceOrientation.clear();
  if (this->Prepared.empty())
  {
    return;
  }
  // GEARS' pieces: piece 0 holds every triangle that is not prepared (open);
  // each block's pieces follow. A closed outward piece stays outward under a
  // transform with a positive determinant and turns inward under a mirror
  // (the vertex order is kept); a projective matrix leaves it open.
  this->Piece.assign(this->NumberOfTriangles(), 0);
  this->PieceOrientation.assign(1, 0);
  for (const PreparedBlock& b : this->Prepared)
  {
    this->PreparedTriangles += b.count;
    this->PreparedClusters += b.table.ranges.size();
    if (b.table.piece.size() != b.count)
    {
      continue;
    }
    const std::uint32_t base = static_cast<std::uint32_t>(this->PieceOrientation.size());
    const std::uint32_t pieces = 1 + *std::max_element(b.table.piece.begin(), b.table.piece.end());
    const bool affine = MayClosePieces(b.m);
    const std::int8_t closed = !affine || !(b.det != 0.0) ? 0 : (b.det > 0.0 ? 1 : -1);
    this->PieceOrientation.resize(base + pieces, closed);
    for (std::size_t i = 0; i < b.count; ++i)
    {
      this->Piece[b.first + i] = base + b.table.piece[i];
      if (!b.table.closedOutward[i])
      {
        this->PieceOrientation[base + b.table.piece[i]] = 0;
      }
    }
  }
}

GearsPieces CasterSet::FindPieces(
  const std::vector<glm::dvec3>& world, GearsPieceCounts& counts, const SolveProgress& progress) const
{
  // prepared triangles keep their tables' pieces (SetPrepared); piece 0, the
  // open piece of all the others, is split per actor
  const std::size_t n = this->NumberOfTriangles();
  GearsPieces out;
  out.piece = this->Piece.empty() ? std::vector<std::uint32_t>(n, 0) : this->Piece;
  out.orientation = this->PieceOrientation.empty() ? std::vector<std::int8_t>(1, 0) : this->PieceOrientation;
  std::vector<std::vector<std::uint32_t>> blocks(this->ActorAffine.size());
  for (std::size_t t = 0; t < n && t < this->ActorOf.size(); ++t)
  {
    if (out.piece[t] == 0)
    {
      blocks[this->ActorOf[t]].push_back(static_cast<std::uint32_t>(t));
    }
  }
  counts = GearsPieceCounts{};
  std::size_t total = 0, done = 0;
  for (const auto& b : blocks)
  {
    total += b.size();
  }
  for (std::size_t a = 0; a < blocks.size(); ++a)
  {
    if (!blocks[a].empty())
    {
      const double from = static_cast<double>(done) / total,
                   to = static_cast<double>(done + blocks[a].size()) / total;
      const GearsPieceCounts c =
        FindGearsPieces(world, blocks[a], this->ActorAffine[a] != 0, out, SubProgress(progress, from, to));
      if (c.aborted)
      {
        counts.aborted = true;
        return out;
      }
      done += blocks[a].size();
      counts.pieces += c.pieces;
      counts.closedPieces += c.closedPieces;
      counts.closedTriangles += c.closedTriangles;
    }
  }
  return out;
}

const char* CasterSet::ClusterSource() const
{
  if (!this->HasClusters())
  {
    return "none";
  }
  return this->Clusters.shapes.empty() ? "morton" : "prepared";
}

std::string CasterSet::ClusterStatsJSON(const ClusterCounts& counts) const
{
  std::ostringstream o;
  o.precision(15);
  o << "{\"source\": \"" << this->ClusterSource() << "\", \"clusters\": "
    << (this->HasClusters() ? this->Clusters.Clusters() : 0) << ", \"prepared_clusters\": " << this->PreparedClusters
    << ", \"drawn\": " << counts.drawn << ", \"culled\": " << counts.culled << "}";
  return o.str();
}

std::string CasterSet::TranslucentInView(const LightFrame& light, const glm::dvec3& origin) const
{
  auto relative = [&](const Box& b) {
    Box r;
    if (!b.Empty())
    {
      r.Add(b.min - origin);
      r.Add(b.max - origin);
    }
    return r;
  };
  const Box receivers = relative(this->Receivers);
  std::string why;
  if (this->Translucent && CastersMayShadow(light, relative(this->TranslucentBounds), receivers))
  {
    why = this->TranslucentWhy;
  }
  if (!this->Volumes.empty() && CastersMayShadow(light, relative(this->VolumeBounds), receivers))
  {
    why += (why.empty() ? "" : ", ") + std::string(this->Volumes.size() > 1 ? "volumes" : "a volume");
  }
  return why;
}

void CasterSet::UpdateVolumes(vtkRenderer* ren)
{
  std::vector<CasterKey> keys;
  std::vector<vtkVolume*> volumes;
  Box bounds;
  vtkVolumeCollection* vc = ren->GetVolumes();
  vtkCollectionSimpleIterator it;
  vc->InitTraversal(it);
  while (vtkVolume* vol = vc->GetNextVolume(it))
  {
    if (!vol->GetVisibility() || !vol->GetMapper() || !vtkSoftShadowPass::GetCastsShadows(vol))
    {
      continue;
    }
    vol->GetMapper()->Update();
    vtkDataObject* data = vol->GetMapper()->GetInputDataObject(0, 0);
    keys.emplace_back(vol, data, data ? data->GetMTime() : 0, MatrixHash(vol->GetMatrix()),
      std::max(vol->GetMapper()->GetMTime(), vol->GetProperty() ? vol->GetProperty()->GetMTime() : 0));
    volumes.push_back(vol);
    double b[6];
    vol->GetBounds(b);
    if (vtkMath::AreBoundsInitialized(b) && Finite3(b) && Finite3(b + 3))
    {
      bounds.Add(glm::dvec3(b[0], b[2], b[4]));
      bounds.Add(glm::dvec3(b[1], b[3], b[5]));
    }
  }
  if (keys != this->VolumeKeys)
  {
    this->VolumeKeys = keys;
    ++this->VolumeVersion;
  }
  this->Volumes = volumes;
  this->VolumeBounds = bounds;
}

std::vector<glm::dvec3> CasterSet::WorldVertices() const
{
  std::vector<glm::dvec3> verts(this->Triangles.size() / 3);
  for (std::size_t i = 0; i < verts.size(); ++i)
  {
    verts[i] =
      this->Origin + glm::dvec3(this->Triangles[3 * i], this->Triangles[3 * i + 1], this->Triangles[3 * i + 2]);
  }
  return verts;
}

void CasterSet::EnsureClusters()
{
  if (this->HasClusters())
  {
    return;
  }
  const std::size_t n = this->NumberOfTriangles();
  std::vector<glm::dvec3> v(3 * n);
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    v[i] = glm::dvec3(this->Triangles[3 * i], this->Triangles[3 * i + 1], this->Triangles[3 * i + 2]);
  }
  if (this->Prepared.empty())
  {
    this->Clusters = ClusterTriangles(v, 1024);
  }
  else
  {
    this->Clusters = this->PreparedClusterOrder(v);
  }
  std::vector<float> tri(this->Triangles.size()), opacity(n, 1.0f), color(3 * n, 1.0f),
    tcoords(this->TCoords.empty() ? 0 : 6 * n);
  std::vector<int> texture(this->TextureIndex.empty() ? 0 : n);
  for (std::size_t t = 0; t < n; ++t)
  {
    const std::size_t from = this->Clusters.order[t];
    std::copy_n(&this->Triangles[9 * from], 9, &tri[9 * t]);
    opacity[t] = from < this->Opacity.size() ? this->Opacity[from] : 1.0f;
    if (3 * from + 2 < this->Color.size())
    {
      std::copy_n(&this->Color[3 * from], 3, &color[3 * t]);
    }
    if (!tcoords.empty())
    {
      std::copy_n(&this->TCoords[6 * from], 6, &tcoords[6 * t]);
      texture[t] = this->TextureIndex[from];
    }
  }
  if (!this->Piece.empty())
  {
    std::vector<std::uint32_t> piece(n);
    for (std::size_t t = 0; t < n; ++t)
    {
      piece[t] = this->Piece[this->Clusters.order[t]];
    }
    this->Piece = std::move(piece);
  }
  std::vector<std::uint32_t> actorOf(n);
  for (std::size_t t = 0; t < n; ++t)
  {
    actorOf[t] = this->ActorOf[this->Clusters.order[t]];
  }
  this->ActorOf = std::move(actorOf);
  // the blocks' triangles now come first, in the order of Prepared
  std::size_t next = 0;
  for (PreparedBlock& b : this->Prepared)
  {
    b.first = next;
    next += b.count;
  }
  this->Triangles = std::move(tri);
  this->Opacity = std::move(opacity);
  this->Color = std::move(color);
  this->TCoords = std::move(tcoords);
  this->TextureIndex = std::move(texture);
  this->ClusterVersion = this->Version;
  this->Uploaded = false;
}

TriangleClusters CasterSet::PreparedClusterOrder(const std::vector<glm::dvec3>& v) const
{
  // the prepared blocks' clusters first (their triangles are already in
  // cluster order), then Morton clusters of the other triangles
  const std::size_t n = v.size() / 3;
  TriangleClusters c;
  c.order.reserve(n);
  std::vector<char> taken(n, 0);
  for (const PreparedBlock& b : this->Prepared)
  {
    const bool affine = MayClosePieces(b.m);
    const auto linear = [&](const glm::dvec3& a) {
      return glm::dvec3(b.m[0] * a.x + b.m[1] * a.y + b.m[2] * a.z, b.m[4] * a.x + b.m[5] * a.y + b.m[6] * a.z,
        b.m[8] * a.x + b.m[9] * a.y + b.m[10] * a.z);
    };
    const auto point = [&](const glm::dvec3& p) {
      return linear(p) + glm::dvec3(b.m[3], b.m[7], b.m[11]) - this->Origin;
    };
    // the bounds of what is drawn (float, relative to Origin), with the
    // table's box axes carried through the matrix (FitOrientedBox makes them
    // orthonormal again and fits the extents to the points)
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    std::vector<std::array<glm::dvec3, 3>> axes;
    for (std::size_t k = 0; k < b.table.ranges.size(); ++k)
    {
      ranges.emplace_back(b.first + b.table.ranges[k].first, b.table.ranges[k].second);
      const OrientedBox& o = b.table.bounds[k].obb;
      axes.push_back({ linear(o.axis[0]), linear(o.axis[1]), linear(o.axis[2]) });
    }
    std::vector<ClusterBounds> shapes = FitClusterBounds(v, ranges, axes);
    for (std::size_t k = 0; k < shapes.size(); ++k)
    {
      const ClusterBounds& in = b.table.bounds[k];
      ClusterBounds& out = shapes[k];
      out.closedOutward = in.closedOutward && affine && b.det > 0.0;
      if (!in.pieceBounds.Empty())
      {
        for (int q = 0; q < 8; ++q)
        {
          out.pieceBounds.Add(point(in.pieceBounds.Corner(q)));
        }
      }
      c.bounds.push_back(out.aabb);
      c.shapes.push_back(out);
    }
    for (const auto& [first, count] : b.table.ranges)
    {
      c.first.push_back(c.order.size());
      for (std::size_t i = 0; i < count; ++i)
      {
        c.order.push_back(b.first + first + i);
        taken[b.first + first + i] = 1;
      }
    }
  }
  std::vector<std::size_t> rest;
  std::vector<glm::dvec3> restVertices;
  for (std::size_t t = 0; t < n; ++t)
  {
    if (!taken[t])
    {
      rest.push_back(t);
      restVertices.insert(restVertices.end(), { v[3 * t], v[3 * t + 1], v[3 * t + 2] });
    }
  }
  const TriangleClusters morton = ClusterTriangles(restVertices, 1024);
  for (std::size_t k = 0; k < morton.Clusters(); ++k)
  {
    c.first.push_back(c.order.size() + morton.first[k]);
    c.bounds.push_back(morton.bounds[k]);
    ClusterBounds shape; // the AABB only (an empty oriented box leaves it to the AABB)
    shape.aabb = morton.bounds[k];
    c.shapes.push_back(shape);
  }
  for (std::size_t i : morton.order)
  {
    c.order.push_back(rest[i]);
  }
  c.first.push_back(c.order.size());
  return c;
}

vtkShaderProgram* CasterSet::ReadyProgram(vtkOpenGLRenderWindow* win, std::string& error)
{
  if (!this->VBO)
  {
    this->VBO = vtkSmartPointer<vtkOpenGLBufferObject>::New();
    this->VBO->SetType(vtkOpenGLBufferObject::ArrayBuffer);
    this->VAO = vtkSmartPointer<vtkOpenGLVertexArrayObject>::New();
  }
  this->Program = win->GetShaderCache()->ReadyShaderProgram(ssCasterVS, ssCasterFS, "");
  if (!this->Program)
  {
    error = "Could not build the caster shadow-map program.";
    return nullptr;
  }
  if (!this->Uploaded)
  {
    this->VBO->Upload(this->Triangles, vtkOpenGLBufferObject::ArrayBuffer);
    this->VAO->Bind();
    this->VAO->RemoveAttributeArray("vertexRel");
    if (!this->VAO->AddAttributeArray(this->Program, this->VBO, "vertexRel", 0, 3 * sizeof(float), VTK_FLOAT, 3, false))
    {
      error = "Could not bind the caster vertex buffer.";
    }
    this->VAO->Release();
    this->Uploaded = true;
    ++this->Uploads;
  }
  return this->Program;
}

vtkOpenGLBufferObject* CasterSet::GetVertexBuffer() const
{
  return this->VBO;
}

vtkOpenGLVertexArrayObject* CasterSet::GetVertexArray() const
{
  return this->VAO;
}

vtkShaderProgram* CasterSet::UseProgram(vtkOpenGLRenderWindow* win)
{
  win->GetShaderCache()->ReadyShaderProgram(this->Program);
  return this->Program;
}

void CasterSet::Draw(vtkShaderProgram* p, vtkOpenGLVertexArrayObject* vao, const ShadowView& v, const Rect& extent,
  const glm::dvec3& offset, const TriangleRanges* ranges) const
{
  p->SetUniform3f("casterOffset", glm::value_ptr(glm::vec3(offset)));
  p->SetUniform3f("viewOrigin", glm::value_ptr(glm::vec3(v.origin)));
  p->SetUniform3f("axisU", glm::value_ptr(glm::vec3(v.u)));
  p->SetUniform3f("axisV", glm::value_ptr(glm::vec3(v.v)));
  p->SetUniform3f("axisN", glm::value_ptr(glm::vec3(v.n)));
  const float e[4] = { static_cast<float>(extent.x0), static_cast<float>(extent.y0), static_cast<float>(extent.x1),
    static_cast<float>(extent.y1) };
  p->SetUniform4f("extent", e);
  p->SetUniformi("orthographic", v.orthographic ? 1 : 0);
  vao->Bind();
  if (!ranges)
  {
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(this->Triangles.size() / 3));
  }
  else if (!ranges->empty())
  {
    std::vector<GLint> first;
    std::vector<GLsizei> count;
    for (const auto& r : *ranges)
    {
      first.push_back(static_cast<GLint>(3 * r.first));
      count.push_back(static_cast<GLsizei>(3 * r.second));
    }
    glMultiDrawArrays(GL_TRIANGLES, first.data(), count.data(), static_cast<GLsizei>(first.size()));
  }
  vao->Release();
}

long long CasterSet::Bytes() const
{
  return this->Uploaded ? static_cast<long long>(this->Triangles.size()) * 4 : 0;
}

int CasterSet::CountGraphicsResources() const
{
  return (this->VBO && this->VBO->GetHandle() != 0) ? 1 : 0;
}

void CasterSet::ReleaseGraphicsResources()
{
  if (this->VAO)
  {
    this->VAO->ReleaseGraphicsResources();
    this->VAO = nullptr;
  }
  if (this->VBO)
  {
    this->VBO->ReleaseGraphicsResources();
    this->VBO = nullptr;
  }
  this->Program = nullptr;
  this->Uploaded = false;
}
}
