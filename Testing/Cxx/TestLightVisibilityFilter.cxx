// vtkLightVisibilityFilter against exact answers: a finely meshed plane under
// a square occluder, light and occluder tilted together (parallel), so that
// ss::ParallelRectOccluderVisibility gives the exact visible fraction.
#include "vtkLightVisibilityFilter.h"

#include "ssAnalytic.h"
#include "ssLightFrame.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSoftShadowLight.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace
{
struct Scene
{
  ss::LightFrame light;
  std::array<glm::dvec3, 4> occluder;
  vtkSmartPointer<vtkPolyData> plane;
  vtkSmartPointer<vtkPolyData> casters;
};

// Light 4 above a 4 x 4 plane, tilted by about 25 degrees; a 1.2 x 1.2 square
// parallel to it, 2.2 below it along its normal (between light and plane).
Scene MakeScene(int resolution)
{
  Scene s;
  const glm::dvec3 center(0.4, -0.3, 4.0);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(0.35, -0.25, -1.0));
  s.light = ss::MakeRectLightFrame(center, normal, glm::dvec3(0.2, 1.0, 0.0), glm::dvec2(1.6, 1.0));
  const glm::dvec3 oc = center + 2.2 * normal + 0.1 * s.light.u;
  const double h = 0.6;
  s.occluder = { oc - h * s.light.u - h * s.light.v, oc + h * s.light.u - h * s.light.v,
    oc + h * s.light.u + h * s.light.v, oc - h * s.light.u + h * s.light.v };
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-2, -2, 0);
  plane->SetPoint1(2, -2, 0);
  plane->SetPoint2(-2, 2, 0);
  plane->SetResolution(resolution, resolution);
  plane->Update();
  s.plane = plane->GetOutput();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (const auto& c : s.occluder)
  {
    pts->InsertNextPoint(c.x, c.y, c.z);
  }
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = { 0, 1, 2, 3 };
  polys->InsertNextCell(4, quad); // a polygon: the filter cuts it
  s.casters = vtkSmartPointer<vtkPolyData>::New();
  s.casters->SetPoints(pts);
  s.casters->SetPolys(polys);
  return s;
}

class ProgressRecorder : public vtkCommand
{
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject*, unsigned long, void* data) override { values.push_back(*static_cast<double*>(data)); }
  std::vector<double> values;
};

class ErrorRecorder : public vtkCommand
{
public:
  static ErrorRecorder* New() { return new ErrorRecorder; }
  void Execute(vtkObject*, unsigned long, void* data) override { text += static_cast<const char*>(data); }
  std::string text;
};

// LightVisibility_0 of a bake (empty when it has none).
std::vector<double> BakedValues(vtkPolyData* out)
{
  vtkDataArray* v = out->GetPointData()->GetArray("LightVisibility_0");
  std::vector<double> values;
  for (vtkIdType i = 0; v && i < v->GetNumberOfTuples(); ++i)
  {
    values.push_back(v->GetComponent(i, 0));
  }
  return values;
}

struct Errors
{
  double maeExact = 0, maxExact = 0, maeSampled = 0, maxSampled = 0;
  std::size_t penumbra = 0;
};

Errors Compare(const Scene& s, vtkDataArray* v, int k)
{
  Errors e;
  const vtkIdType n = s.plane->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    s.plane->GetPoint(i, p);
    const glm::dvec3 x(p[0], p[1], p[2]);
    const double exact = ss::ParallelRectOccluderVisibility(s.light, s.occluder, x);
    const double sampled = ss::ParallelRectOccluderVisibilitySampled(s.light, s.occluder, x, k);
    const double got = v->GetComponent(i, 0);
    EXPECT_TRUE(std::isfinite(got)) << "point " << i;
    e.maeExact += std::abs(got - exact) / n;
    e.maxExact = std::max(e.maxExact, std::abs(got - exact));
    e.maeSampled += std::abs(got - sampled) / n;
    e.maxSampled = std::max(e.maxSampled, std::abs(got - sampled));
    e.penumbra += (exact > 0.01 && exact < 0.99) ? 1 : 0;
  }
  return e;
}
}

// The measured errors when this test was written (k = 16, 201 x 201 points,
// 8,405 of them in the penumbra): against the exact fraction MAE 3.1e-3 (max
// 0.056: the 16 x 16 samples' quantisation); against the same 16 x 16
// samples MAE 5.5e-6 (max 1/16: a row of samples grazing an edge), the same
// for GEARS and the reference.
TEST(LightVisibilityFilter, PlaneUnderATiltedSquareMatchesTheExactVisibleFraction)
{
  const Scene s = MakeScene(200);
  for (int method : { vtkLightVisibilityFilter::METHOD_GEARS, vtkLightVisibilityFilter::METHOD_REFERENCE })
  {
    vtkNew<vtkLightVisibilityFilter> f;
    f->SetInputData(s.plane);
    f->SetCasterData(s.casters);
    f->SetMethod(method);
    f->SetSamples(16);
    f->SetLightCenter(s.light.center.x, s.light.center.y, s.light.center.z);
    f->SetLightNormal(s.light.n.x, s.light.n.y, s.light.n.z);
    f->SetLightUp(s.light.v.x, s.light.v.y, s.light.v.z);
    f->SetLightSize(s.light.width, s.light.height);
    vtkNew<ProgressRecorder> progress;
    f->AddObserver(vtkCommand::ProgressEvent, progress);
    f->Update();
    vtkDataArray* v = f->GetOutput()->GetPointData()->GetArray("LightVisibility_0");
    ASSERT_NE(v, nullptr);
    ASSERT_EQ(v->GetNumberOfTuples(), s.plane->GetNumberOfPoints());
    const Errors e = Compare(s, v, 16);
    EXPECT_GT(e.penumbra, 2000u); // a real penumbra on the plane
    EXPECT_LT(e.maeExact, 5e-3) << "method " << method;
    EXPECT_LT(e.maxExact, 0.07) << "method " << method;
    EXPECT_LT(e.maeSampled, 1e-4) << "method " << method;
    // the occluder's edges run along the light's sample rows, so at most a
    // row of samples grazes an edge at once
    EXPECT_LE(e.maxSampled, 1.0 / 16.0 + 1e-6) << "method " << method;
    std::cout << "method " << method << ": MAE vs exact " << e.maeExact << " (max " << e.maxExact
              << "), vs the same samples " << e.maeSampled << " (max " << e.maxSampled << "), "
              << e.penumbra << " penumbra points\n";
    ASSERT_FALSE(progress->values.empty());
    EXPECT_DOUBLE_EQ(progress->values.back(), 1.0);
    // the input's own arrays pass through
    EXPECT_NE(f->GetOutput()->GetPointData()->GetNormals(), nullptr);
  }
}

// More samples, smaller error: the bake converges to the exact fraction.
TEST(LightVisibilityFilter, ErrorFallsWithMoreSamples)
{
  const Scene s = MakeScene(80);
  double previous = 1.0;
  for (int k : { 2, 8, 32 })
  {
    vtkNew<vtkLightVisibilityFilter> f;
    f->SetInputData(s.plane);
    f->SetCasterData(s.casters);
    f->SetSamples(k);
    f->SetLightCenter(s.light.center.x, s.light.center.y, s.light.center.z);
    f->SetLightNormal(s.light.n.x, s.light.n.y, s.light.n.z);
    f->SetLightUp(s.light.v.x, s.light.v.y, s.light.v.z);
    f->SetLightSize(s.light.width, s.light.height);
    f->Update();
    const Errors e = Compare(s, f->GetOutput()->GetPointData()->GetArray("LightVisibility_0"), k);
    EXPECT_LT(e.maeExact, previous) << "k = " << k;
    EXPECT_LT(e.maeSampled, 1e-4) << "k = " << k;
    previous = e.maeExact;
  }
}

// Lights from a collection, as the CLI passes a scene's: a rect light (the
// same V as from the properties), a switched-off light (no array, its index
// skipped) and a point light (0 or 1).
TEST(LightVisibilityFilter, LightsFromACollection)
{
  const Scene s = MakeScene(60);
  vtkNew<vtkLight> rect;
  rect->SetPositional(true);
  rect->SetPosition(s.light.center.x, s.light.center.y, s.light.center.z);
  rect->SetFocalPoint(s.light.center.x + s.light.n.x, s.light.center.y + s.light.n.y, s.light.center.z + s.light.n.z);
  vtkSoftShadowLight::SetAreaSize(rect, s.light.width, s.light.height);
  vtkSoftShadowLight::SetAreaUp(rect, s.light.v.x, s.light.v.y, s.light.v.z);
  vtkNew<vtkLight> off;
  off->SetSwitch(false);
  vtkNew<vtkLight> point;
  point->SetPositional(true);
  point->SetPosition(0.4, -0.3, 4.0);
  point->SetFocalPoint(0.4, -0.3, 0.0);
  vtkNew<vtkLightCollection> lights;
  lights->AddItem(rect);
  lights->AddItem(off);
  lights->AddItem(point);
  vtkNew<vtkLightVisibilityFilter> f;
  f->SetInputData(s.plane);
  f->SetCasterData(s.casters);
  f->SetLights(lights);
  f->Update();
  vtkPointData* pd = f->GetOutput()->GetPointData();
  ASSERT_NE(pd->GetArray("LightVisibility_0"), nullptr);
  EXPECT_EQ(pd->GetArray("LightVisibility_1"), nullptr);
  ASSERT_NE(pd->GetArray("LightVisibility_2"), nullptr);
  const Errors e = Compare(s, pd->GetArray("LightVisibility_0"), 16);
  EXPECT_LT(e.maeSampled, 1e-4);
  vtkDataArray* hard = pd->GetArray("LightVisibility_2");
  std::size_t dark = 0;
  for (vtkIdType i = 0; i < hard->GetNumberOfTuples(); ++i)
  {
    const double v = hard->GetComponent(i, 0);
    ASSERT_TRUE(v == 0.0 || v == 1.0);
    dark += v == 0.0 ? 1 : 0;
  }
  EXPECT_GT(dark, 50u);
  // changing a light re-executes the filter (its MTime counts)
  const vtkMTimeType before = f->GetMTime();
  vtkSoftShadowLight::SetAreaSize(rect, 0.1, 0.1);
  EXPECT_GT(f->GetMTime(), before);
}

// Translucent casters let light through; a missing opacity array and a zero
// light normal are errors, not silently wrong arrays.
TEST(LightVisibilityFilter, OpacityAndBadInput)
{
  Scene s = MakeScene(40);
  vtkNew<vtkFloatArray> opacity;
  opacity->SetName("Opacity");
  opacity->InsertNextValue(0.25f);
  s.casters->GetCellData()->AddArray(opacity);
  vtkNew<vtkLightVisibilityFilter> f;
  f->SetInputData(s.plane);
  f->SetCasterData(s.casters);
  f->SetOpacityArrayName("Opacity");
  f->SetLightCenter(s.light.center.x, s.light.center.y, s.light.center.z);
  f->SetLightNormal(s.light.n.x, s.light.n.y, s.light.n.z);
  f->SetLightSize(0.0, 0.0); // a point light: umbra points see 1 - 0.25
  f->Update();
  vtkDataArray* v = f->GetOutput()->GetPointData()->GetArray("LightVisibility_0");
  ASSERT_NE(v, nullptr);
  std::size_t shaded = 0;
  for (vtkIdType i = 0; i < v->GetNumberOfTuples(); ++i)
  {
    const double x = v->GetComponent(i, 0);
    ASSERT_TRUE(std::abs(x - 1.0) < 1e-6 || std::abs(x - 0.75) < 1e-6) << x;
    shaded += std::abs(x - 0.75) < 1e-6 ? 1 : 0;
  }
  EXPECT_GT(shaded, 10u);

  vtkNew<ErrorRecorder> errors;
  f->AddObserver(vtkCommand::ErrorEvent, errors);
  f->SetOpacityArrayName("NoSuchArray");
  f->Update();
  EXPECT_NE(errors->text.find("NoSuchArray"), std::string::npos);
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("LightVisibility_0"), nullptr);
  errors->text.clear();
  f->SetOpacityArrayName(nullptr);
  f->SetLightNormal(0, 0, 0);
  f->SetLightSize(1, 1);
  f->Update();
  EXPECT_NE(errors->text.find("LightNormal"), std::string::npos);
  // a negative size is refused like a NaN one (it was baked as a point light)
  errors->text.clear();
  f->SetLightNormal(0, 0, -1);
  f->SetLightSize(-1, -1);
  f->Update();
  EXPECT_NE(errors->text.find("LightSize"), std::string::npos) << errors->text;
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("LightVisibility_0"), nullptr);
  // a light beyond 1e30 is refused: its shadow vanished in the solvers'
  // squares (GEARS from 1e37, both from 1e155)
  errors->text.clear();
  f->SetLightSize(1, 1);
  f->SetLightCenter(0, 0, 1e37);
  f->Update();
  EXPECT_NE(errors->text.find("farther than 1e30"), std::string::npos) << errors->text;
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("LightVisibility_0"), nullptr);
}

// One point the solvers cannot take (infinite, or beyond the float range)
// gets NaN; every other point keeps its value. Before (stop 45's Python
// sweep) the float origin was the bounds' centre, infinite then, and every
// value came out NaN; and the input's triangles at the 1e39 point (the input
// casts shadows) were kept as casters, inf in float, which hid the light
// from every point.
// A tilted rect light of any size bakes as one of 1e30 (ss::ClampRectLightSize,
// as the render pass does): the same shadow. Before stop 53 the reference's
// sample distances overflowed when squared from a side of about 1.5e155, its
// rays had no direction and hit nothing: V = 1 where GEARS gives 0.48.
TEST(LightVisibilityFilter, AHugeRectLightBakesAsOneOf1e30)
{
  Scene s = MakeScene(12);
  for (const int method : { vtkLightVisibilityFilter::METHOD_GEARS, vtkLightVisibilityFilter::METHOD_REFERENCE })
  {
    SCOPED_TRACE(method);
    auto bake = [&](double side) {
      vtkNew<vtkLightVisibilityFilter> f;
      f->SetInputData(s.plane);
      f->SetCasterData(s.casters);
      f->SetMethod(method);
      f->SetSamples(4);
      f->SetLightCenter(0.0, 0.0, 3.0);
      f->SetLightNormal(0.5, 0.0, -1.0);
      f->SetLightUp(0.0, 1.0, 0.0);
      f->SetLightSize(side, side);
      f->Update();
      return BakedValues(f->GetOutput());
    };
    const std::vector<double> a = bake(1e30), b = bake(1e160);
    ASSERT_EQ(a.size(), static_cast<std::size_t>(s.plane->GetNumberOfPoints()));
    ASSERT_EQ(b.size(), a.size());
    std::size_t shaded = 0, differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      shaded += a[i] < 0.99 ? 1 : 0;
      differ += std::abs(a[i] - b[i]) > 1e-6 ? 1 : 0;
    }
    EXPECT_GT(shaded, a.size() / 10); // the caster shadows a half space's light
    EXPECT_EQ(differ, 0u);
  }
}

// An input without points (a threshold that kept nothing) gets the arrays,
// empty, so that colouring or thresholding by them downstream finds them.
TEST(LightVisibilityFilter, AnEmptyInputGetsEmptyArrays)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkLightVisibilityFilter> f;
  f->SetInputData(empty);
  f->Update();
  vtkDataArray* v = f->GetOutput()->GetPointData()->GetArray("LightVisibility_0");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->GetNumberOfTuples(), 0);
}

TEST(LightVisibilityFilter, AnInfinitePointSpoilsOnlyItself)
{
  for (const int method : { vtkLightVisibilityFilter::METHOD_GEARS, vtkLightVisibilityFilter::METHOD_REFERENCE })
  {
    SCOPED_TRACE(method);
    Scene s = MakeScene(20);
    auto bake = [&](vtkPolyData* input) {
      vtkNew<vtkLightVisibilityFilter> f;
      f->SetInputData(input);
      f->SetCasterData(s.casters);
      f->SetMethod(method);
      f->SetSamples(8);
      f->SetLightCenter(s.light.center.x, s.light.center.y, s.light.center.z);
      f->SetLightNormal(s.light.n.x, s.light.n.y, s.light.n.z);
      f->SetLightUp(s.light.v.x, s.light.v.y, s.light.v.z);
      f->SetLightSize(1.6, 1.0);
      f->Update();
      return BakedValues(f->GetOutput());
    };
    const std::vector<double> clean = bake(s.plane);
    vtkNew<vtkPolyData> spoiled;
    spoiled->DeepCopy(s.plane);
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->DeepCopy(s.plane->GetPoints());
    pts->SetPoint(7, std::numeric_limits<double>::infinity(), 0.0, 0.0);
    pts->SetPoint(300, 1e39, 0.0, 0.0);
    spoiled->SetPoints(pts);
    const std::vector<double> got = bake(spoiled);
    ASSERT_EQ(got.size(), clean.size());
    std::size_t nan = 0, shaded = 0, equal = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
    {
      nan += std::isnan(got[i]) ? 1 : 0;
      shaded += clean[i] < 0.5 ? 1 : 0;
      // (points next to the two moved ones may get other normals)
      equal += std::abs(got[i] - clean[i]) < 1e-6 ? 1 : 0;
    }
    EXPECT_TRUE(std::isnan(got[7]) && std::isnan(got[300]));
    EXPECT_EQ(nan, 2u);
    EXPECT_GT(shaded, 20u);
    EXPECT_GE(equal, got.size() - 20);
  }
}
