// vtkShadowCasterPreparation on broken CAD-like exports (duplicated vertices,
// slivers, NaNs, T-junctions, inverted and self-intersecting pieces,
// non-manifold edges, polygons and strips), and its clusters' bounds.
#include "vtkShadowCasterPreparation.h"

#include "ssClusterBounds.h"
#include "ssClusterTable.h"
#include "ssOrientedBoxes.h"
#include "ssWeld.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <vector>

namespace
{
using P3 = std::array<double, 3>;
using Tri = std::array<P3, 3>;

// The surface of [0,1]^3 as triangles (outward), each side a n x n grid; the
// top (z = 1) an m x m grid, so that where n != m its corners on the top edges
// meet the sides' edges in T-junctions.
std::vector<Tri> Cube(int n, int m)
{
  std::vector<Tri> out;
  // side s: origin o, axes a (first) and b (second), normal a x b outward
  struct Side
  {
    P3 o, a, b;
    int res;
  };
  const std::vector<Side> sides{
    { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, n }, // z = 0, normal -z
    { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 }, m }, // z = 1, normal +z
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, n }, // y = 0, normal -y
    { { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 0 }, n }, // y = 1, normal +y
    { { 0, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 }, n }, // x = 0, normal -x
    { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, n }, // x = 1, normal +x
  };
  for (const Side& s : sides)
  {
    const auto p = [&](int i, int j) {
      const double u = double(i) / s.res, v = double(j) / s.res;
      return P3{ s.o[0] + u * s.a[0] + v * s.b[0], s.o[1] + u * s.a[1] + v * s.b[1], s.o[2] + u * s.a[2] + v * s.b[2] };
    };
    for (int j = 0; j < s.res; ++j)
    {
      for (int i = 0; i < s.res; ++i)
      {
        out.push_back({ p(i, j), p(i + 1, j), p(i + 1, j + 1) });
        out.push_back({ p(i, j), p(i + 1, j + 1), p(i, j + 1) });
      }
    }
  }
  return out;
}

// A triangle soup as an STL export writes it: three points per triangle,
// every shared point duplicated, duplicates off by `jitter`.
void AddSoup(const std::vector<Tri>& tris, vtkPoints* pts, vtkCellArray* polys, double jitter, std::mt19937& rng)
{
  std::uniform_real_distribution<double> d(-jitter, jitter);
  for (const auto& t : tris)
  {
    vtkIdType ids[3];
    for (int k = 0; k < 3; ++k)
    {
      ids[k] = pts->InsertNextPoint(t[k][0] + d(rng), t[k][1] + d(rng), t[k][2] + d(rng));
    }
    polys->InsertNextCell(3, ids);
  }
}

vtkSmartPointer<vtkPolyData> Prepare(vtkPolyData* in, vtkShadowCasterPreparation* f = nullptr)
{
  vtkNew<vtkShadowCasterPreparation> own;
  if (!f)
  {
    f = own;
  }
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

long long Count(vtkPolyData* out, const char* name)
{
  vtkDataArray* a = out->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? static_cast<long long>(a->GetComponent(0, 0)) : -1;
}

P3 Pt(vtkPolyData* pd, vtkIdType id)
{
  P3 p;
  pd->GetPoint(id, p.data());
  return p;
}

glm::dvec3 G(const P3& p)
{
  return { p[0], p[1], p[2] };
}

// Area and signed volume of the triangles whose PieceId is `piece` (-1: all).
void Measure(vtkPolyData* out, long long piece, double& area, double& volume)
{
  area = volume = 0.0;
  vtkDataArray* pid = out->GetCellData()->GetArray("PieceId");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    if (piece >= 0 && static_cast<long long>(pid->GetComponent(c, 0)) != piece)
    {
      continue;
    }
    out->GetCellPoints(c, ids);
    const glm::dvec3 a = G(Pt(out, ids->GetId(0))), b = G(Pt(out, ids->GetId(1))), d = G(Pt(out, ids->GetId(2)));
    area += 0.5 * glm::length(glm::cross(b - a, d - a));
    volume += glm::dot(a, glm::cross(b, d)) / 6.0;
  }
}
}

namespace
{
// Records the progress a filter reports.
class ProgressRecorder : public vtkCommand
{
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject*, unsigned long, void* data) override { values.push_back(*static_cast<double*>(data)); }
  std::vector<double> values;
};

// Records the error messages a filter reports.
class ErrorRecorder : public vtkCommand
{
public:
  static ErrorRecorder* New() { return new ErrorRecorder; }
  void Execute(vtkObject*, unsigned long, void* data) override { text += static_cast<const char*>(data); }
  std::string text;
};

// The cube with the T-junctions of Cube(2, 3) and, on its bottom, the edge
// A-B = (0,0,0)-(0,0.5,0) closed by a zero-area sliver (A, B, E), E = (0,0.25,0)
// on it: the bottom's triangle on that edge is split at E, the side's is not
// (how exporters patch a T-junction).
std::vector<Tri> BrokenCube()
{
  std::vector<Tri> cube = Cube(2, 3);
  const P3 A{ 0, 0, 0 }, B{ 0, 0.5, 0 }, C{ 0.5, 0.5, 0 }, E{ 0, 0.25, 0 };
  for (auto it = cube.begin(); it != cube.end(); ++it)
  {
    if ((*it)[0] == A && (*it)[1] == B && (*it)[2] == C)
    {
      cube.erase(it);
      cube.push_back({ A, E, C });
      cube.push_back({ E, B, C });
      cube.push_back({ A, B, E }); // the sliver
      return cube;
    }
  }
  ADD_FAILURE() << "the bottom triangle A B C was not found";
  return cube;
}

std::vector<Tri> Moved(std::vector<Tri> tris, const P3& d, bool reverse = false)
{
  for (auto& t : tris)
  {
    for (auto& p : t)
    {
      for (int k = 0; k < 3; ++k)
      {
        p[k] += d[k];
      }
    }
    if (reverse)
    {
      std::swap(t[1], t[2]);
    }
  }
  return tris;
}

vtkSmartPointer<vtkPolyData> Soup(const std::vector<Tri>& tris, double jitter, unsigned seed)
{
  std::mt19937 rng(seed);
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  AddSoup(tris, pts, polys, jitter, rng);
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

long long PieceWhere(vtkPolyData* out, const std::function<bool(const P3&)>& inside)
{
  vtkNew<vtkIdList> ids;
  vtkDataArray* pid = out->GetCellData()->GetArray("PieceId");
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    out->GetCellPoints(c, ids);
    if (inside(Pt(out, ids->GetId(0))))
    {
      return static_cast<long long>(pid->GetComponent(c, 0));
    }
  }
  return -1;
}

bool PieceClosedOutward(vtkPolyData* out, long long piece)
{
  vtkDataArray* pid = out->GetCellData()->GetArray("PieceId");
  vtkDataArray* co = out->GetCellData()->GetArray("ClosedOutward");
  bool any = false, all = true;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    if (static_cast<long long>(pid->GetComponent(c, 0)) == piece)
    {
      any = true;
      all = all && co->GetComponent(c, 0) == 1;
    }
  }
  return any && all;
}
}

// One export with every defect at once: the cube must come out closed,
// outward, with all its area, and each defect counted.
TEST(ShadowCasterPreparation, RepairsABrokenCADExport)
{
  std::mt19937 rng(7);
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys, strips;
  // duplicated points 1e-9 apart: welded by the tolerance (1e-6 of the
  // diagonal, about 1.3e-5 here), not by exact merging
  AddSoup(BrokenCube(), pts, polys, 1e-9, rng);
  {
    // corners that weld together: the triangle collapses
    vtkIdType ids[3] = { pts->InsertNextPoint(1, 1, 1), pts->InsertNextPoint(1 + 1e-9, 1, 1),
      pts->InsertNextPoint(0.5, 0.5, 1) };
    polys->InsertNextCell(3, ids);
  }
  {
    // a NaN point and a triangle that uses it
    vtkIdType ids[3] = { pts->InsertNextPoint(std::nan(""), 0, 0), pts->InsertNextPoint(3, 0, 0),
      pts->InsertNextPoint(3, 1, 0) };
    polys->InsertNextCell(3, ids);
  }
  {
    // a concave L-shaped polygon of area 3 and a 1 x 1 strip of 4 triangles
    const double L[6][2] = { { 0, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1, 2 }, { 0, 2 } };
    vtkIdType ids[6], s[6];
    for (int i = 0; i < 6; ++i)
    {
      ids[i] = pts->InsertNextPoint(5 + L[i][0], L[i][1], -2);
      s[i] = pts->InsertNextPoint(10 + 0.5 * (i / 2), i % 2, -2);
    }
    polys->InsertNextCell(6, ids);
    strips->InsertNextCell(6, s);
  }
  vtkNew<vtkPolyData> in;
  in->SetPoints(pts);
  in->SetPolys(polys);
  in->SetStrips(strips);

  vtkNew<vtkShadowCasterPreparation> f;
  vtkNew<ProgressRecorder> progress;
  f->AddObserver(vtkCommand::ProgressEvent, progress);
  const vtkSmartPointer<vtkPolyData> out = Prepare(in, f);

  EXPECT_EQ(Count(out, "NonFinitePoints"), 1);
  EXPECT_EQ(Count(out, "NonFiniteCells"), 1);
  EXPECT_GT(Count(out, "WeldedPoints"), 100);
  EXPECT_EQ(Count(out, "CollapsedTriangles"), 1);
  EXPECT_EQ(Count(out, "DegenerateTriangles"), 1); // the sliver
  EXPECT_GE(Count(out, "TJunctionsSnapped"), 4 * 3);  // 3 per top edge
  EXPECT_EQ(Count(out, "TriangulatedPolygons"), 1);
  EXPECT_EQ(Count(out, "TriangulatedStrips"), 1);
  EXPECT_EQ(Count(out, "Pieces"), 3); // cube, L, strip
  EXPECT_EQ(Count(out, "ClosedPieces"), 1);
  EXPECT_EQ(Count(out, "ClosedOutwardPieces"), 1);
  EXPECT_EQ(Count(out, "SelfIntersectingPieces"), 0);
  EXPECT_EQ(Count(out, "OutputTriangles"), out->GetNumberOfCells());

  // no NaN, no zero-area triangle
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const P3 p = Pt(out, i);
    ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    out->GetCellPoints(c, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 3);
    const glm::dvec3 a = G(Pt(out, ids->GetId(0))), b = G(Pt(out, ids->GetId(1))), d = G(Pt(out, ids->GetId(2)));
    EXPECT_GT(glm::length(glm::cross(b - a, d - a)), 1e-12) << "cell " << c;
  }
  // the cube: closed, outward, all of its area, volume +1; nothing lost elsewhere
  const long long cube = PieceWhere(out, [](const P3& p) { return p[2] >= -0.5 && p[0] < 2; });
  ASSERT_GE(cube, 0);
  EXPECT_TRUE(PieceClosedOutward(out, cube));
  double area, volume;
  Measure(out, cube, area, volume);
  EXPECT_NEAR(area, 6.0, 1e-6);
  EXPECT_NEAR(volume, 1.0, 1e-6);
  Measure(out, -1, area, volume);
  EXPECT_NEAR(area, 6.0 + 3.0 + 1.0, 1e-6);
  // progress from 0 to 1, never backwards
  ASSERT_GE(progress->values.size(), 3u);
  EXPECT_DOUBLE_EQ(progress->values.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(progress->values.begin(), progress->values.end()));
}

// Without snapping, the same cube stays open at its T-junctions (the repair
// is what closes it), and with no tolerance nothing is welded either.
TEST(ShadowCasterPreparation, SnappingIsWhatClosesTJunctions)
{
  vtkSmartPointer<vtkPolyData> in = Soup(Cube(2, 3), 0.0, 1);
  vtkNew<vtkShadowCasterPreparation> f;
  f->SnapTJunctionsOff();
  vtkSmartPointer<vtkPolyData> out = Prepare(in, f);
  EXPECT_EQ(Count(out, "ClosedPieces"), 0);
  EXPECT_EQ(Count(out, "TJunctionsSnapped"), 0);
  f->SnapTJunctionsOn();
  out = Prepare(in, f);
  EXPECT_EQ(Count(out, "ClosedOutwardPieces"), 1);
  vtkSmartPointer<vtkPolyData> jittered = Soup(Cube(2, 2), 1e-9, 2);
  f->SetWeldTolerance(0.0);
  out = Prepare(jittered, f);
  EXPECT_EQ(Count(out, "ClosedPieces"), 0); // 1e-9 apart is not the same point
  f->SetWeldTolerance(1e-6);
  out = Prepare(jittered, f);
  EXPECT_EQ(Count(out, "ClosedOutwardPieces"), 1);
}

// Closed pieces: an inside-out cube is reversed, a self-intersecting one is
// found and not trusted, two cubes sharing an edge (a non-manifold edge) are
// cut apart into two closed pieces.
TEST(ShadowCasterPreparation, ClassifiesClosedPieces)
{
  std::vector<Tri> tris = Moved(Cube(2, 2), { 0, 0, 0 }, true); // inward
  // a cube with its top centre pushed down through its bottom
  std::vector<Tri> poked = Moved(Cube(2, 2), { 3, 0, 0 });
  for (auto& t : poked)
  {
    for (auto& p : t)
    {
      if (std::abs(p[0] - 3.5) < 1e-12 && std::abs(p[1] - 0.5) < 1e-12 && p[2] == 1.0)
      {
        p[2] = -0.5;
      }
    }
  }
  tris.insert(tris.end(), poked.begin(), poked.end());
  // two cubes sharing the edge x = 7, z = 0..1 at y = 0 (diagonal neighbours)
  const std::vector<Tri> c1 = Moved(Cube(1, 1), { 6, -1, 0 }), c2 = Moved(Cube(1, 1), { 7, 0, 0 });
  tris.insert(tris.end(), c1.begin(), c1.end());
  tris.insert(tris.end(), c2.begin(), c2.end());
  vtkSmartPointer<vtkPolyData> out = Prepare(Soup(tris, 0.0, 3));
  EXPECT_EQ(Count(out, "Pieces"), 4);
  EXPECT_EQ(Count(out, "ClosedPieces"), 4);
  EXPECT_EQ(Count(out, "ReorientedPieces"), 1);
  EXPECT_EQ(Count(out, "SelfIntersectingPieces"), 1);
  EXPECT_EQ(Count(out, "ClosedOutwardPieces"), 3);
  EXPECT_GE(Count(out, "NonManifoldEdges"), 1);
  const long long inverted = PieceWhere(out, [](const P3& p) { return p[0] <= 1.0; });
  const long long pokedPiece = PieceWhere(out, [](const P3& p) { return p[0] >= 3.0 && p[0] <= 4.0; });
  EXPECT_TRUE(PieceClosedOutward(out, inverted));
  EXPECT_FALSE(PieceClosedOutward(out, pokedPiece));
  double area, volume;
  Measure(out, inverted, area, volume);
  EXPECT_NEAR(volume, 1.0, 1e-9); // reversed: outward now
}

namespace
{
// Every cluster's bounds hold its triangles, the ranges partition the cells,
// no cluster is larger than asked, and closed clusters' cones are narrower
// than a hemisphere.
void CheckClusters(vtkPolyData* out, int maxTriangles)
{
  ss::ClusterTable table;
  std::string why;
  ASSERT_TRUE(ss::ReadClusterTable(out, table, why, true)) << why; // the ranges partition the cells
  ASSERT_EQ(table.piece.size(), static_cast<std::size_t>(out->GetNumberOfCells()));
  ASSERT_EQ(table.closedOutward.size(), table.piece.size());
  vtkDataArray* normals = out->GetCellData()->GetNormals();
  vtkDataArray* cellClosed = out->GetCellData()->GetArray("ClosedOutward");
  vtkDataArray* clusterId = out->GetCellData()->GetArray("ClusterId");
  ASSERT_TRUE(normals && cellClosed && clusterId);
  std::size_t next = 0;
  vtkNew<vtkIdList> ids;
  for (std::size_t c = 0; c < table.ranges.size(); ++c)
  {
    const auto [first, count] = table.ranges[c];
    ASSERT_EQ(first, next);
    ASSERT_GE(count, 1u);
    ASSERT_LE(count, static_cast<std::size_t>(maxTriangles));
    next = first + count;
    const ss::ClusterBounds& b = table.bounds[c];
    if (b.closedOutward)
    {
      EXPECT_GT(b.cone.cosAngle, 0.0) << "closed cluster " << c << " has a cone wider than a hemisphere";
    }
    for (std::size_t cell = first; cell < first + count; ++cell)
    {
      const vtkIdType id = static_cast<vtkIdType>(cell);
      ASSERT_EQ(clusterId->GetComponent(id, 0), c);
      ASSERT_EQ(cellClosed->GetComponent(id, 0) == 1, b.closedOutward) << "cluster " << c << " mixes pieces";
      ASSERT_EQ(table.closedOutward[cell] == 1, b.closedOutward);
      out->GetCellPoints(id, ids);
      for (vtkIdType k = 0; k < 3; ++k)
      {
        const glm::dvec3 p = G(Pt(out, ids->GetId(k)));
        ASSERT_TRUE(b.aabb.Contains(p)) << "cluster " << c << ": a vertex outside its AABB";
        ASSERT_TRUE(b.pieceBounds.Contains(p)) << "cluster " << c << ": a vertex outside its pieces' bounds";
        ASSERT_TRUE(b.obb.Contains(p)) << "cluster " << c << ": a vertex outside its oriented box";
      }
      double n[3];
      normals->GetTuple(id, n);
      ASSERT_GE(glm::dot(b.cone.axis, glm::dvec3(n[0], n[1], n[2])), b.cone.cosAngle - 1e-6)
        << "cluster " << c << ": a face normal outside its cone";
    }
  }
  EXPECT_EQ(next, static_cast<std::size_t>(out->GetNumberOfCells()));
}
}

TEST(ShadowCasterPreparation, NoTriangleOutsideItsClusterBounds)
{
  // a closed sphere far from the origin, a broken cube and a random soup
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(1e5, -2e5, 3e4);
  sphere->SetRadius(2.0);
  sphere->SetThetaResolution(60);
  sphere->SetPhiResolution(40);
  sphere->Update();
  std::vector<Tri> tris = BrokenCube();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0), d(-0.2, 0.2);
  for (int t = 0; t < 2000; ++t)
  {
    const P3 c{ u(rng) + 1e5, u(rng) - 2e5, u(rng) + 3e4 };
    tris.push_back({ P3{ c[0] + d(rng), c[1] + d(rng), c[2] + d(rng) }, P3{ c[0] + d(rng), c[1] + d(rng), c[2] + d(rng) },
      P3{ c[0] + d(rng), c[1] + d(rng), c[2] + d(rng) } });
  }
  for (int boxes : { vtkShadowCasterPreparation::BOXES_PLANE, vtkShadowCasterPreparation::BOXES_AXIS_ALIGNED })
  {
    for (int n : { 1, 7, 64, 256 })
    {
      vtkNew<vtkShadowCasterPreparation> f;
      f->SetMaximumClusterTriangles(n);
      f->SetOrientedBoxes(boxes);
      CheckClusters(Prepare(Soup(tris, 0.0, 4), f), n);
      CheckClusters(Prepare(sphere->GetOutput(), f), n);
    }
  }
  // CGAL's optimal boxes on a small input (tens of milliseconds per cluster)
  vtkNew<vtkShadowCasterPreparation> f;
  f->SetOrientedBoxes(vtkShadowCasterPreparation::BOXES_OPTIMAL);
  f->SetMaximumClusterTriangles(512);
  CheckClusters(Prepare(sphere->GetOutput(), f), 512);
}

// The oriented boxes are tight: on a tilted thin plate their volume is a
// small part of the AABB's.
TEST(ShadowCasterPreparation, OrientedBoxesAreTight)
{
  std::vector<Tri> plate;
  const glm::dvec3 a = glm::normalize(glm::dvec3(1, 1, 0.3)), b = glm::normalize(glm::cross(a, glm::dvec3(0, 0.3, 1)));
  for (int j = 0; j < 8; ++j)
  {
    for (int i = 0; i < 8; ++i)
    {
      const auto q = [&](int x, int y) {
        const glm::dvec3 p = 0.25 * x * a + 0.25 * y * b;
        return P3{ p.x, p.y, p.z };
      };
      plate.push_back({ q(i, j), q(i + 1, j), q(i + 1, j + 1) });
      plate.push_back({ q(i, j), q(i + 1, j + 1), q(i, j + 1) });
    }
  }
  for (int boxes : { vtkShadowCasterPreparation::BOXES_PLANE, vtkShadowCasterPreparation::BOXES_OPTIMAL })
  {
    vtkNew<vtkShadowCasterPreparation> f;
    f->SetMaximumClusterTriangles(1024);
    f->SetOrientedBoxes(boxes);
    vtkSmartPointer<vtkPolyData> out = Prepare(Soup(plate, 0.0, 5), f);
    ASSERT_EQ(out->GetFieldData()->GetArray("ClusterOBB")->GetNumberOfTuples(), 1);
    double ob[15], ab[6];
    out->GetFieldData()->GetArray("ClusterOBB")->GetTuple(0, ob);
    out->GetFieldData()->GetArray("ClusterAABB")->GetTuple(0, ab);
    // the plate is 2 x 2 and flat: the box is 2 x 2 x (rounding)
    // the plane box is exact; CGAL's optimal box is a genetic search that
    // ended 1.6% long on this plate when written
    const double tolerance = boxes == vtkShadowCasterPreparation::BOXES_PLANE ? 1e-6 : 0.05;
    EXPECT_NEAR(2.0 * std::max({ ob[12], ob[13], ob[14] }), 2.0, tolerance) << "boxes " << boxes;
    EXPECT_NEAR(2.0 * std::min(std::max(ob[12], ob[13]), std::max(ob[13], ob[14])), 2.0, tolerance);
    EXPECT_LT(std::min({ ob[12], ob[13], ob[14] }), boxes == vtkShadowCasterPreparation::BOXES_PLANE ? 1e-9 : 0.05);
    EXPECT_GT((ab[1] - ab[0]) * (ab[3] - ab[2]) * (ab[5] - ab[4]), 0.1);
  }
}

// Far out, the same boxes (scaled). Before stop 53, CGAL's optimal box on
// coordinates from about 1e117 overflowed to inf and GMP raised SIGFPE: the
// process died (pvpython with it). The axes are computed on the points
// scaled by a power of two, exactly the same ones.
TEST(ShadowCasterPreparation, OrientedBoxesAtAnyScale)
{
  const double big = std::ldexp(1.0, 400); // 2.6e120
  std::vector<glm::dvec3> points, scaled;
  for (int i = 0; i < 40; ++i)
  {
    const glm::dvec3 p(std::cos(0.7 * i) * (1.0 + 0.1 * i), std::sin(1.3 * i), 0.2 * std::cos(2.9 * i) + 0.05 * i);
    points.push_back(p);
    scaled.push_back(big * p);
  }
  const auto a = ssf::OptimalBoxAxes(points), b = ssf::OptimalBoxAxes(scaled);
  const auto c = ssf::PlaneBoxAxes(points, glm::dvec3(0.0)), d = ssf::PlaneBoxAxes(scaled, glm::dvec3(0.0));
  for (int r = 0; r < 3; ++r)
  {
    EXPECT_EQ(a[r], b[r]) << "optimal, axis " << r;
    EXPECT_EQ(c[r], d[r]) << "plane, axis " << r;
  }
  // the filter on a sphere 1e130 out and 1e130 wide, with optimal boxes
  vtkNew<vtkSphereSource> sphere;
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->SetCenter(1e130, -1e130, 0.0);
  sphere->SetRadius(1e130);
  sphere->Update();
  vtkNew<vtkShadowCasterPreparation> f;
  f->SetOrientedBoxes(vtkShadowCasterPreparation::BOXES_OPTIMAL);
  vtkSmartPointer<vtkPolyData> out = Prepare(sphere->GetOutput(), f);
  EXPECT_GT(out->GetNumberOfCells(), 0);
  vtkDataArray* obb = out->GetFieldData()->GetArray("ClusterOBB");
  ASSERT_NE(obb, nullptr);
  for (vtkIdType i = 0; i < obb->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < 15; ++k)
    {
      EXPECT_TRUE(std::isfinite(obb->GetComponent(i, k))) << "cluster " << i;
    }
  }
}

// The output does not depend on the number of threads.
TEST(ShadowCasterPreparation, SameOutputOnOneThreadAndMany)
{
  std::vector<Tri> tris = BrokenCube();
  for (int i = 0; i < 40; ++i)
  {
    const std::vector<Tri> c = Moved(Cube(3, 3), { 2.0 * (i % 8), 2.0 * (i / 8), 0 }, i % 3 == 0);
    tris.insert(tris.end(), c.begin(), c.end());
  }
  vtkSmartPointer<vtkPolyData> in = Soup(tris, 1e-9, 6);
  vtkSmartPointer<vtkPolyData> many = Prepare(in);
  vtkSmartPointer<vtkPolyData> one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = Prepare(in);
  }
  ASSERT_EQ(one->GetNumberOfPoints(), many->GetNumberOfPoints());
  ASSERT_EQ(one->GetNumberOfCells(), many->GetNumberOfCells());
  for (vtkIdType i = 0; i < one->GetNumberOfPoints(); ++i)
  {
    ASSERT_EQ(Pt(one, i), Pt(many, i));
  }
  vtkNew<vtkIdList> a, b;
  for (vtkIdType c = 0; c < one->GetNumberOfCells(); ++c)
  {
    one->GetCellPoints(c, a);
    many->GetCellPoints(c, b);
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(a->GetId(k), b->GetId(k));
    }
  }
  for (const char* name : { "ClusterAABB", "ClusterOBB", "ClusterNormalCone" })
  {
    vtkDataArray* x = one->GetFieldData()->GetArray(name);
    vtkDataArray* y = many->GetFieldData()->GetArray(name);
    ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues());
    for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
    {
      ASSERT_EQ(x->GetComponent(v / x->GetNumberOfComponents(), v % x->GetNumberOfComponents()),
        y->GetComponent(v / y->GetNumberOfComponents(), v % y->GetNumberOfComponents()))
        << name;
    }
  }
}

// vtkSetClampMacro lets NaN through: a NaN weld tolerance welded nothing and
// wrote NaN into the output's field data (Python, C++; ParaView's domain and
// the CLI refuse it). Now the filter fails with an error naming the key.
TEST(ShadowCasterPreparation, NaNWeldToleranceIsAnError)
{
  vtkNew<vtkSphereSource> sphere;
  vtkNew<vtkShadowCasterPreparation> f;
  f->SetInputConnection(sphere->GetOutputPort());
  f->SetWeldTolerance(std::nan(""));
  vtkNew<ErrorRecorder> errors;
  f->AddObserver(vtkCommand::ErrorEvent, errors);
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
  f->Update();
  EXPECT_NE(errors->text.find("WeldTolerance"), std::string::npos) << errors->text;
  vtkPolyData* out = f->GetOutput();
  EXPECT_EQ(out->GetNumberOfCells(), 0);
  vtkDataArray* w = out->GetFieldData()->GetArray("WeldToleranceAbsolute");
  EXPECT_TRUE(w == nullptr || std::isfinite(w->GetComponent(0, 0)));
}

TEST(ShadowCasterPreparation, EmptyAndDegenerateInput)
{
  vtkNew<vtkPolyData> empty;
  vtkSmartPointer<vtkPolyData> out = Prepare(empty);
  EXPECT_EQ(out->GetNumberOfCells(), 0);
  EXPECT_EQ(Count(out, "Clusters"), 0);
  ss::ClusterTable table;
  std::string why;
  EXPECT_TRUE(ss::ReadClusterTable(out, table, why)) << why;
  EXPECT_TRUE(table.ranges.empty());
  EXPECT_FALSE(ss::ReadClusterTable(empty, table, why)); // not a preparation output
  EXPECT_NE(why.find("ClusterRange"), std::string::npos);
  // only NaN points and collapsed triangles: an empty surface, counted
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> polys;
  vtkIdType ids[3] = { pts->InsertNextPoint(std::nan(""), 0, 0), pts->InsertNextPoint(1, 0, 0),
    pts->InsertNextPoint(1, 0, 0) };
  polys->InsertNextCell(3, ids);
  vtkIdType ids2[3] = { 1, 2, 1 };
  polys->InsertNextCell(3, ids2);
  vtkNew<vtkPolyData> bad;
  bad->SetPoints(pts);
  bad->SetPolys(polys);
  out = Prepare(bad);
  EXPECT_EQ(out->GetNumberOfCells(), 0);
  EXPECT_EQ(Count(out, "NonFiniteCells"), 1);
  EXPECT_EQ(Count(out, "CollapsedTriangles"), 1);
}

// The weld (ssWeld.h) against the O(n^2) greedy merge in point order on the
// hard cases: points on axis-aligned planes and lines (a CAD model's grid,
// where an axis sweep would see thousands of equal keys), near-copies that
// chain (a - b and b - c within the tolerance, a - c not), exact copies, far
// coordinates, and the tolerance 0.
TEST(ShadowCasterPreparation, WeldIsTheGreedyMergeInPointOrder)
{
  const auto bruteForce = [](const std::vector<glm::dvec3>& p, double tol) {
    std::vector<std::int64_t> map(p.size(), -1);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
      if (map[i] >= 0)
      {
        continue;
      }
      map[i] = static_cast<std::int64_t>(i);
      for (std::size_t j = i + 1; j < p.size(); ++j)
      {
        const glm::dvec3 e = p[j] - p[i];
        if (map[j] < 0 && glm::dot(e, e) <= tol * tol)
        {
          map[j] = static_cast<std::int64_t>(i);
        }
      }
    }
    return map;
  };
  std::mt19937 rng(11);
  for (const glm::dvec3 offset : { glm::dvec3(0.0), glm::dvec3(3e5, -2e5, 1e5) })
  {
    for (const double tol : { 0.0, 0.01, 0.3 })
    {
      std::vector<glm::dvec3> p;
      for (int i = 0; i < 12; ++i)
      {
        for (int j = 0; j < 12; ++j)
        {
          for (int k = 0; k < 12; ++k)
          {
            p.push_back(offset + glm::dvec3(i, j, 0.5 * k)); // sheets and lines of equal coordinates
          }
        }
      }
      std::uniform_int_distribution<std::size_t> pick(0, p.size() - 1);
      std::uniform_real_distribution<double> jitter(-0.7, 0.7);
      const std::size_t grid = p.size();
      for (int c = 0; c < 1500; ++c)
      {
        const glm::dvec3 base = p[pick(rng)];
        switch (c % 3)
        {
          case 0: // an exact copy
            p.push_back(base);
            break;
          case 1: // a near copy, up to 1.2 tolerances away: chains form
            p.push_back(base + tol * glm::dvec3(jitter(rng), jitter(rng), jitter(rng)));
            break;
          default: // just outside along an axis, and just inside
            p.push_back(base + glm::dvec3(tol * (1.0 + 1e-9) + 1e-12, 0.0, 0.0));
            p.push_back(base + glm::dvec3(0.0, tol * (1.0 - 1e-9), 0.0));
            break;
        }
      }
      // the copies come before and after their originals in id order
      std::shuffle(p.begin() + static_cast<std::ptrdiff_t>(grid / 2), p.end(), rng);
      const std::vector<std::int64_t> expected = bruteForce(p, tol);
      const std::vector<std::int64_t> got = ssf::WeldPoints(p, tol);
      ASSERT_EQ(got.size(), p.size());
      std::size_t welded = 0, differ = 0;
      for (std::size_t i = 0; i < p.size(); ++i)
      {
        welded += expected[i] != static_cast<std::int64_t>(i) ? 1 : 0;
        differ += got[i] != expected[i] ? 1 : 0;
      }
      EXPECT_EQ(differ, 0u) << "tolerance " << tol << ", offset " << offset.x;
      EXPECT_GT(welded, 500u); // the exact copies at least
    }
  }
  EXPECT_TRUE(ssf::WeldPoints({}, 1.0).empty());
  // a pile of 300,000 copies of one point (a collapsed export) next to a
  // small grid: all go to the first copy, in linear time (every pair of the
  // pile would be 4.5e10 distance tests)
  std::vector<glm::dvec3> pile(300000, glm::dvec3(0.25, 0.5, 0.75));
  for (int i = 0; i < 1000; ++i)
  {
    pile.push_back(glm::dvec3(i % 10, (i / 10) % 10, i / 100));
  }
  const std::vector<std::int64_t> piled = ssf::WeldPoints(pile, 1e-3);
  EXPECT_EQ(std::count(piled.begin(), piled.begin() + 300000, 0), 300000);
  for (std::size_t i = 300000; i < pile.size(); ++i)
  {
    ASSERT_EQ(piled[i], static_cast<std::int64_t>(i));
  }
}

namespace
{
// Asks the filter to abort at the first progress the repair reports.
class AbortInRepair : public vtkCommand
{
public:
  static AbortInRepair* New() { return new AbortInRepair; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    const double v = *static_cast<double*>(data);
    values.push_back(v);
    if (armed && v > 0.1 && v <= 0.6)
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
  }
  bool armed = true;
  std::vector<double> values;
};
}

// The pieces run in one parallel loop; an abort asked for during it stops it
// at once (units not started are skipped) and leaves an empty output, and the
// same filter then runs to the end.
TEST(ShadowCasterPreparation, AbortStopsTheRepairLoop)
{
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(12);
  sphere->SetPhiResolution(12);
  sphere->Update();
  vtkPolyData* s = sphere->GetOutput();
  vtkNew<vtkIdList> ids;
  for (int i = 0; i < 300; ++i)
  {
    const vtkIdType base = pts->GetNumberOfPoints();
    for (vtkIdType p = 0; p < s->GetNumberOfPoints(); ++p)
    {
      double x[3];
      s->GetPoint(p, x);
      pts->InsertNextPoint(x[0] + 2.0 * (i % 20), x[1] + 2.0 * (i / 20), x[2]);
    }
    for (vtkIdType c = 0; c < s->GetNumberOfCells(); ++c)
    {
      s->GetCellPoints(c, ids);
      vtkIdType tri[3] = { base + ids->GetId(0), base + ids->GetId(1), base + ids->GetId(2) };
      polys->InsertNextCell(3, tri);
    }
  }
  vtkNew<vtkPolyData> in;
  in->SetPoints(pts);
  in->SetPolys(polys);
  vtkNew<vtkShadowCasterPreparation> f;
  vtkNew<AbortInRepair> observer;
  f->AddObserver(vtkCommand::ProgressEvent, observer);
  f->SetInputData(in);
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0);
  const auto inRepair = std::count_if(
    observer->values.begin(), observer->values.end(), [](double v) { return v > 0.1 && v <= 0.6; });
  EXPECT_EQ(inRepair, 1); // nothing reported after the abort
  // no cluster was bounded (that stage reports from 0.6 up; the pipeline
  // itself reports 1 at the end)
  EXPECT_EQ(std::count_if(observer->values.begin(), observer->values.end(),
              [](double v) { return v > 0.6 && v < 1.0; }),
    0);

  observer->armed = false;
  observer->values.clear();
  f->SetAbortExecute(0);
  f->Modified();
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 300 * s->GetNumberOfCells());
  EXPECT_EQ(Count(f->GetOutput(), "ClosedOutwardPieces"), 300);
  EXPECT_DOUBLE_EQ(observer->values.back(), 1.0);
}
