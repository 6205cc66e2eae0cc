// The render pass with prepared casters (vtkShadowCasterPreparation upstream,
// Documentation/filters.md): the caster set takes its clusters from the
// preparation's cluster table and GEARS its closed pieces, and neither the
// culling nor the pieces change what any pixel sees. And with plain casters:
// GEARS' closed pieces found by the pass itself (gears_find_pieces), which
// change no pixel either.
#include "ssRenderTestUtilities.h"

#include "vtkAppendPolyData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkPolyDataMapper.h"
#include "vtkShadowCasterPreparation.h"
#include "vtkTransform.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace sstest;

namespace
{
// A field of closed spheres and boxes (25 pieces), prepared, with clusters of
// at most 64 triangles so that tiles and cells have many to choose from.
vtkSmartPointer<vtkPolyData> PreparedField()
{
  vtkNew<vtkAppendPolyData> append;
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 5; ++i)
    {
      if ((i + j) % 2)
      {
        vtkNew<vtkSphereSource> s;
        s->SetCenter(-4 + 2 * i, -4 + 2 * j, 0.6 + 0.1 * ((i + j) % 3));
        s->SetRadius(0.45);
        s->SetThetaResolution(32);
        s->SetPhiResolution(16);
        append->AddInputConnection(s->GetOutputPort());
      }
      else
      {
        vtkNew<vtkCubeSource> c;
        c->SetCenter(-4 + 2 * i, -4 + 2 * j, 0.7);
        c->SetXLength(0.7);
        c->SetYLength(0.5);
        c->SetZLength(0.9);
        append->AddInputConnection(c->GetOutputPort());
      }
    }
  }
  vtkNew<vtkShadowCasterPreparation> prep;
  prep->SetInputConnection(append->GetOutputPort());
  prep->SetMaximumClusterTriangles(64);
  prep->Update();
  return prep->GetOutput();
}

// The same triangles without the cluster table (what a user who did not run
// the filter would give): the pass falls back to Morton clusters, no pieces.
vtkSmartPointer<vtkPolyData> Stripped(vtkPolyData* prepared)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->ShallowCopy(prepared);
  pd->SetFieldData(vtkSmartPointer<vtkFieldData>::New());
  return pd;
}

double Number(const std::string& js, const std::string& key, std::size_t from = 0)
{
  const std::size_t at = js.find("\"" + key + "\": ", from);
  return at == std::string::npos ? -1.0 : std::stod(js.substr(at + key.size() + 4));
}

std::string Text(const std::string& js, const std::string& key, std::size_t from = 0)
{
  const std::size_t at = js.find("\"" + key + "\": \"", from);
  if (at == std::string::npos)
  {
    return {};
  }
  const std::size_t b = at + key.size() + 5;
  return js.substr(b, js.find('"', b) - b);
}

struct Result
{
  Frame frame;
  std::string stats;
};

// Ground + the field (rotated, scaled and moved by the actor's matrix), a
// rect light, a close-up camera; `setup` picks the method and its options.
// camera: position, focal point, view angle
const std::vector<double> kFieldCamera = { 0, -6.5, 3.2, 0, -1.5, 0, 40.0 };
// two close-ups of the field: its visible receivers are a small part of the light's view
const std::vector<double> kCloseUp = { 0.6, -3.4, 2.0, 0.2, -0.6, 0.2, 35.0 };
const std::vector<double> kCloseUpLow = { -1.5, -3.0, 1.8, -1.8, 0.2, 0.3, 30.0 };
Result RenderField(vtkPolyData* casters, const std::function<void(vtkSoftShadowPass*)>& setup, double opacity = 1.0,
  int w = 240, int h = 180, const std::vector<double>& camera = kFieldCamera)
{
  Scene s(w, h);
  s.renderer->AddActor(Ground(7.0));
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(casters);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetOpacity(opacity);
  vtkNew<vtkTransform> t;
  t->Translate(0.2, -0.1, 0.05);
  t->RotateZ(17.0);
  t->Scale(1.1, 1.1, 1.1);
  actor->SetUserTransform(t);
  s.renderer->AddActor(actor);
  s.renderer->AddLight(RectLight(0.5, -0.5, 6, 0, 0, 0, 2.5, 2.5));
  s.Camera(camera[0], camera[1], camera[2], camera[3], camera[4], camera[5], camera[6]);
  setup(s.pass);
  Result r;
  r.frame = s.Render();
  r.stats = s.pass->GetStatsJSON();
  return r;
}

// The field at 240 x 180 with a culling off (r[0]) and on (r[1]).
std::array<Result, 2> OffAndOn(vtkPolyData* casters, const std::function<void(vtkSoftShadowPass*, bool)>& setup,
  double opacity = 1.0, const std::vector<double>& camera = kFieldCamera)
{
  std::array<Result, 2> r;
  for (int on = 0; on < 2; ++on)
  {
    r[on] = RenderField(
      casters, [&](vtkSoftShadowPass* p) { setup(p, on != 0); }, opacity, 240, 180, camera);
  }
  return r;
}

// Equal V on every pixel; the number of shadowed pixels.
std::size_t ExpectSameV(const Frame& a, const Frame& b, const std::string& what, double tolerance = 0.0)
{
  EXPECT_EQ(a.V.size(), b.V.size()) << what;
  std::size_t shadowed = 0, differ = 0;
  double maxDiff = 0.0;
  for (std::size_t i = 0; i < std::min(a.V.size(), b.V.size()); ++i)
  {
    EXPECT_EQ(std::isnan(a.V[i]), std::isnan(b.V[i])) << what << " pixel " << i;
    if (!std::isnan(a.V[i]))
    {
      shadowed += a.V[i] < 0.5f;
      const double d = std::abs(double(a.V[i]) - b.V[i]);
      maxDiff = std::max(maxDiff, d);
      differ += d > 0.0;
    }
  }
  std::cout << what << ": max |dV| " << maxDiff << ", " << differ << " pixels differ, " << shadowed
            << " shadowed\n";
  EXPECT_LE(maxDiff, tolerance) << what;
  EXPECT_GT(shadowed, 500u) << what;
  return shadowed;
}
}

// The caster set reads the table: PVSM's tiles report prepared clusters,
// their number is the table's, and some are culled; without the table the
// same triangles get Morton clusters.
TEST(PreparedCasters, ClustersComeFromTheTable)
{
  const auto prepared = PreparedField();
  const double tableClusters = prepared->GetFieldData()->GetArray("ClusterRange")->GetNumberOfTuples();
  ASSERT_GT(tableClusters, 25.0);
  const auto pvsm = [](vtkSoftShadowPass* p) { p->SetMethod(vtkSoftShadowPass::PVSM); };
  const Result a = RenderField(prepared, pvsm);
  const std::size_t at = a.stats.find("\"tile_clusters\"");
  ASSERT_NE(at, std::string::npos) << a.stats;
  EXPECT_EQ(Text(a.stats, "source", at), "prepared");
  EXPECT_EQ(Number(a.stats, "prepared_clusters", at), tableClusters);
  // the table's clusters and one Morton cluster of the ground
  EXPECT_EQ(Number(a.stats, "clusters", at), tableClusters + 1);
  EXPECT_GT(Number(a.stats, "culled", at), 0.0);
  EXPECT_GT(Number(a.stats, "drawn", at), 0.0);
  const Result b = RenderField(Stripped(prepared), pvsm);
  const std::size_t bt = b.stats.find("\"tile_clusters\"");
  EXPECT_EQ(Text(b.stats, "source", bt), "morton");
  EXPECT_EQ(Number(b.stats, "prepared_clusters", bt), 0.0);
  ExpectSameV(a.frame, b.frame, "pvsm prepared vs morton clusters");
}

// The culling changes no pixel, for each method that culls: PVSM tiles
// (PVSMTileCulling), ASM cells and the AVSM build's views (CasterCulling).
TEST(PreparedCasters, CullingKeepsVForEachMethod)
{
  const auto prepared = PreparedField();
  struct Case
  {
    const char* method;
    double opacity;
    std::function<void(vtkSoftShadowPass*, bool)> culling;
    const char* key;  // the stats object with the counts
    bool expectCulls; // the AVSM views are fitted to every caster: nothing to cull in this scene
  };
  const Case cases[] = {
    { "pvsm", 1.0, [](vtkSoftShadowPass* p, bool on) { p->SetPVSMTileCulling(on); }, "tile_clusters", true },
    { "asm", 1.0,
      [](vtkSoftShadowPass* p, bool on) {
        p->SetCasterCulling(on);
        p->SetASMTimeBudget(1e5); // every node the analysis asks for, whatever the clock says
      },
      "cell_clusters", true },
    { "avsm", 0.6, [](vtkSoftShadowPass* p, bool on) { p->SetCasterCulling(on); }, "view_clusters", false },
  };
  for (const Case& c : cases)
  {
    const auto r = OffAndOn(
      prepared,
      [&](vtkSoftShadowPass* p, bool on) {
        ASSERT_TRUE(p->SetMethodByName(c.method));
        c.culling(p, on);
      },
      c.opacity);
    ExpectSameV(r[0].frame, r[1].frame, std::string(c.method) + " culling off vs on");
    const std::size_t at = r[1].stats.find(std::string("\"") + c.key + "\"");
    ASSERT_NE(at, std::string::npos) << c.method << ": " << r[1].stats;
    EXPECT_EQ(Text(r[1].stats, "source", at), "prepared") << c.method;
    if (c.expectCulls)
    {
      EXPECT_GT(Number(r[1].stats, "culled", at), 0.0) << c.method << ": " << r[1].stats.substr(at, 200);
    }
    EXPECT_GT(Number(r[1].stats, "drawn", at), 0.0) << c.method << ": " << r[1].stats.substr(at, 200);
    const std::size_t off = r[0].stats.find(std::string("\"") + c.key + "\"");
    EXPECT_EQ(Number(r[0].stats, "culled", off), 0.0) << c.method << " without culling";
  }
}

// PVSM's conservative low-resolution map drawn with only the clusters that
// may reach the texels the visible receivers' blocker searches read
// (pvsm_map_culling, ss::BlockerSearchWindows): on close-ups, whose visible
// receivers are a small part of the light's view, V is the same on every
// pixel with and without it, and most clusters are left out of the map. Also
// with a coarse map (large texels, coarse search cells) and a large normal
// offset, which widen what the search reads.
TEST(PreparedCasters, MapCullingKeepsVOnCloseUps)
{
  const auto prepared = PreparedField();
  struct Case
  {
    const char* what;
    int lowResolution;
    double normalOffset;
    std::vector<double> camera;
  };
  const Case cases[] = {
    { "close-up", 1024, 0.0, kCloseUp },
    { "close-up, 256 map, normal offset 4", 256, 4.0, kCloseUpLow },
  };
  for (const Case& c : cases)
  {
    const auto r = OffAndOn(
      prepared,
      [&](vtkSoftShadowPass* p, bool on) {
        p->SetMethod(vtkSoftShadowPass::PVSM);
        p->SetSolverOption("pvsm_map_culling", on ? 1 : 0);
        p->SetSolverOption("pvsm_low_resolution", c.lowResolution);
        p->SetNormalOffset(c.normalOffset);
      },
      1.0, c.camera);
    ExpectSameV(r[0].frame, r[1].frame, std::string("pvsm map culling off vs on, ") + c.what);
    const std::size_t at = r[1].stats.find("\"map_clusters\"");
    ASSERT_NE(at, std::string::npos) << r[1].stats;
    const double drawn = Number(r[1].stats, "drawn", at), culled = Number(r[1].stats, "culled", at);
    std::cout << c.what << ": map clusters drawn " << drawn << ", culled " << culled << "\n";
    EXPECT_GT(drawn, 0.0) << c.what;
    EXPECT_GT(culled, 0.3 * (drawn + culled)) << c.what;
    const std::size_t off = r[0].stats.find("\"map_clusters\"");
    EXPECT_EQ(Number(r[0].stats, "culled", off), 0.0) << c.what << " without map culling";
  }
}

// Each tile cleared, drawn, reduced and filtered only where the pixels whose
// kernel reaches it read it, and not at all when none does
// (pvsm_tile_regions, ss::PVSMTileReads): V is the same on every pixel with
// and without it, on the field's camera and two close-ups, also with small
// tiles (many tile edges) and coarse filter quads (reads at high pyramid
// levels), and fewer texels are drawn.
TEST(PreparedCasters, TileRegionsKeepV)
{
  const auto prepared = PreparedField();
  struct Case
  {
    const char* what;
    int maxTile, maxQuads;
    std::vector<double> camera;
  };
  const Case cases[] = {
    { "field camera", 4096, 24, kFieldCamera },
    { "close-up", 4096, 24, kCloseUp },
    { "close-up, tiles of 256, 4 quads", 256, 4, kCloseUpLow },
    { "field camera, tiles of 128, 6 quads", 128, 6, kFieldCamera },
  };
  for (const Case& c : cases)
  {
    const auto r = OffAndOn(
      prepared,
      [&](vtkSoftShadowPass* p, bool on) {
        p->SetMethod(vtkSoftShadowPass::PVSM);
        p->SetSolverOption("pvsm_tile_regions", on ? 1 : 0);
        p->SetSolverOption("pvsm_max_tile", c.maxTile);
        p->SetSolverOption("filter_max_quads", c.maxQuads);
      },
      1.0, c.camera);
    ExpectSameV(r[0].frame, r[1].frame, std::string("pvsm tile regions off vs on, ") + c.what);
    // (PVSM's own stats: they follow its "high_res_sms" time)
    const std::size_t off = r[0].stats.find("\"high_res_sms\""), on = r[1].stats.find("\"high_res_sms\"");
    ASSERT_NE(off, std::string::npos) << r[0].stats;
    ASSERT_NE(on, std::string::npos) << r[1].stats;
    const auto get = [&](int i, const char* key) { return Number(r[i].stats, key, i ? on : off); };
    std::cout << c.what << ": " << get(1, "tiles") << " tiles, " << get(1, "tiles_skipped")
              << " skipped; texels drawn " << get(0, "texels_rendered") << " -> " << get(1, "texels_rendered")
              << "; filter pixels " << get(0, "filter_pixels") << " -> " << get(1, "filter_pixels") << "\n";
    EXPECT_EQ(get(0, "texels_rendered"), get(0, "tile_texels")) << c.what;
    EXPECT_EQ(get(0, "tile_texels"), get(1, "tile_texels")) << c.what;
    EXPECT_EQ(get(0, "tiles_skipped"), 0.0) << c.what;
    EXPECT_LT(get(1, "texels_rendered"), get(0, "texels_rendered")) << c.what;
    EXPECT_LT(get(1, "filter_pixels"), get(0, "filter_pixels")) << c.what;
  }
}

// GEARS with the closed pieces of prepared casters (the closed-mesh rule and
// inner occluders) sees exactly what it sees without them, and has no more
// (triangle, cell) pairs to do.
TEST(PreparedCasters, GearsPiecesKeepVAndDropPairs)
{
  const auto prepared = PreparedField();
  const auto gears = [](vtkSoftShadowPass* p) {
    p->SetMethod(vtkSoftShadowPass::GEARS);
    p->SetGearsSamples(8);
  };
  const Result with = RenderField(prepared, gears);
  const Result without = RenderField(Stripped(prepared), [&](vtkSoftShadowPass* p) {
    gears(p);
    p->GearsFindPiecesOff(); // no pieces at all: the plain triangles
  });
  ExpectSameV(with.frame, without.frame, "gears with vs without closed pieces");
  const double pairsWith = Number(with.stats, "pairs"), pairsWithout = Number(without.stats, "pairs");
  const double droppedWith = Number(with.stats, "dropped_triangles");
  std::cout << "gears pairs with pieces " << pairsWith << ", without " << pairsWithout << "; dropped "
            << droppedWith << "\n";
  EXPECT_GT(droppedWith, 0.0);
  EXPECT_EQ(Number(without.stats, "dropped_triangles"), 0.0);
  EXPECT_GT(pairsWithout, 0.0);
  EXPECT_LT(pairsWith, pairsWithout);
}

// A mirrored actor turns the outward pieces inward: the pass must not cull
// or drop on the table's word then, and V stays that of the plain triangles.
TEST(PreparedCasters, MirroredActorKeepsV)
{
  const auto prepared = PreparedField();
  const auto mirrored = [](vtkPolyData* pd, const std::function<void(vtkSoftShadowPass*)>& setup) {
    Scene s(200, 150);
    s.renderer->AddActor(Ground(7.0));
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->SetScale(-1.0, 1.0, 1.0);
    s.renderer->AddActor(actor);
    s.renderer->AddLight(RectLight(0.5, -0.5, 6, 0, 0, 0, 2.5, 2.5));
    s.Camera(0, -6.5, 3.2, 0, -1.5, 0, 40.0);
    setup(s.pass);
    return s.Render();
  };
  for (const char* method : { "gears", "pvsm" })
  {
    const auto setup = [&](vtkSoftShadowPass* p) {
      ASSERT_TRUE(p->SetMethodByName(method));
      p->SetGearsSamples(8);
    };
    ExpectSameV(mirrored(prepared, setup), mirrored(Stripped(prepared), setup),
      std::string(method) + " mirrored, prepared vs plain");
  }
}

namespace
{
// Plain casters as a VTK user gives them (no preparation): a sphere, a box
// (vtkCubeSource: quads whose corners are repeated per face, so it is closed
// only through the exact weld) and one actor holding a sphere and a box (two
// pieces in one block), over a ground that casts too (open). Every actor's
// matrix scales x by `mirror` (-1: a mirror, det < 0). `frames` renders, the
// camera turning between them (the casters stay).
Result RenderPlain(const std::function<void(vtkSoftShadowPass*)>& setup, double mirror = 1.0, int frames = 1,
  bool open = false)
{
  Scene s(240, 180);
  s.renderer->AddActor(Ground(7.0));
  std::vector<vtkSmartPointer<vtkActor>> actors;
  if (open)
  {
    // a hemisphere (a bowl open at its rim) and a tilted square
    vtkNew<vtkSphereSource> bowl;
    bowl->SetCenter(-1.0, -0.5, 1.2);
    bowl->SetRadius(0.7);
    bowl->SetThetaResolution(32);
    bowl->SetPhiResolution(16);
    bowl->SetEndPhi(90.0);
    actors.push_back(MakeActor(bowl));
    vtkNew<vtkPlaneSource> square;
    square->SetOrigin(0.5, -0.8, 0.6);
    square->SetPoint1(1.6, -0.8, 1.0);
    square->SetPoint2(0.5, 0.4, 0.6);
    square->SetResolution(4, 4);
    actors.push_back(MakeActor(square));
  }
  else
  {
    actors.push_back(Sphere(-1.6, -0.6, 1.0, 0.6));
    actors.push_back(Box(1.1, 0.1, 0.6, 0.8, 0.6, 1.0));
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(0.2, -2.0, 0.5);
    sphere->SetRadius(0.4);
    vtkNew<vtkCubeSource> cube;
    cube->SetCenter(-0.3, 1.2, 0.8);
    vtkNew<vtkAppendPolyData> both;
    both->AddInputConnection(sphere->GetOutputPort());
    both->AddInputConnection(cube->GetOutputPort());
    actors.push_back(MakeActor(both));
  }
  for (auto& a : actors)
  {
    a->SetScale(mirror, 1.0, 1.0);
    s.renderer->AddActor(a);
  }
  s.renderer->AddLight(RectLight(0.5, -0.5, 6, 0, 0, 0, 2.5, 2.5));
  s.Camera(0, -6.5, 3.2, 0, -0.8, 0, 40.0);
  setup(s.pass);
  Result r;
  for (int f = 0; f < frames; ++f)
  {
    // the camera turns a little (an unchanged view would reuse V unsolved)
    s.renderer->GetActiveCamera()->Azimuth(f > 0 ? 3.0 : 0.0);
    r.frame = s.Render();
  }
  r.stats = s.pass->GetStatsJSON();
  return r;
}

const auto kGears = [](vtkSoftShadowPass* p) {
  p->SetMethod(vtkSoftShadowPass::GEARS);
  p->SetGearsSamples(8);
};
const auto kGearsWithoutPieces = [](vtkSoftShadowPass* p) {
  kGears(p);
  p->GearsFindPiecesOff();
};

// GEARS' assignments (Table 9's total) in the pass's stats
double Assignments(const std::string& js)
{
  return Number(js, "total", js.find("\"assignments\": {", js.find("\"gears\": {\"samples_per_axis")));
}
}

// The pass finds the closed pieces of plain casters itself, once per caster
// set: GEARS sees exactly what it sees without them, with fewer pairs; the
// stats count the four closed pieces (not the ground).
TEST(UnpreparedCasters, GearsFindsClosedPiecesKeepsVDropsPairs)
{
  const Result with = RenderPlain(kGears, 1.0, 3);
  const Result without = RenderPlain(kGearsWithoutPieces, 1.0, 3);
  ExpectSameV(with.frame, without.frame, "gears, plain casters, pieces found vs none");
  std::cout << with.stats.substr(with.stats.find("\"pieces\": {\"find")) << "\n";
  EXPECT_EQ(Number(with.stats, "closed_pieces"), 4.0);
  EXPECT_GT(Number(with.stats, "closed_triangles"), 0.0);
  EXPECT_EQ(Number(with.stats, "solver_closed_triangles"), Number(with.stats, "closed_triangles"));
  EXPECT_EQ(Number(without.stats, "closed_pieces"), 0.0);
  // the last frame solved with the pieces found in the first (the caster set did not change)
  EXPECT_NE(with.stats.find("\"found_this_frame\": false"), std::string::npos);
  const double pairsWith = Number(with.stats, "pairs"), pairsWithout = Number(without.stats, "pairs");
  const double listedWith = Assignments(with.stats), listedWithout = Assignments(without.stats);
  std::cout << "pairs with found pieces " << pairsWith << ", without " << pairsWithout << "; assignments "
            << listedWith << " vs " << listedWithout << "\n";
  EXPECT_GT(Number(with.stats, "dropped_triangles"), 0.0);
  EXPECT_EQ(Number(without.stats, "dropped_triangles"), 0.0);
  EXPECT_LT(pairsWith, pairsWithout);
  EXPECT_LT(listedWith, listedWithout);
}

// Under a mirror (det < 0) the same pieces come out inward (-1); GEARS must
// still see what the plain triangles give, and what the reference's own
// regular samples give.
TEST(UnpreparedCasters, MirroredActorsKeepV)
{
  const Result with = RenderPlain(kGears, -1.0);
  const Result without = RenderPlain(kGearsWithoutPieces, -1.0);
  ExpectSameV(with.frame, without.frame, "gears, mirrored plain casters, pieces found vs none");
  EXPECT_EQ(Number(with.stats, "closed_pieces"), 4.0);
  EXPECT_GT(Number(with.stats, "dropped_triangles"), 0.0);
  const Result ref = RenderPlain(
    [](vtkSoftShadowPass* p) {
      p->SetMethod(vtkSoftShadowPass::REFERENCE);
      p->SetReferenceSamples(8);
    },
    -1.0);
  // as GEARSEqualsReferenceAndBaseline: equal up to samples grazing an edge
  ExpectSameV(with.frame, ref.frame, "gears with found pieces vs the reference, mirrored", 2.0 / 64 + 1e-6);
  std::size_t fg = 0, equal = 0;
  for (std::size_t i = 0; i < ref.frame.V.size() && i < with.frame.V.size(); ++i)
  {
    if (!std::isnan(ref.frame.V[i]))
    {
      ++fg;
      equal += std::abs(double(with.frame.V[i]) - ref.frame.V[i]) < 1e-6;
    }
  }
  EXPECT_GE(equal, 0.999 * fg);
}

// Open casters (a hemisphere, a square, the ground) get no closed piece, and
// GEARS drops nothing.
TEST(UnpreparedCasters, OpenMeshesGetNoClosedPiece)
{
  const Result with = RenderPlain(kGears, 1.0, 1, true);
  const Result without = RenderPlain(kGearsWithoutPieces, 1.0, 1, true);
  ExpectSameV(with.frame, without.frame, "gears, open casters, pieces found vs none");
  EXPECT_GE(Number(with.stats, "pieces_found"), 3.0);
  EXPECT_EQ(Number(with.stats, "closed_pieces"), 0.0);
  EXPECT_EQ(Number(with.stats, "dropped_triangles"), 0.0);
}

// gears_cell_culling=0 (for measuring, bench --culling) gives the paper's
// assignment: every triangle to every cell its shadow volume's box covers.
// The culling changes no bit of V and lists far fewer pairs.
TEST(UnpreparedCasters, GearsCellCullingKeepsVAndListsFewerPairs)
{
  const Result culled = RenderPlain(kGears);
  const Result plain = RenderPlain([](vtkSoftShadowPass* p) {
    kGears(p);
    p->GearsCellCullingOff();
  });
  ExpectSameV(culled.frame, plain.frame, "gears, cell culling on vs off");
  // listed: the pairs the per-pixel rejection is given (it then keeps about
  // the same with or without the culling: the culling saves work, not bits)
  const double listedCulled = Number(culled.stats, "assignments_listed"),
               listedPlain = Number(plain.stats, "assignments_listed");
  std::cout << "assignments with cell culling " << listedCulled << ", without " << listedPlain << "; clusters culled "
            << Number(culled.stats, "clusters_culled") << " / " << Number(plain.stats, "clusters_culled") << "\n";
  EXPECT_GT(Number(culled.stats, "clusters_culled"), 0.0);
  EXPECT_EQ(Number(plain.stats, "clusters_culled"), 0.0);
  EXPECT_EQ(Number(plain.stats, "triangles_culled"), 0.0);
  EXPECT_LT(listedCulled, 0.8 * listedPlain);
}
