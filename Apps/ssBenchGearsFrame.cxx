#include "ssBenchGearsFrame.h"
#include "ssBenchCommon.h"

#include "vtkActor.h"
#include "vtkAssemblyNode.h"
#include "vtkAssemblyPath.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkPropCollection.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkSoftShadowLight.h"
#include "vtkSoftShadowPass.h"
#include "vtkTriangleFilter.h"

#include "ssGearsPieces.h"
#include "ssTriangleSet.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace ssapp
{
namespace bench
{
namespace
{
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// One actor's triangles in world coordinates, with its point normals (world,
// or none) and the point ids of each triangle.
struct ActorTriangles
{
  std::vector<glm::dvec3> points;
  std::vector<glm::dvec3> normals; // empty: the mapper uses face normals
  std::vector<std::array<vtkIdType, 3>> tris;
  float opacity = 1.0f;
  bool casts = true;
  bool affine = true; // a projective matrix leaves the actor's pieces open
};


ActorTriangles Gather(vtkActor* actor, vtkMatrix4x4* m)
{
  ActorTriangles a;
  a.opacity = static_cast<float>(actor->GetProperty()->GetOpacity());
  a.casts = vtkSoftShadowPass::GetCastsShadows(actor);
  a.affine = ss::MayClosePieces(m->GetData());
  actor->GetMapper()->Update();
  auto* pd = vtkPolyData::SafeDownCast(actor->GetMapper()->GetInputDataObject(0, 0));
  if (!pd || !pd->GetPoints())
  {
    return a;
  }
  vtkNew<vtkTriangleFilter> tf;
  tf->SetInputData(pd);
  tf->PassVertsOff();
  tf->PassLinesOff();
  tf->Update();
  vtkPolyData* t = tf->GetOutput();
  const vtkIdType np = t->GetNumberOfPoints();
  a.points.resize(static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i)
  {
    double p[3];
    t->GetPoint(i, p);
    double in[4] = { p[0], p[1], p[2], 1.0 }, out[4];
    m->MultiplyPoint(in, out);
    const double w = out[3] != 0.0 ? out[3] : 1.0;
    a.points[i] = glm::dvec3(out[0] / w, out[1] / w, out[2] / w);
  }
  if (vtkDataArray* n = t->GetPointData()->GetNormals())
  {
    // normals transform with the inverse transpose of the linear part
    vtkNew<vtkMatrix4x4> inv;
    vtkMatrix4x4::Invert(m, inv);
    a.normals.resize(static_cast<std::size_t>(np));
    for (vtkIdType i = 0; i < np; ++i)
    {
      double v[3];
      n->GetTuple(i, v);
      glm::dvec3 w(0.0);
      for (int r = 0; r < 3; ++r)
      {
        w[r] = inv->GetElement(0, r) * v[0] + inv->GetElement(1, r) * v[1] + inv->GetElement(2, r) * v[2];
      }
      a.normals[i] = w;
    }
  }
  vtkCellArray* polys = t->GetPolys();
  vtkIdType npts;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    if (npts == 3)
    {
      a.tris.push_back({ ids[0], ids[1], ids[2] });
    }
  }
  return a;
}

ss::LightFrame FirstShadowLight(vtkRenderer* ren)
{
  vtkLightCollection* lc = ren->GetLights();
  vtkCollectionSimpleIterator lit;
  for (lc->InitTraversal(lit); vtkLight* light = lc->GetNextLight(lit);)
  {
    if (light->GetSwitch() <= 0 || light->LightTypeIsHeadlight() || !vtkSoftShadowLight::GetCastsShadows(light))
    {
      continue;
    }
    return vtkSoftShadowLight::MakeLightFrame(light); // world coordinates, as the pass builds it
  }
  throw std::runtime_error("bench --gears: the scene has no shadow-casting light");
}
}

GearsFrame CaptureGearsFrame(vtkRenderWindow* win, vtkRenderer* ren)
{
  const auto t0 = Clock::now();
  GearsFrame f;
  vtkNew<vtkSoftShadowPass> pass;
  pass->SetMethod(vtkSoftShadowPass::HARD);
  ren->SetPass(pass);
  win->Render();
  vtkNew<vtkFloatArray> positions;
  if (!pass->GetPositionsImage(positions))
  {
    throw std::runtime_error("bench --gears: the pass gave no positions image");
  }
  pass->GetLastPositionsOrigin(&f.origin.x);
  f.width = pass->GetLastWidth();
  f.height = pass->GetLastHeight();
  pass->ReleaseGraphicsResources(win);
  ren->SetPass(nullptr);
  f.light = FirstShadowLight(ren);
  const std::size_t n = static_cast<std::size_t>(positions->GetNumberOfTuples());
  f.pos.assign(positions->GetPointer(0), positions->GetPointer(0) + 3 * n);
  f.nrm.assign(3 * n, 0.0f);

  // every visible actor into one Embree scene (receivers too), the casters
  // into the frame
  std::vector<ActorTriangles> actors;
  vtkSoftShadowPass::ForEachVisibleActor(ren, [&](vtkActor* actor, vtkMatrix4x4* m) { actors.push_back(Gather(actor, m)); });
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  for (std::size_t ai = 0; ai < actors.size(); ++ai)
  {
    const ActorTriangles& a = actors[ai];
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), std::max<std::size_t>(1, a.points.size())));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), a.tris.size()));
    for (std::size_t i = 0; i < a.points.size(); ++i)
    {
      const glm::dvec3 r = a.points[i] - f.origin;
      vb[3 * i] = float(r.x);
      vb[3 * i + 1] = float(r.y);
      vb[3 * i + 2] = float(r.z);
    }
    for (std::size_t t = 0; t < a.tris.size(); ++t)
    {
      for (int j = 0; j < 3; ++j)
      {
        ib[3 * t + j] = static_cast<unsigned>(a.tris[t][j]);
      }
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, static_cast<unsigned>(ai));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(scene);
  double cam[3];
  ren->GetActiveCamera()->GetPosition(cam);
  const glm::dvec3 eye = glm::dvec3(cam[0], cam[1], cam[2]) - f.origin;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    RTCIntersectContext ctx;
    for (std::size_t i = r.begin(); i != r.end(); ++i)
    {
      const glm::dvec3 P(f.pos[3 * i], f.pos[3 * i + 1], f.pos[3 * i + 2]);
      if (!(std::isfinite(P.x) && std::isfinite(P.y) && std::isfinite(P.z)))
      {
        continue;
      }
      const glm::dvec3 d = P - eye;
      RTCRayHit rh;
      rh.ray.org_x = float(eye.x);
      rh.ray.org_y = float(eye.y);
      rh.ray.org_z = float(eye.z);
      rh.ray.dir_x = float(d.x);
      rh.ray.dir_y = float(d.y);
      rh.ray.dir_z = float(d.z);
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = 1.01f;
      rh.ray.time = 0.0f;
      rh.ray.mask = 0xFFFFFFFFu;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcInitIntersectContext(&ctx);
      rtcIntersect1(scene, &ctx, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
      {
        continue; // no normal: the pixel keeps a zero normal (no offset, no horizon)
      }
      const ActorTriangles& a = actors[rh.hit.geomID];
      const auto& tr = a.tris[rh.hit.primID];
      const glm::dvec3 face = glm::cross(a.points[tr[1]] - a.points[tr[0]], a.points[tr[2]] - a.points[tr[0]]);
      const bool front = glm::dot(face, eye - P) > 0.0;
      glm::dvec3 N;
      if (!a.normals.empty())
      {
        const double u = rh.hit.u, v = rh.hit.v;
        N = (1.0 - u - v) * a.normals[tr[0]] + u * a.normals[tr[1]] + v * a.normals[tr[2]];
        N = front ? N : -N; // two-sided lighting: VTK turns back faces' normals
      }
      else
      {
        N = front ? face : -face; // flat: VTK's derivative normal faces the viewer
      }
      const double l = glm::length(N);
      if (l > 0.0)
      {
        N /= l;
        f.nrm[3 * i] = float(N.x);
        f.nrm[3 * i + 1] = float(N.y);
        f.nrm[3 * i + 2] = float(N.z);
      }
    }
  });
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  for (std::size_t i = 0; i < n; ++i)
  {
    f.foreground += std::isfinite(f.pos[3 * i]) ? 1 : 0;
  }
  const auto t1 = Clock::now();
  f.msCapture = Ms(t0, t1);

  // the casters and their pieces, one actor at a time (as the pass finds them)
  std::vector<std::uint32_t> block;
  for (const ActorTriangles& a : actors)
  {
    if (!a.casts)
    {
      continue;
    }
    block.clear();
    for (const auto& tr : a.tris)
    {
      block.push_back(static_cast<std::uint32_t>(f.tris.size() / 3));
      for (int j = 0; j < 3; ++j)
      {
        f.tris.push_back(a.points[tr[j]]);
      }
      f.opacity.push_back(a.opacity);
    }
    f.pieces.piece.resize(f.tris.size() / 3);
    ss::FindGearsPieces(f.tris, block, a.affine, f.pieces);
  }
  f.pieceCount = f.pieces.orientation.size();
  for (auto o : f.pieces.orientation)
  {
    f.closedPieces += o != 0;
  }
  for (auto p : f.pieces.piece)
  {
    f.closedTriangles += f.pieces.orientation[p] != 0;
  }
  f.msPieces = Ms(t1, Clock::now());
  return f;
}

std::vector<float> MinimalEmbreeLoop(const GearsFrame& f, int k, double& ms, double& rays, double& cpuMs)
{
  // The program anyone would write first with Embree: no filter callback,
  // rays set up per lane, rtcOccluded16, TBB over rows of pixels. The scene,
  // start offset and light samples are the reference's (ssReference.cxx), so
  // its V is comparable; it is timed from the first ray to the last.
  const ss::TriangleSelection sel = ss::SelectTriangles(f.tris, f.opacity, false);
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
    geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), std::max<std::size_t>(3, 3 * sel.kept)));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
    geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), sel.kept));
  std::size_t out = 0;
  for (std::size_t t = 0; t < f.tris.size() / 3; ++t)
  {
    if (!sel.keep[t])
    {
      continue;
    }
    for (int j = 0; j < 3; ++j)
    {
      const glm::dvec3 r = f.tris[3 * t + j] - sel.center;
      vb[9 * out + 3 * j] = float(r.x);
      vb[9 * out + 3 * j + 1] = float(r.y);
      vb[9 * out + 3 * j + 2] = float(r.z);
      ib[3 * out + j] = static_cast<unsigned>(3 * out + j);
    }
    ++out;
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);

  const ss::LightFrame& L = f.light;
  const int kk = L.type == ss::LightType::Point ? 1 : k;
  const int ns = kk * kk;
  const std::size_t n = f.pos.size() / 3;
  std::vector<float> V(n, std::numeric_limits<float>::quiet_NaN());
  std::atomic<long long> count{ 0 };
  const auto t0 = Clock::now();
  const double c0 = ProcessCpuMs();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    long long local = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::size_t i = r.begin(); i != r.end(); ++i)
    {
      const float* pf = &f.pos[3 * i];
      if (!(std::isfinite(pf[0]) && std::isfinite(pf[1]) && std::isfinite(pf[2])))
      {
        continue;
      }
      const glm::dvec3 p = f.origin + glm::dvec3(pf[0], pf[1], pf[2]);
      const glm::dvec3 N(f.nrm[3 * i], f.nrm[3 * i + 1], f.nrm[3 * i + 2]);
      if (L.type == ss::LightType::Rect && glm::dot(p - L.center, L.n) <= 0.0)
      {
        V[i] = 0.0f;
        continue;
      }
      const double eps = ss::StartOffset(p - sel.center, sel.scale, ss::DistanceToLight(L, p - L.center));
      const glm::dvec3 S = p + N * eps;
      const glm::dvec3 So = S - sel.center;
      int visible = 0;
      for (int s0 = 0; s0 < ns; s0 += 16)
      {
        RTCRay16 rays16;
        int valid[16];
        for (int q = 0; q < 16; ++q)
        {
          const int s = s0 + q;
          glm::dvec3 d(0.0, 0.0, 1.0);
          double tfar = -1.0;
          valid[q] = 0;
          if (s < ns)
          {
            const double su = (s % kk + 0.5) / kk - 0.5, sv = (s / kk + 0.5) / kk - 0.5;
            if (L.type == ss::LightType::Directional)
            {
              const double T = 2.0 * std::tan(0.5 * L.angularDiameter);
              d = glm::normalize(-L.n + su * T * L.u + sv * T * L.v);
              tfar = 1e30;
            }
            else
            {
              d = L.center + su * L.width * L.u + sv * L.height * L.v - S;
              tfar = glm::length(d);
              d /= tfar;
              tfar *= 1.0 - 1e-6;
            }
            valid[q] = glm::dot(d, N) >= 0.0 && tfar > 0.0 ? -1 : 0;
          }
          rays16.org_x[q] = float(So.x);
          rays16.org_y[q] = float(So.y);
          rays16.org_z[q] = float(So.z);
          rays16.dir_x[q] = float(d.x);
          rays16.dir_y[q] = float(d.y);
          rays16.dir_z[q] = float(d.z);
          rays16.tnear[q] = valid[q] ? float(eps) : 0.0f;
          rays16.tfar[q] = valid[q] ? float(tfar) : -1.0f;
          rays16.time[q] = 0.0f;
          rays16.mask[q] = 0xFFFFFFFFu;
          rays16.id[q] = static_cast<unsigned>(q);
          rays16.flags[q] = 0;
        }
        rtcOccluded16(valid, scene, &ctx, &rays16);
        for (int q = 0; q < 16; ++q)
        {
          local += valid[q] != 0;
          visible += valid[q] != 0 && rays16.tfar[q] >= 0.0f;
        }
      }
      V[i] = static_cast<float>(double(visible) / ns);
    }
    count += local;
  });
  ms = Ms(t0, Clock::now());
  cpuMs = ProcessCpuMs() - c0;
  rays = static_cast<double>(count.load());
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return V;
}
}
}
