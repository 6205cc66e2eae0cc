// The camera's clipping range from the cells in view (ssClippingRange, stop
// 51). ResetClippingRangeToVisible walks a dataset's cells in runs with
// cached boxes; these tests hold it to a walk over every cell, under cameras
// inside and outside the data, with needles to a lost vertex, NaN cells and
// data changed between frames. An actor with a transform (every ParaView
// representation) must give the range of its data transformed beforehand,
// and the view's cheap test must ask for the walk where the camera is among
// a broken mesh's bounds. No window is needed.
#include "ssClippingRange.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
// Small triangles in a 10-unit box (`shuffled`: in random order, so that the
// runs' boxes span the scene), a floor, two needles to 1e10 and a NaN cell.
vtkSmartPointer<vtkPolyData> Scene(std::mt19937& rng, int n, bool shuffled)
{
  std::uniform_real_distribution<double> u(-5.0, 5.0), s(-0.2, 0.2);
  std::vector<std::array<double, 9>> tris;
  for (int i = 0; i < n; ++i)
  {
    const double c[3] = { u(rng), u(rng), 0.5 * (u(rng) + 5.0) };
    std::array<double, 9> t;
    for (int k = 0; k < 9; ++k)
    {
      t[k] = c[k % 3] + s(rng);
    }
    tris.push_back(t);
  }
  if (!shuffled)
  {
    std::sort(tris.begin(), tris.end()); // runs along x
  }
  tris.push_back({ -6, -6, 0, 6, -6, 0, 6, 6, 0 });
  tris.push_back({ 0, 0, 0.01, 0.01, 0, 0.01, 0.3, -0.2, -1e10 });
  tris.push_back({ 1, 1, 2, 1.01, 1, 2, 1e10, 0.5, 2 });
  const double nan = std::numeric_limits<double>::quiet_NaN();
  tris.push_back({ nan, 0, 0, 1, 0, 0, 0, 1, 0 });
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  for (const auto& t : tris)
  {
    const vtkIdType ids[3] = { pts->InsertNextPoint(t.data()), pts->InsertNextPoint(t.data() + 3),
      pts->InsertNextPoint(t.data() + 6) };
    polys->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

struct World
{
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkActor> actor;
  vtkNew<vtkPolyDataMapper> mapper;
  explicit World(vtkPolyData* pd)
  {
    mapper->SetInputData(pd);
    actor->SetMapper(mapper);
    renderer->AddActor(actor);
  }
};

// The range from a walk over every cell's bounds: the rule of
// ResetClippingRangeToVisible written out (cells not wholly outside a side
// plane set VTK's range; the near plane then moves to 0.99 of the nearest
// cell wholly in front where it passed it).
void EveryCellRange(vtkRenderer* ren, vtkPolyData* pd, double aspect, double out[2], bool& moved)
{
  vtkCamera* cam = ren->GetActiveCamera();
  double planes[24], eye[3], dir[3];
  cam->GetFrustumPlanes(aspect, planes);
  cam->GetPosition(eye);
  cam->GetDirectionOfProjection(dir);
  double box[6] = { DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX }, nearest = DBL_MAX, b[6];
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellBounds(c, b);
    bool usable = b[0] <= b[1];
    for (double x : b)
    {
      usable = usable && std::isfinite(x);
    }
    bool outside = false;
    double d = DBL_MAX;
    for (int corner = 0; corner < 8; ++corner)
    {
      const double p[3] = { b[corner & 1], b[2 + ((corner >> 1) & 1)], b[4 + (corner >> 2)] };
      const double de = dir[0] * eye[0] + dir[1] * eye[1] + dir[2] * eye[2];
      d = std::min(d, dir[0] * p[0] + dir[1] * p[1] + dir[2] * p[2] - de);
    }
    for (int q = 0; q < 4 && usable; ++q)
    {
      bool allOut = true;
      for (int corner = 0; corner < 8; ++corner)
      {
        const double* P = planes + 4 * q;
        allOut = allOut &&
          P[0] * b[corner & 1] + P[1] * b[2 + ((corner >> 1) & 1)] + P[2] * b[4 + (corner >> 2)] + P[3] < 0.0;
      }
      outside = outside || allOut;
    }
    if (!usable || outside)
    {
      continue;
    }
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = std::min(box[2 * a], b[2 * a]);
      box[2 * a + 1] = std::max(box[2 * a + 1], b[2 * a + 1]);
    }
    if (d > 0.0)
    {
      nearest = std::min(nearest, d);
    }
  }
  moved = false;
  ASSERT_LE(box[0], box[1]) << "no cell in view: pick another camera";
  ren->ResetCameraClippingRange(box);
  cam->GetClippingRange(out);
  const double ratio = ren->GetNearClippingPlaneTolerance() > 0.0 ? ren->GetNearClippingPlaneTolerance() : 1e-3;
  if (nearest < DBL_MAX && out[0] > nearest)
  {
    const double n = 0.99 * nearest;
    out[1] = std::min(out[1], n / ratio);
    out[0] = n;
    moved = true;
  }
}

void PlaceCamera(vtkCamera* cam, std::mt19937& rng, bool inside)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double pos[3];
  for (int a = 0; a < 3; ++a)
  {
    pos[a] = inside ? 4.0 * u(rng) : 18.0 * u(rng);
  }
  if (!inside)
  {
    pos[2] = 6.0 + 10.0 * std::abs(u(rng));
  }
  cam->SetPosition(pos);
  cam->SetFocalPoint(3.0 * u(rng), 3.0 * u(rng), 0.5 + std::abs(u(rng)));
  cam->SetViewUp(0.0, 0.0, 1.0);
  cam->OrthogonalizeViewUp();
  cam->SetViewAngle(20.0 + 40.0 * std::abs(u(rng)));
}
}

// The walk in runs gives the range of a walk over every cell, bit for bit:
// shuffled and ordered cells, cameras inside and outside the data, the same
// data over many frames (its cached runs) and after it changed.
TEST(ClippingRange, RunsGiveTheRangeOfEveryCell)
{
  std::mt19937 rng(51);
  const double aspect = 4.0 / 3.0;
  for (bool shuffled : { true, false })
  {
    vtkSmartPointer<vtkPolyData> pd = Scene(rng, 6000, shuffled);
    World w(pd);
    vtkCamera* cam = w.renderer->GetActiveCamera();
    int compared = 0, moved = 0;
    for (int frame = 0; frame < 60; ++frame)
    {
      if (frame == 30)
      {
        // the data changes: its runs must be rebuilt
        double p[3];
        for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); i += 7)
        {
          pd->GetPoint(i, p);
          p[2] += 1.5;
          pd->GetPoints()->SetPoint(i, p);
        }
        pd->GetPoints()->Modified();
        pd->Modified();
      }
      PlaceCamera(cam, rng, frame % 2 == 0);
      double expected[2], got[2];
      bool nearMoved = false;
      EveryCellRange(w.renderer, pd, aspect, expected, nearMoved);
      if (::testing::Test::HasFatalFailure())
      {
        continue;
      }
      cam->SetClippingRange(0.5, 1.0);
      ss::ResetClippingRangeToVisible(w.renderer, aspect);
      cam->GetClippingRange(got);
      EXPECT_EQ(got[0], expected[0]) << "frame " << frame << (shuffled ? ", shuffled" : ", ordered");
      EXPECT_EQ(got[1], expected[1]) << "frame " << frame << (shuffled ? ", shuffled" : ", ordered");
      ++compared;
      moved += nearMoved ? 1 : 0;
    }
    EXPECT_EQ(compared, 60);
    // many frames see a needle: the near plane moved to the nearest cell
    EXPECT_GT(moved, 10) << "the cameras did not exercise the nearest-cell rule";
  }
}

// An actor with a transform (ParaView's representations all have one) gives
// the range of its data transformed beforehand. The transform (a shift, a
// quarter turn, a uniform scale) takes boxes to boxes, so the cells' boxes
// are the same either way. Before stop 51 such an actor counted by its
// bounds, and with a needle in it and the camera among its bounds the near
// plane stayed at 1e7. (Under other rotations the walk in model coordinates
// tests a cell's box turned into the world, which is tighter than the world
// box of the turned cell: still nothing visible is clipped.)
TEST(ClippingRange, TransformedActorAsItsTransformedData)
{
  std::mt19937 rng(7);
  const double aspect = 1.5;
  vtkSmartPointer<vtkPolyData> pd = Scene(rng, 3000, true);
  vtkNew<vtkTransform> xf;
  xf->Translate(100.0, -40.0, 3.0);
  xf->RotateZ(90.0);
  xf->Scale(2.0, 2.0, 2.0);
  vtkNew<vtkTransformPolyDataFilter> moved;
  moved->SetInputData(pd);
  moved->SetTransform(xf);
  moved->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  moved->Update();
  World model(pd), world(moved->GetOutput());
  model.actor->SetUserTransform(xf);
  int compared = 0;
  for (int frame = 0; frame < 30; ++frame)
  {
    // cameras in the transformed data's frame: place them in the model's
    // and carry them over
    vtkNew<vtkCamera> c;
    PlaceCamera(c, rng, frame % 2 == 0);
    double p[3], f[3], up[3];
    xf->TransformPoint(c->GetPosition(), p);
    xf->TransformPoint(c->GetFocalPoint(), f);
    xf->TransformVector(c->GetViewUp(), up);
    for (vtkRenderer* r : { model.renderer.Get(), world.renderer.Get() })
    {
      vtkCamera* cam = r->GetActiveCamera();
      cam->SetPosition(p);
      cam->SetFocalPoint(f);
      cam->SetViewUp(up);
      cam->SetViewAngle(c->GetViewAngle());
      cam->SetClippingRange(0.5, 1.0);
      ss::ResetClippingRangeToVisible(r, aspect);
    }
    double a[2], b[2];
    model.renderer->GetActiveCamera()->GetClippingRange(a);
    world.renderer->GetActiveCamera()->GetClippingRange(b);
    // (the needles reach 1e10: the quarter turn's cosine, 6e-17, moves their
    // boxes by 1e-6 either way)
    EXPECT_NEAR(a[0], b[0], 1e-9 * b[0] + 1e-6) << "frame " << frame;
    EXPECT_NEAR(a[1], b[1], 1e-9 * b[1] + 1e-4) << "frame " << frame;
    ++compared;
  }
  EXPECT_EQ(compared, 30);
}

// The view's cheap test: a mesh around the camera with a needle in view puts
// VTK's near plane at 1e7; its bounds hold the camera, so only the near
// plane beyond the focal point can tell. An ordinary scene around the camera
// needs no walk.
TEST(ClippingRange, TheCheapTestAsksForTheWalkAroundTheCamera)
{
  std::mt19937 rng(3);
  vtkSmartPointer<vtkPolyData> pd = Scene(rng, 500, true);
  World w(pd);
  vtkCamera* cam = w.renderer->GetActiveCamera();
  cam->SetPosition(0.0, -3.0, 2.0);
  cam->SetFocalPoint(0.0, 0.0, 0.0);
  cam->SetViewUp(0.0, 0.0, 1.0);
  w.renderer->ResetCameraClippingRange(); // VTK's, from every bound
  double range[2];
  cam->GetClippingRange(range);
  ASSERT_GT(range[0], 1e5) << "VTK's near plane was expected far out";
  EXPECT_TRUE(ss::NearPlaneMayPassVisibleCells(w.renderer, 1.0));
  ss::ResetClippingRangeToVisible(w.renderer, 1.0);
  cam->GetClippingRange(range);
  EXPECT_LT(range[0], cam->GetDistance());
  EXPECT_FALSE(ss::NearPlaneMayPassVisibleCells(w.renderer, 1.0));

  // without the needles and the NaN cell: VTK's own range, no walk asked for
  vtkSmartPointer<vtkPolyData> plain = Scene(rng, 500, true);
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 0; c < plain->GetNumberOfCells() - 3; ++c)
  {
    polys->InsertNextCell(plain->GetCell(c));
  }
  plain->SetPolys(polys);
  World v(plain);
  v.renderer->SetActiveCamera(cam);
  v.renderer->ResetCameraClippingRange();
  EXPECT_FALSE(ss::NearPlaneMayPassVisibleCells(v.renderer, 1.0));
}
