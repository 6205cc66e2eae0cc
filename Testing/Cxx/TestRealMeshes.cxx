// The real-mesh image set (issue 17): smooth-shaded meshes as users load
// them (normals on, as ParaView's Contour and Generate Surface Normals make
// them) on a ground plane, lit from the side and from a grazing angle by a
// small and a large rect light. Every registered method renders each frame
// and is compared with GEARS at the same light samples (the light's centre
// for the methods that shadow from it, the regular k x k grid for the soft
// ones), pixel by pixel on V:
//   GEARS >= 0.5 and V < GEARS - 0.25 (too dark: acne, self-shadowing), or
//   GEARS <  0.5 and V > GEARS + 0.25 (too light: light leaks, detached shadows)
// is a failing pixel. Failing pixels at silhouettes (next to a depth
// discontinuity on screen, where a pixel's footprint spans two surfaces, or
// next to a shadow edge of GEARS, the silhouette of a caster seen from the
// light, which a shadow map places to within a texel) are counted apart and
// have an allowance; the others have the per-method allowance measured on this
// set (Documentation/stability.md), so a regression fails. Every frame
// is written as a picture (V of each method, the failing pixels in colour)
// to Testing/Temporary/realmesh_<mesh>_<light>.png.
#include "ssImageIO.h"
#include "ssRenderTestUtilities.h"
#include "vtkShadowMeshReader.h"

#include "vtkContourFilter.h"
#include "vtkCylinderSource.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkRTAnalyticSource.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkTriangleFilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace sstest;

namespace
{
const int W = 160, H = 120;
const int kArea = 4; // light samples a side of GEARS, the reference and hardavg

// The mesh scaled to a largest extent of 1.6, centred over the origin and
// standing on the ground (its lowest point at z = 0: a contact).
vtkSmartPointer<vtkPolyData> OnGround(vtkAlgorithmOutput* port)
{
  vtkNew<vtkTransformPolyDataFilter> probe;
  probe->SetInputConnection(port);
  vtkNew<vtkTransform> id;
  probe->SetTransform(id);
  probe->Update();
  double b[6];
  probe->GetOutput()->GetBounds(b);
  const double extent = std::max({ b[1] - b[0], b[3] - b[2], b[5] - b[4] });
  const double s = 1.6 / extent;
  vtkNew<vtkTransform> t;
  t->PostMultiply();
  t->Translate(-0.5 * (b[0] + b[1]), -0.5 * (b[2] + b[3]), -b[4]);
  t->Scale(s, s, s);
  vtkNew<vtkTransformPolyDataFilter> f;
  f->SetInputConnection(port);
  f->SetTransform(t);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

// ParaView's Wavelet source and Contour filter with their defaults (extent
// [-10, 10]^3, normals computed), at the middle of the data range.
vtkSmartPointer<vtkPolyData> WaveletIsosurface()
{
  vtkNew<vtkRTAnalyticSource> wavelet;
  vtkNew<vtkContourFilter> contour;
  contour->SetInputConnection(wavelet->GetOutputPort());
  contour->SetValue(0, 157.0);
  contour->ComputeNormalsOn();
  return OnGround(contour->GetOutputPort());
}

// The getting-started sphere: vtkSphereSource at 16 x 8 (its point normals).
vtkSmartPointer<vtkPolyData> CoarseSphere()
{
  vtkNew<vtkSphereSource> s;
  s->SetThetaResolution(16);
  s->SetPhiResolution(8);
  return OnGround(s->GetOutputPort());
}

// A CGAL sample mesh (scripts/generate_scenes.py extracts them) with the
// normals of ParaView's Generate Surface Normals (feature angle 30).
vtkSmartPointer<vtkPolyData> MeshFile(const std::string& name)
{
  const std::string path = std::string(SS_MESH_DIR) + "/" + name;
  vtkNew<vtkShadowMeshReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (std::string(reader->GetErrorMessage()) != "" || reader->GetOutput()->GetNumberOfCells() == 0)
  {
    ADD_FAILURE() << "cannot read " << path << " (" << reader->GetErrorMessage()
                  << "): run scripts/setup.sh or scripts/generate_scenes.py";
    return nullptr;
  }
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(reader->GetOutputPort());
  return OnGround(normals->GetOutputPort());
}

// A CAD-like part: a tessellated cylinder (24 sides) lying on its side, its
// flat caps split from the smooth side at the default feature angle.
vtkSmartPointer<vtkPolyData> MachinedCylinder()
{
  vtkNew<vtkCylinderSource> c;
  c->SetResolution(24);
  c->SetHeight(2.0);
  c->SetRadius(0.6);
  c->CappingOn();
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(c->GetOutputPort());
  vtkNew<vtkTransform> t;
  t->RotateZ(60.0); // axis (y) turned in the ground plane, seen at an angle
  vtkNew<vtkTransformPolyDataFilter> turn;
  turn->SetInputConnection(tri->GetOutputPort());
  turn->SetTransform(t);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(turn->GetOutputPort());
  return OnGround(normals->GetOutputPort());
}

struct LightSetup
{
  const char* name;
  double elevation; // degrees above the ground
  double size;      // rect side (world; the mesh is 1.6 across, the light 6 away)
};

const LightSetup kLights[] = {
  { "side_small", 35.0, 0.1 },
  { "side_large", 35.0, 2.0 },
  { "grazing_small", 10.0, 0.1 },
  { "grazing_large", 10.0, 2.0 },
};

void Build(Scene& s, vtkPolyData* mesh, const LightSetup& l)
{
  s.renderer->AddActor(Ground(3.0));
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(mesh);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.85, 0.55, 0.4);
  s.renderer->AddActor(actor);
  // from the front left (the camera sees the lit side, the terminator and
  // the shadow on the ground), at `elevation`, 6 units from the mesh's
  // centre (0, 0, 0.5), aimed at it
  const double e = l.elevation * M_PI / 180.0, a = 240.0 * M_PI / 180.0;
  s.renderer->AddLight(RectLight(6.0 * std::cos(e) * std::cos(a), 6.0 * std::cos(e) * std::sin(a),
    0.5 + 6.0 * std::sin(e), 0, 0, 0.5, l.size, l.size));
  s.Camera(1.5, -5.5, 3.2, 0, 0, 0.45);
}

// Wall time of a render, printed next to its counts (what the label spends).
long MillisecondsSince(std::chrono::steady_clock::time_point t0)
{
  return static_cast<long>(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
}

// The methods that shadow from the light's centre (compared with GEARS at
// k = 1); the others integrate over the light (GEARS at k x k).
bool ShadowsFromCentre(int m)
{
  return m == vtkSoftShadowPass::HARD || m == vtkSoftShadowPass::PCF || m == vtkSoftShadowPass::ASM ||
    m == vtkSoftShadowPass::AVSM;
}

// Every method renders the same scene in turn (the pass's options enter its
// reuse signature, so each render solves anew).
Frame RenderWith(Scene& s, int method, int k)
{
  s.pass->SetMethod(method);
  s.pass->SetGearsSamples(k);
  s.pass->SetReferenceSamples(k);
  s.pass->SetReferencePattern(0); // GEARS' regular samples
  s.pass->SetAverageSamples(k);
  Frame f = s.Render();
  // ASM refines progressively: the frame once the still view is refined
  for (int i = 0; i < 40 && method == vtkSoftShadowPass::ASM && s.pass->GetASMRefining(); ++i)
  {
    f = s.Render();
  }
  return f;
}

// The silhouettes, where a pixel's footprint spans two surfaces or two
// sides of a shadow edge and one sample decides it: pixels next to a depth
// discontinuity on screen (a neighbour that is background or whose distance
// from the camera differs by more than 3 % from the pixel's), and pixels
// next to a shadow edge of the reference (a neighbour on the other side of
// V = 0.5: the silhouette of a caster seen from the light, which a shadow
// map places to within a texel).
std::vector<char> Silhouettes(const Frame& f, const Frame& ref, const double eye[3])
{
  std::vector<double> depth(f.V.size(), -1.0);
  for (std::size_t i = 0; i < f.V.size(); ++i)
  {
    if (!std::isnan(f.V[i]))
    {
      double d2 = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        const double x = f.P[3 * i + c] + f.origin[c] - eye[c];
        d2 += x * x;
      }
      depth[i] = std::sqrt(d2);
    }
  }
  std::vector<char> edge(f.V.size(), 0);
  for (int y = 0; y < f.height; ++y)
  {
    for (int x = 0; x < f.width; ++x)
    {
      const std::size_t i = static_cast<std::size_t>(y) * f.width + x;
      if (depth[i] < 0.0)
      {
        continue;
      }
      for (int dy = -1; dy <= 1; ++dy)
      {
        for (int dx = -1; dx <= 1; ++dx)
        {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height)
          {
            continue;
          }
          const std::size_t j = static_cast<std::size_t>(ny) * f.width + nx;
          const double dn = depth[j];
          if (dn < 0.0 || std::abs(dn - depth[i]) > 0.03 * depth[i] || ((ref.V[i] < 0.5f) != (ref.V[j] < 0.5f)))
          {
            edge[i] = 1;
          }
        }
      }
    }
  }
  return edge;
}

struct Failures
{
  int dark = 0, light = 0;     // away from silhouettes
  int silhouette = 0;          // at silhouettes
  int compared = 0, nonFinite = 0;
  std::vector<char> map;       // 0 ok, 1 too dark, 2 too light (per pixel)
};

Failures Check(const Frame& f, const Frame& gears, const std::vector<char>& edge)
{
  Failures r;
  r.map.assign(gears.V.size(), 0);
  for (std::size_t i = 0; i < gears.V.size() && i < f.V.size(); ++i)
  {
    const float g = gears.V[i], v = f.V[i];
    if (std::isnan(g))
    {
      continue;
    }
    if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
    {
      ++r.nonFinite;
      continue;
    }
    ++r.compared;
    const bool dark = g >= 0.5f && v < g - 0.25f;
    const bool light = g < 0.5f && v > g + 0.25f;
    if (dark || light)
    {
      r.map[i] = dark ? 1 : 2;
      if (edge[i])
      {
        ++r.silhouette;
      }
      else
      {
        (dark ? r.dark : r.light) += 1;
      }
    }
  }
  return r;
}

// One row of pictures: V in grey (background white), and under it the
// failing pixels (red: too dark, blue: too light) over a faint V.
void AppendPanel(std::vector<unsigned char>& rgb, int panel, int panels, const Frame& f, const std::vector<char>& map)
{
  const int rowW = panels * W;
  for (int y = 0; y < H; ++y)
  {
    for (int x = 0; x < W; ++x)
    {
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      const float v = f.V.size() > i ? f.V[i] : NAN;
      const unsigned char grey = std::isnan(v) ? 255 : static_cast<unsigned char>(255.0f * std::clamp(v, 0.0f, 1.0f));
      unsigned char* top = &rgb[3 * ((static_cast<std::size_t>(H + y) * rowW) + panel * W + x)];
      unsigned char* bottom = &rgb[3 * ((static_cast<std::size_t>(y) * rowW) + panel * W + x)];
      top[0] = top[1] = top[2] = grey;
      const unsigned char faint = static_cast<unsigned char>(160 + grey / 3);
      bottom[0] = bottom[1] = bottom[2] = faint;
      if (!map.empty() && map[i] == 1)
      {
        bottom[0] = 230, bottom[1] = 0, bottom[2] = 0;
      }
      else if (!map.empty() && map[i] == 2)
      {
        bottom[0] = 0, bottom[1] = 60, bottom[2] = 230;
      }
    }
  }
}

std::vector<int> RegisteredMethods()
{
  std::vector<int> methods;
  std::stringstream names(vtkSoftShadowPass::GetMethodNames());
  std::string name;
  while (std::getline(names, name, ','))
  {
    name.erase(0, name.find_first_not_of(' '));
    vtkNew<vtkSoftShadowPass> probe;
    if (probe->SetMethodByName(name.c_str()) && probe->GetMethod() != vtkSoftShadowPass::AUTO &&
      probe->GetMethod() != vtkSoftShadowPass::NONE && probe->GetMethod() != vtkSoftShadowPass::GEARS)
    {
      methods.push_back(probe->GetMethod());
    }
  }
  return methods;
}

// The allowances, from the failing pixels measured on this set (Mesa
// llvmpipe, 2048^2 maps; Documentation/stability.md) plus 20 % and 10 px for
// other drivers, so that a regression fails: per method and mesh off the
// silhouettes over the four lights (`Measured`), and per method and frame at
// the silhouettes. GEARS and the reference use the same samples: no
// allowance. What remains off the silhouettes is each method's own
// approximation: PCSS's one average blocker depth per pixel under the large
// lights, PVSM's penumbrae and the bunny's concave creases (stability.md).
// Measured with the views fitted to the visible receivers and AVSM's
// first-frame sampler fixed (issue 20).
using Measured = std::map<std::string, int>;
int Allow(int measured)
{
  return measured + measured / 5 + 10;
}
const Measured kSilhouettes = { { "hard", 32 }, { "pcf", 101 }, { "pcss", 507 }, { "pvsm", 130 },
  { "hardavg", 20 }, { "asm", 47 }, { "vpcss", 507 }, { "avsm", 77 } };
int SilhouetteAllowance(const std::string& method)
{
  const auto it = kSilhouettes.find(method);
  return it == kSilhouettes.end() ? 0 : Allow(it->second);
}

void RunMesh(const std::string& meshName, vtkPolyData* mesh, const Measured& measured)
{
  ASSERT_NE(mesh, nullptr);
  const std::vector<int> methods = RegisteredMethods();
  ASSERT_GE(methods.size(), 8u) << vtkSoftShadowPass::GetMethodNames();
  std::map<int, int> offSilhouette;
  const double eye[3] = { 1.5, -5.5, 3.2 };
  for (const LightSetup& l : kLights)
  {
    Scene scene(W, H);
    Build(scene, mesh, l);
    const auto g0 = std::chrono::steady_clock::now();
    const Frame gearsHard = RenderWith(scene, vtkSoftShadowPass::GEARS, 1);
    const Frame gearsArea = RenderWith(scene, vtkSoftShadowPass::GEARS, kArea);
    const long gearsMs = MillisecondsSince(g0);
    ASSERT_EQ(gearsHard.V.size(), static_cast<std::size_t>(W * H));
    ASSERT_EQ(gearsArea.V.size(), static_cast<std::size_t>(W * H));
    const std::vector<char> edgeHard = Silhouettes(gearsHard, gearsHard, eye);
    const std::vector<char> edgeArea = Silhouettes(gearsArea, gearsArea, eye);
    const int panels = 2 + static_cast<int>(methods.size());
    std::vector<unsigned char> rgb(static_cast<std::size_t>(3) * panels * W * 2 * H, 255);
    AppendPanel(rgb, 0, panels, gearsHard, {});
    AppendPanel(rgb, 1, panels, gearsArea, {});
    std::ostringstream line;
    line << "realmesh " << meshName << " " << l.name << ": GEARS references " << gearsMs
         << " ms; failing px (dark/light/silhouette)";
    int panel = 2;
    for (int m : methods)
    {
      const Frame& ref = ShadowsFromCentre(m) ? gearsHard : gearsArea;
      const auto t0 = std::chrono::steady_clock::now();
      const Frame f = RenderWith(scene, m, ShadowsFromCentre(m) ? 1 : kArea);
      const long ms = MillisecondsSince(t0);
      ASSERT_EQ(f.V.size(), ref.V.size()) << vtkSoftShadowPass::GetMethodName(m);
      const Failures r = Check(f, ref, ShadowsFromCentre(m) ? edgeHard : edgeArea);
      AppendPanel(rgb, panel++, panels, f, r.map);
      line << " " << vtkSoftShadowPass::GetMethodName(m) << " " << r.dark << "/" << r.light << "/" << r.silhouette
           << " (" << ms << " ms)";
      EXPECT_EQ(r.nonFinite, 0) << vtkSoftShadowPass::GetMethodName(m);
      EXPECT_GT(r.compared, W * H / 3) << vtkSoftShadowPass::GetMethodName(m);
      EXPECT_LE(r.silhouette, SilhouetteAllowance(vtkSoftShadowPass::GetMethodName(m)))
        << meshName << " " << l.name << " " << vtkSoftShadowPass::GetMethodName(m) << ": failing pixels at silhouettes";
      offSilhouette[m] += r.dark + r.light;
    }
    std::cout << line.str() << "\n";
    std::string message;
    const std::string png = std::string(SS_TEMP_DIR) + "/realmesh_" + meshName + "_" + l.name + ".png";
    EXPECT_TRUE(ssapp::WriteRGB8Image(png, rgb.data(), panels * W, 2 * H, 3, message)) << message;
  }
  for (int m : methods)
  {
    const std::string name = vtkSoftShadowPass::GetMethodName(m);
    const auto a = measured.find(name);
    const int allowance = a == measured.end() ? 0 : Allow(a->second);
    std::cout << "realmesh " << meshName << " " << name << ": " << offSilhouette[m]
              << " failing px off silhouettes over the 4 lights (allowed " << allowance << ")\n";
    EXPECT_LE(offSilhouette[m], allowance) << meshName << " " << name;
  }
}
}

TEST(RealMeshes, WaveletIsosurface)
{
  RunMesh("wavelet", WaveletIsosurface(),
    { { "hard", 0 }, { "pcf", 61 }, { "pcss", 632 }, { "pvsm", 264 }, { "hardavg", 2 }, { "asm", 4 },
      { "vpcss", 632 }, { "avsm", 15 } });
}

TEST(RealMeshes, CoarseSphere)
{
  RunMesh("sphere16x8", CoarseSphere(),
    { { "hard", 0 }, { "pcf", 0 }, { "pcss", 48 }, { "pvsm", 5 }, { "hardavg", 0 }, { "asm", 0 }, { "vpcss", 48 },
      { "avsm", 0 } });
}

TEST(RealMeshes, Bunny)
{
  RunMesh("bunny", MeshFile("bunny00.off"),
    { { "hard", 2 }, { "pcf", 107 }, { "pcss", 419 }, { "pvsm", 169 }, { "hardavg", 1 }, { "asm", 4 },
      { "vpcss", 419 }, { "avsm", 26 } });
}

TEST(RealMeshes, Fandisk)
{
  RunMesh("fandisk", MeshFile("fandisk.off"),
    { { "hard", 0 }, { "pcf", 6 }, { "pcss", 728 }, { "pvsm", 137 }, { "hardavg", 0 }, { "asm", 0 },
      { "vpcss", 728 }, { "avsm", 11 } });
}

TEST(RealMeshes, MachinedCylinder)
{
  RunMesh("cylinder", MachinedCylinder(),
    { { "hard", 0 }, { "pcf", 0 }, { "pcss", 4 }, { "pvsm", 4 }, { "hardavg", 0 }, { "asm", 0 }, { "vpcss", 4 },
      { "avsm", 0 } });
}
