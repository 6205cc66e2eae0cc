#include "ssCasterRepair.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/internal/Snapping/snap.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Face_filtered_graph.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <ctime>
#include <numeric>
#include <thread>

namespace ssf
{
namespace
{
namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Double-precision points and normals; status bits for CGAL's Euler
// operations, which delete elements.
struct MeshTraits : public OpenMesh::DefaultTraits
{
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  VertexAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;
using GT = boost::graph_traits<Mesh>;
using face_descriptor = GT::face_descriptor;
using vertex_descriptor = GT::vertex_descriptor;

// Plain union-find over point indices (pieces are vertex-connected sets).
struct DisjointSets
{
  std::vector<std::int64_t> parent;
  explicit DisjointSets(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), 0);
  }
  std::int64_t Find(std::int64_t x)
  {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void Unite(std::int64_t a, std::int64_t b)
  {
    a = Find(a);
    b = Find(b);
    if (a != b)
    {
      parent[std::max(a, b)] = std::min(a, b);
    }
  }
};

// Counts what CGAL's soup orientation cut apart and flipped. The orienter
// copies its visitor, so the counts live behind pointers.
struct OrientVisitor : public PMP::Default_orientation_visitor
{
  RepairStats* stats = nullptr;
  std::vector<std::pair<std::size_t, std::size_t>>* duplicates = nullptr;
  void non_manifold_edge(std::size_t, std::size_t, std::size_t) { ++stats->nonManifoldEdges; }
  void non_manifold_vertex(std::size_t, std::size_t) { ++stats->nonManifoldVertices; }
  void duplicated_vertex(std::size_t from, std::size_t to)
  {
    ++stats->duplicatedPoints;
    duplicates->emplace_back(from, to);
  }
  void polygon_orientation_reversed(std::size_t) { ++stats->flippedForConsistency; }
};

// A unit's OpenMesh mesh with the input cell of each face and the input
// point of each vertex.
struct UnitMesh
{
  Mesh mesh;
  OpenMesh::FPropHandleT<std::int64_t> cell;
  OpenMesh::VPropHandleT<std::int64_t> point;
  UnitMesh()
  {
    mesh.add_property(cell);
    mesh.add_property(point);
  }
};

// CGAL's snapping keeps bool vertex and halfedge properties, which OpenMesh
// stores as std::vector<bool> and CGAL's OpenMesh property maps cannot return
// by reference (a compile error in CGAL 5.5). So T-junctions are snapped on a
// CGAL::Surface_mesh copy of the unit, and the result is copied back.
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;

// Keeps the input cell of faces that snapping splits, and marks the vertices
// it creates. Surface_mesh appends new elements, so of the two faces of a
// split the newer has the larger index.
struct SnapVisitor : public PMP::internal::Snapping_default_visitor<SurfaceMesh>
{
  SurfaceMesh* mesh = nullptr;
  SurfaceMesh::Property_map<SurfaceMesh::Face_index, std::int64_t> cell;
  SurfaceMesh::Property_map<SurfaceMesh::Vertex_index, std::int64_t> point;

  template <typename Vertex, typename M>
  void after_vertex_edge_snap(const Vertex v, const M&)
  {
    point[v] = -1;
  }
  template <typename Halfedge, typename M>
  void after_split_face(const Halfedge h1, const Halfedge h2, const M&)
  {
    const auto f1 = mesh->face(h1), f2 = mesh->face(h2);
    if (f1 == SurfaceMesh::null_face() || f2 == SurfaceMesh::null_face())
    {
      return;
    }
    cell[std::max(f1, f2)] = cell[std::min(f1, f2)];
  }
};

// Snaps border vertices onto border edges within `tolerance` and stitches the
// borders. Returns the number of snaps; `unit` is replaced when there were any.
std::size_t SnapTJunctions(UnitMesh& unit, double tolerance)
{
  SurfaceMesh sm;
  auto cell = sm.add_property_map<SurfaceMesh::Face_index, std::int64_t>("f:cell", -1).first;
  auto point = sm.add_property_map<SurfaceMesh::Vertex_index, std::int64_t>("v:source", -1).first;
  {
    std::vector<std::pair<vertex_descriptor, SurfaceMesh::Vertex_index>> v2v;
    std::vector<std::pair<face_descriptor, SurfaceMesh::Face_index>> f2f;
    CGAL::copy_face_graph(unit.mesh, sm,
      CGAL::parameters::vertex_to_vertex_output_iterator(std::back_inserter(v2v))
        .face_to_face_output_iterator(std::back_inserter(f2f)));
    for (const auto& v : v2v)
    {
      point[v.second] = unit.mesh.property(unit.point, v.first);
    }
    for (const auto& f : f2f)
    {
      cell[f.second] = unit.mesh.property(unit.cell, f.first);
    }
  }
  SnapVisitor sv;
  sv.mesh = &sm;
  sv.cell = cell;
  sv.point = point;
  const std::size_t snapped = PMP::experimental::snap_borders(sm,
    CGAL::Constant_property_map<SurfaceMesh::Vertex_index, double>(tolerance),
    CGAL::parameters::visitor(std::ref(sv)));
  if (snapped == 0)
  {
    return 0;
  }
  PMP::stitch_borders(sm);
  sm.collect_garbage();
  UnitMesh back;
  std::vector<std::pair<SurfaceMesh::Vertex_index, vertex_descriptor>> v2v;
  std::vector<std::pair<SurfaceMesh::Face_index, face_descriptor>> f2f;
  CGAL::copy_face_graph(sm, back.mesh,
    CGAL::parameters::vertex_to_vertex_output_iterator(std::back_inserter(v2v))
      .face_to_face_output_iterator(std::back_inserter(f2f)));
  for (const auto& v : v2v)
  {
    back.mesh.property(back.point, v.second) = point[v.first];
  }
  for (const auto& f : f2f)
  {
    back.mesh.property(back.cell, f.second) = cell[f.first];
  }
  std::swap(unit, back);
  return snapped;
}

// CPU time of the calling thread (ms): under a loaded machine's time
// slicing, wall time per unit says more about the load than about the work.
double ThreadCpuMs()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

// Components with more faces than this test themselves for self-intersections
// on all cores.
constexpr std::size_t kParallelComponent = 200000;

// This thread's CPU milliseconds since `t`, and `t` moved to now.
double Lap(double& t)
{
  const double now = ThreadCpuMs();
  const double ms = now - t;
  t = now;
  return ms;
}

struct UnitResult
{
  std::vector<glm::dvec3> points;
  std::vector<std::int64_t> sourcePoint;
  std::vector<glm::dvec3> pointNormals;
  std::vector<std::array<std::int64_t, 3>> triangles; // local point indices
  std::vector<std::int64_t> sourceCell;
  std::vector<glm::dvec3> faceNormals;
  std::vector<std::int64_t> piece; // local piece index
  std::vector<PieceInfo> pieces;
  RepairStats stats;
};

glm::dvec3 Glm(const Mesh::Point& p)
{
  return { p[0], p[1], p[2] };
}

// Normal of a face from its corners, for the rare unit the mesh could not hold.
glm::dvec3 FaceNormal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double l = glm::length(n);
  return l > 0.0 && std::isfinite(l) ? n / l : glm::dvec3(0.0);
}

// The soup as it is, one open piece, when CGAL cannot make a polygon mesh of
// it (not expected after orient_polygon_soup; kept so that nothing is lost).
void ExportSoup(const std::vector<K::Point_3>& pts, const std::vector<std::int64_t>& psrc,
  const std::vector<std::array<std::size_t, 3>>& polys, const std::vector<std::int64_t>& fsrc, UnitResult& out)
{
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    out.points.emplace_back(pts[i].x(), pts[i].y(), pts[i].z());
    out.sourcePoint.push_back(psrc[i]);
    out.pointNormals.emplace_back(0.0);
  }
  PieceInfo info;
  for (std::size_t f = 0; f < polys.size(); ++f)
  {
    const auto& p = polys[f];
    out.triangles.push_back({ static_cast<std::int64_t>(p[0]), static_cast<std::int64_t>(p[1]),
      static_cast<std::int64_t>(p[2]) });
    out.sourceCell.push_back(fsrc[f]);
    const glm::dvec3 n = FaceNormal(out.points[p[0]], out.points[p[1]], out.points[p[2]]);
    out.faceNormals.push_back(n);
    for (int k = 0; k < 3; ++k)
    {
      out.pointNormals[p[k]] += n;
      info.bounds.Add(out.points[p[k]]);
    }
    out.piece.push_back(0);
  }
  for (auto& n : out.pointNormals)
  {
    const double l = glm::length(n);
    n = l > 0.0 ? n / l : glm::dvec3(0.0);
  }
  info.triangles = polys.size();
  out.pieces.push_back(info);
  ++out.stats.pieces;
  ++out.stats.openPieces;
}

UnitResult ProcessUnit(const RepairInput& in, const std::vector<std::int64_t>& tris,
  std::vector<std::int64_t>& localOf, const RepairOptions& options)
{
  UnitResult out;
  // --- the unit's soup, with local point indices (units own their points,
  // so localOf is written by one unit only)
  std::vector<K::Point_3> pts;
  std::vector<std::int64_t> psrc;
  std::vector<std::array<std::size_t, 3>> polys;
  std::vector<std::int64_t> fsrc;
  polys.reserve(tris.size());
  for (std::int64_t t : tris)
  {
    std::array<std::size_t, 3> poly;
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t p = in.triangles[t][k];
      if (localOf[p] < 0)
      {
        localOf[p] = static_cast<std::int64_t>(pts.size());
        pts.emplace_back(in.points[p].x, in.points[p].y, in.points[p].z);
        psrc.push_back(in.sourcePoint[p]);
      }
      poly[k] = static_cast<std::size_t>(localOf[p]);
    }
    polys.push_back(poly);
    fsrc.push_back(in.sourceCell[t]);
  }

  // --- into OpenMesh: face f is polygon f, vertex v is point v. OpenMesh's
  // add_face refuses a face that would make an edge or vertex non-manifold or
  // disagree with its neighbours' orientation; when it refuses none, the soup
  // was already a consistent manifold (the common case, and the fast one).
  double t0 = ThreadCpuMs();
  UnitMesh unit;
  const auto build = [&]() {
    Mesh& m = unit.mesh;
    m.reserve(pts.size(), 3 * polys.size() / 2 + 3, polys.size());
    std::vector<Mesh::VertexHandle> vh(pts.size());
    for (std::size_t v = 0; v < pts.size(); ++v)
    {
      vh[v] = m.add_vertex(Mesh::Point(pts[v].x(), pts[v].y(), pts[v].z()));
      m.property(unit.point, vh[v]) = psrc[v];
    }
    for (std::size_t f = 0; f < polys.size(); ++f)
    {
      const Mesh::FaceHandle fh = m.add_face(vh[polys[f][0]], vh[polys[f][1]], vh[polys[f][2]]);
      if (!fh.is_valid())
      {
        return false;
      }
      m.property(unit.cell, fh) = fsrc[f];
    }
    return true;
  };
  if (!build())
  {
    out.stats.msBuildMesh += Lap(t0);
    // CGAL orients the soup consistently, cutting non-manifold edges and
    // vertices apart (duplicated points) instead of dropping faces
    unit = UnitMesh();
    std::vector<std::pair<std::size_t, std::size_t>> duplicates;
    OrientVisitor ov;
    ov.stats = &out.stats;
    ov.duplicates = &duplicates;
    PMP::orient_polygon_soup(pts, polys, CGAL::parameters::visitor(ov));
    psrc.resize(pts.size(), -1);
    for (const auto& d : duplicates)
    {
      psrc[d.second] = psrc[d.first];
    }
    out.stats.msOrientSoup += Lap(t0);
    if (!build())
    {
      ExportSoup(pts, psrc, polys, fsrc, out); // not expected after CGAL's orientation
      return out;
    }
  }
  Mesh& m0 = unit.mesh;

  out.stats.msBuildMesh += Lap(t0);

  // --- zero-area faces (exactly collinear corners): CGAL collapses and flips
  // them away without opening the surface
  {
    std::vector<face_descriptor> degenerate;
    PMP::degenerate_faces(m0, std::back_inserter(degenerate));
    if (!degenerate.empty())
    {
      const std::size_t before = m0.n_faces();
      PMP::remove_degenerate_faces(m0);
      m0.garbage_collection();
      out.stats.degenerate += before - m0.n_faces();
    }
  }

  // --- slivers at the tolerance: a face whose height over its longest edge
  // is below the tolerance (a corner within the tolerance of the opposite
  // edge; exporters leave these where they patched a T-junction). Removing
  // it leaves that corner on a border edge: the T-junction snapping below
  // closes the crack, so slivers go only when snapping is on.
  if (options.snapTJunctions && options.tolerance > 0.0)
  {
    std::size_t slivers = 0;
    for (auto f : m0.faces())
    {
      std::array<glm::dvec3, 3> c;
      int k = 0;
      for (auto v : m0.fv_range(f))
      {
        c[k++ % 3] = Glm(m0.point(v));
      }
      const double longest =
        std::max({ glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2]) });
      const double twiceArea = glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
      if (longest > 0.0 && twiceArea <= options.tolerance * longest)
      {
        m0.delete_face(f, true);
        ++slivers;
      }
    }
    if (slivers > 0)
    {
      m0.garbage_collection();
      out.stats.degenerate += slivers;
    }
  }
  out.stats.msDegenerate += Lap(t0);

  // --- T-junctions: a border vertex within the tolerance of a border edge
  // splits that edge; stitching then closes the crack
  if (options.snapTJunctions && options.tolerance > 0.0)
  {
    bool border = false;
    for (auto h : m0.halfedges())
    {
      if (m0.is_boundary(h))
      {
        border = true;
        break;
      }
    }
    if (border)
    {
      out.stats.tJunctionsSnapped += SnapTJunctions(unit, options.tolerance);
    }
  }
  out.stats.msSnap += Lap(t0);
  Mesh& mesh = unit.mesh;
  const auto cellProp = unit.cell;
  const auto pointProp = unit.point;

  // --- classify each edge-connected component
  auto componentMap = get(CGAL::dynamic_face_property_t<std::size_t>(), mesh);
  const std::size_t components = PMP::connected_components(mesh, componentMap);
  std::vector<std::vector<face_descriptor>> faces(components);
  for (auto f : mesh.faces())
  {
    faces[get(componentMap, f)].push_back(f);
  }
  out.pieces.resize(components);
  out.stats.msComponents += Lap(t0);
  for (std::size_t c = 0; c < components; ++c)
  {
    PieceInfo& info = out.pieces[c];
    info.triangles = faces[c].size();
    bool closed = !faces[c].empty();
    for (auto f : faces[c])
    {
      for (auto h : mesh.fh_range(f))
      {
        closed = closed && !mesh.is_boundary(mesh.opposite_halfedge_handle(h));
      }
    }
    info.closed = closed;
    if (closed && options.checkSelfIntersections)
    {
      // units already run in parallel; a component that is a large part of
      // the work (one huge closed surface) uses all cores itself
      info.selfIntersecting = faces[c].size() > kParallelComponent
        ? PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(faces[c], mesh)
        : PMP::does_self_intersect<CGAL::Sequential_tag>(faces[c], mesh);
      out.stats.msSelfIntersections += Lap(t0);
    }
    if (closed && !info.selfIntersecting)
    {
      // CGAL's orientation test needs a closed, self-intersection-free
      // component: the one this filtered view shows it
      CGAL::Face_filtered_graph<Mesh> one(mesh, faces[c]);
      bool outward = PMP::is_outward_oriented(one);
      if (!outward && options.orientOutward)
      {
        PMP::reverse_face_orientations(faces[c], mesh);
        outward = true;
        info.reoriented = true;
      }
      // without the self-intersection test a piece is never trusted as closedOutward
      info.closedOutward = outward && options.checkSelfIntersections;
      out.stats.msOrientation += Lap(t0);
    }
    ++out.stats.pieces;
    out.stats.closedPieces += closed ? 1 : 0;
    out.stats.openPieces += closed ? 0 : 1;
    out.stats.selfIntersectingPieces += info.selfIntersecting ? 1 : 0;
    out.stats.reorientedPieces += info.reoriented ? 1 : 0;
    out.stats.closedOutwardPieces += info.closedOutward ? 1 : 0;
  }

  // --- normals (OpenMesh), then out
  mesh.update_normals();
  std::vector<std::int64_t> vertexIndex(mesh.n_vertices(), -1);
  for (auto v : mesh.vertices())
  {
    if (mesh.is_isolated(v))
    {
      continue;
    }
    vertexIndex[v.idx()] = static_cast<std::int64_t>(out.points.size());
    out.points.push_back(Glm(mesh.point(v)));
    out.sourcePoint.push_back(mesh.property(pointProp, v));
    const glm::dvec3 n = Glm(mesh.normal(v));
    out.pointNormals.push_back(std::isfinite(glm::length(n)) ? n : glm::dvec3(0.0));
  }
  for (std::size_t c = 0; c < components; ++c)
  {
    for (auto f : faces[c])
    {
      std::array<std::int64_t, 3> tri{};
      int k = 0;
      for (auto v : mesh.fv_range(f))
      {
        if (k < 3)
        {
          tri[k] = vertexIndex[v.idx()];
          out.pieces[c].bounds.Add(out.points[tri[k]]);
        }
        ++k;
      }
      out.triangles.push_back(tri);
      out.sourceCell.push_back(mesh.property(cellProp, f));
      const glm::dvec3 n = Glm(mesh.normal(f));
      const double l = glm::length(n);
      out.faceNormals.push_back(std::isfinite(l) && l > 0.5 ? n / l : glm::dvec3(0.0));
      out.piece.push_back(static_cast<std::int64_t>(c));
    }
  }
  out.stats.msNormalsOut += Lap(t0);
  return out;
}

void Add(RepairStats& a, const RepairStats& b)
{
  a.collapsed += b.collapsed;
  a.degenerate += b.degenerate;
  a.nonManifoldEdges += b.nonManifoldEdges;
  a.nonManifoldVertices += b.nonManifoldVertices;
  a.duplicatedPoints += b.duplicatedPoints;
  a.flippedForConsistency += b.flippedForConsistency;
  a.tJunctionsSnapped += b.tJunctionsSnapped;
  a.pieces += b.pieces;
  a.closedPieces += b.closedPieces;
  a.openPieces += b.openPieces;
  a.selfIntersectingPieces += b.selfIntersectingPieces;
  a.reorientedPieces += b.reorientedPieces;
  a.closedOutwardPieces += b.closedOutwardPieces;
  a.msOrientSoup += b.msOrientSoup;
  a.msBuildMesh += b.msBuildMesh;
  a.msDegenerate += b.msDegenerate;
  a.msSnap += b.msSnap;
  a.msComponents += b.msComponents;
  a.msSelfIntersections += b.msSelfIntersections;
  a.msOrientation += b.msOrientation;
  a.msNormalsOut += b.msNormalsOut;
}
}

RepairedMesh RepairMesh(const RepairInput& in, const RepairOptions& options, RepairStats& stats,
  const RepairProgress& progress, bool* aborted)
{
  RepairedMesh out;
  // OpenMesh reports every face its add_face refuses; here a refusal is
  // expected (it sends the piece through CGAL's orientation), not an error.
  omerr().disable();
  if (aborted)
  {
    *aborted = false;
  }
  // --- triangles whose corners were welded together carry no area
  std::vector<std::int64_t> kept;
  kept.reserve(in.triangles.size());
  for (std::size_t t = 0; t < in.triangles.size(); ++t)
  {
    const auto& tr = in.triangles[t];
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
    {
      ++stats.collapsed;
      continue;
    }
    kept.push_back(static_cast<std::int64_t>(t));
  }

  // --- vertex-connected pieces, in the order of their first triangle
  DisjointSets sets(in.points.size());
  for (std::int64_t t : kept)
  {
    sets.Unite(in.triangles[t][0], in.triangles[t][1]);
    sets.Unite(in.triangles[t][0], in.triangles[t][2]);
  }
  std::vector<std::int64_t> pieceOfRoot(in.points.size(), -1);
  std::vector<std::vector<std::int64_t>> pieces;
  for (std::int64_t t : kept)
  {
    const std::int64_t r = sets.Find(in.triangles[t][0]);
    if (pieceOfRoot[r] < 0)
    {
      pieceOfRoot[r] = static_cast<std::int64_t>(pieces.size());
      pieces.emplace_back();
    }
    pieces[pieceOfRoot[r]].push_back(t);
  }
  // Units: a large piece alone; small pieces share a unit up to a quarter of
  // the unit size (CGAL's orientation test walks a unit's vertices once per
  // closed component, so units of many small pieces stay small).
  const std::size_t unitSize = std::max<std::size_t>(options.unitTriangles, 64);
  std::vector<std::vector<std::int64_t>> units;
  for (auto& p : pieces)
  {
    const bool small = p.size() < unitSize / 4;
    if (small && !units.empty() && units.back().size() + p.size() <= unitSize / 4)
    {
      units.back().insert(units.back().end(), p.begin(), p.end());
    }
    else
    {
      units.push_back(std::move(p));
    }
  }
  pieces.clear();

  // --- units in parallel in one loop, the largest first (a loop per batch
  // left a core idle behind each batch's last unit). Progress is reported,
  // and an abort honoured, on the calling thread only (VTK's progress events
  // are not thread-safe), after each unit it ran.
  std::vector<UnitResult> results(units.size());
  std::vector<std::int64_t> localOf(in.points.size(), -1);
  std::vector<char> finished(units.size(), 0);
  std::vector<std::size_t> largestFirst(units.size());
  std::iota(largestFirst.begin(), largestFirst.end(), std::size_t(0));
  std::stable_sort(largestFirst.begin(), largestFirst.end(),
    [&](std::size_t a, std::size_t b) { return units[a].size() > units[b].size(); });
  const std::size_t total = std::max<std::size_t>(kept.size(), 1);
  std::atomic<std::size_t> done{ 0 };
  std::atomic<bool> stop{ false };
  const std::thread::id caller = std::this_thread::get_id();
  tbb::parallel_for(std::size_t(0), units.size(), [&](std::size_t i) {
    const std::size_t u = largestFirst[i];
    if (stop.load())
    {
      return;
    }
    results[u] = ProcessUnit(in, units[u], localOf, options);
    finished[u] = 1;
    const std::size_t d = done.fetch_add(units[u].size()) + units[u].size();
    if (progress && std::this_thread::get_id() == caller &&
      !progress(static_cast<double>(d) / static_cast<double>(total)))
    {
      stop = true;
    }
  });
  std::size_t next = 0;
  while (next < units.size() && finished[next])
  {
    ++next;
  }
  if (next < units.size())
  {
    if (aborted)
    {
      *aborted = true;
    }
  }
  else if (progress && !stop.load())
  {
    progress(1.0);
  }

  // --- concatenate in unit order: offsets first, then the units' copies in parallel
  std::vector<std::size_t> pointBase(next + 1, 0), triBase(next + 1, 0), pieceBase(next + 1, 0);
  for (std::size_t u = 0; u < next; ++u)
  {
    pointBase[u + 1] = pointBase[u] + results[u].points.size();
    triBase[u + 1] = triBase[u] + results[u].triangles.size();
    pieceBase[u + 1] = pieceBase[u] + results[u].pieces.size();
    Add(stats, results[u].stats);
  }
  out.points.resize(pointBase[next]);
  out.sourcePoint.resize(pointBase[next]);
  out.pointNormals.resize(pointBase[next]);
  out.triangles.resize(triBase[next]);
  out.sourceCell.resize(triBase[next]);
  out.faceNormals.resize(triBase[next]);
  out.piece.resize(triBase[next]);
  out.pieces.resize(pieceBase[next]);
  tbb::parallel_for(std::size_t(0), next, [&](std::size_t u) {
    UnitResult& r = results[u];
    const std::int64_t pb = static_cast<std::int64_t>(pointBase[u]);
    const std::int64_t qb = static_cast<std::int64_t>(pieceBase[u]);
    std::copy(r.points.begin(), r.points.end(), out.points.begin() + pointBase[u]);
    std::copy(r.sourcePoint.begin(), r.sourcePoint.end(), out.sourcePoint.begin() + pointBase[u]);
    std::copy(r.pointNormals.begin(), r.pointNormals.end(), out.pointNormals.begin() + pointBase[u]);
    for (std::size_t t = 0; t < r.triangles.size(); ++t)
    {
      const auto& tr = r.triangles[t];
      out.triangles[triBase[u] + t] = { tr[0] + pb, tr[1] + pb, tr[2] + pb };
      out.piece[triBase[u] + t] = r.piece[t] + qb;
    }
    std::copy(r.sourceCell.begin(), r.sourceCell.end(), out.sourceCell.begin() + triBase[u]);
    std::copy(r.faceNormals.begin(), r.faceNormals.end(), out.faceNormals.begin() + triBase[u]);
    std::copy(r.pieces.begin(), r.pieces.end(), out.pieces.begin() + pieceBase[u]);
    r = UnitResult();
  });
  return out;
}
}
