#include "vtkShadowCasterPreparation.h"

#include "ssCasterClusters.h"
#include "ssCasterRepair.h"
#include "ssOrientedBoxes.h"
#include "ssPolyDataTriangles.h"
#include "ssWeld.h"
#include "ssClusterBounds.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkShadowCasterPreparation);

namespace
{
using Clock = std::chrono::steady_clock;

double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

bool Finite(const double p[3])
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Process CPU time (all threads), milliseconds.
double CpuMs()
{
  return 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// The report: named counts in a fixed order, then stage times: wall time and
// the process's CPU time (a loaded machine stretches the first, less the second).
struct ReportData
{
  std::vector<std::pair<std::string, double>> counts;
  std::vector<std::pair<std::string, double>> ms, cpu;
  Clock::time_point wall0 = Clock::now();
  double cpu0 = CpuMs();
  void Count(const std::string& name, double v) { counts.emplace_back(name, v); }
  void Start()
  {
    wall0 = Clock::now();
    cpu0 = CpuMs();
  }
  void Stage(const std::string& name)
  {
    ms.emplace_back(name, Ms(wall0, Clock::now()));
    cpu.emplace_back(name, CpuMs() - cpu0);
    Start();
  }
};

template <typename T, typename A>
vtkSmartPointer<A> Scalar(const char* name, T value)
{
  auto a = vtkSmartPointer<A>::New();
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  return a;
}
}

//------------------------------------------------------------------------------
vtkShadowCasterPreparation::vtkShadowCasterPreparation() = default;
vtkShadowCasterPreparation::~vtkShadowCasterPreparation() = default;

//------------------------------------------------------------------------------
int vtkShadowCasterPreparation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("vtkShadowCasterPreparation needs a vtkPolyData input.");
    return 0;
  }
  // (vtkSetClampMacro lets NaN through: it welded nothing and wrote a NaN
  // WeldToleranceAbsolute into the output's field data)
  if (!(this->WeldTolerance >= 0.0 && this->WeldTolerance <= 0.01))
  {
    vtkErrorMacro("WeldTolerance: must be a fraction of the bounds' diagonal in [0, 0.01] (got "
      << this->WeldTolerance << ").");
    return 0;
  }
  this->Report.clear();
  this->ReportJSON = "{}";
  ReportData report;
  const auto tStart = Clock::now();
  const double cpuStart = CpuMs();
  const vtkIdType nIn = input->GetNumberOfPoints();

  // --- 1. non-finite points, triangles
  std::vector<char> finite(static_cast<std::size_t>(nIn), 0);
  vtkPoints* inPoints = input->GetPoints();
  tbb::parallel_for(tbb::blocked_range<vtkIdType>(0, nIn, 16384), [&](const tbb::blocked_range<vtkIdType>& r) {
    for (vtkIdType i = r.begin(); i != r.end(); ++i)
    {
      double p[3];
      inPoints->GetPoint(i, p);
      finite[i] = Finite(p) ? 1 : 0;
    }
  });
  const std::size_t nonFinitePoints =
    static_cast<std::size_t>(std::count(finite.begin(), finite.end(), static_cast<char>(0)));
  ssf::PolyTriangles tri = ssf::Triangulate(input, finite);
  report.Count("InputCells", static_cast<double>(input->GetNumberOfCells()));
  report.Count("InputPoints", static_cast<double>(nIn));
  report.Count("NonFinitePoints", static_cast<double>(nonFinitePoints));
  report.Count("NonFiniteCells", static_cast<double>(tri.nonFiniteCells));
  report.Count("DroppedVertsAndLines", static_cast<double>(input->GetNumberOfVerts() + input->GetNumberOfLines()));
  report.Count("TriangulatedPolygons", static_cast<double>(tri.polygons));
  report.Count("TriangulatedStrips", static_cast<double>(tri.strips));
  report.Stage("triangulate");
  this->UpdateProgress(0.05);

  // --- 2. weld the finite points that triangles use
  std::vector<vtkIdType> compact(static_cast<std::size_t>(nIn), -1);
  std::vector<vtkIdType> usedPoints;
  for (const auto& t : tri.tris)
  {
    for (vtkIdType p : t)
    {
      if (compact[p] < 0)
      {
        compact[p] = static_cast<vtkIdType>(usedPoints.size());
        usedPoints.push_back(p);
      }
    }
  }
  // the used points in double, their bounds, the tolerance from the diagonal
  std::vector<glm::dvec3> used(usedPoints.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, usedPoints.size(), 16384),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        double p[3];
        inPoints->GetPoint(usedPoints[i], p);
        used[i] = glm::dvec3(p[0], p[1], p[2]);
      }
    });
  double bounds[6] = { 0, 0, 0, 0, 0, 0 };
  if (!used.empty())
  {
    glm::dvec3 lo = used[0], hi = used[0];
    for (const glm::dvec3& p : used)
    {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double b[6] = { lo.x, hi.x, lo.y, hi.y, lo.z, hi.z };
    std::copy(b, b + 6, bounds);
  }
  const double diagonal =
    std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) + (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
      (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const double tolerance = this->WeldTolerance * diagonal;
  // each point to the lowest-id point within the tolerance of it (ssWeld.h)
  const std::vector<std::int64_t> mergeMap = ssf::WeldPoints(used, tolerance);
  ssf::RepairInput repairIn;
  std::vector<vtkIdType> welded(usedPoints.size(), -1);
  for (std::size_t i = 0; i < usedPoints.size(); ++i)
  {
    const vtkIdType rep = mergeMap[i];
    if (welded[rep] < 0)
    {
      welded[rep] = static_cast<vtkIdType>(repairIn.points.size());
      repairIn.points.push_back(used[rep]);
      repairIn.sourcePoint.push_back(usedPoints[rep]);
    }
    welded[i] = welded[rep];
  }
  repairIn.triangles.reserve(tri.tris.size());
  for (const auto& t : tri.tris)
  {
    repairIn.triangles.push_back({ welded[compact[t[0]]], welded[compact[t[1]]], welded[compact[t[2]]] });
  }
  repairIn.sourceCell = std::move(tri.cell);
  tri.tris.clear();
  report.Count("WeldedPoints", static_cast<double>(usedPoints.size() - repairIn.points.size()));
  report.Stage("weld");
  this->UpdateProgress(0.1);
  if (this->CheckAbort())
  {
    return 1;
  }

  // --- 3, 4. OpenMesh/CGAL repair and classification
  ssf::RepairOptions ro;
  ro.tolerance = this->SnapTJunctions ? tolerance : 0.0;
  ro.snapTJunctions = this->SnapTJunctions;
  ro.checkSelfIntersections = this->CheckSelfIntersections;
  ro.orientOutward = this->OrientClosedPieces;
  ssf::RepairStats rs;
  bool aborted = false;
  ssf::RepairedMesh mesh = ssf::RepairMesh(repairIn, ro, rs,
    [this](double f) {
      this->UpdateProgress(0.1 + 0.5 * f);
      return !this->CheckAbort();
    },
    &aborted);
  repairIn = ssf::RepairInput();
  if (aborted)
  {
    return 1;
  }
  report.Count("CollapsedTriangles", static_cast<double>(rs.collapsed));
  report.Count("DegenerateTriangles", static_cast<double>(rs.degenerate));
  report.Count("NonManifoldEdges", static_cast<double>(rs.nonManifoldEdges));
  report.Count("NonManifoldVertices", static_cast<double>(rs.nonManifoldVertices));
  report.Count("FlippedForConsistency", static_cast<double>(rs.flippedForConsistency));
  report.Count("TJunctionsSnapped", static_cast<double>(rs.tJunctionsSnapped));
  report.Count("Pieces", static_cast<double>(rs.pieces));
  report.Count("ClosedPieces", static_cast<double>(rs.closedPieces));
  report.Count("OpenPieces", static_cast<double>(rs.openPieces));
  report.Count("SelfIntersectingPieces", static_cast<double>(rs.selfIntersectingPieces));
  report.Count("ReorientedPieces", static_cast<double>(rs.reorientedPieces));
  report.Count("ClosedOutwardPieces", static_cast<double>(rs.closedOutwardPieces));
  report.Stage("repair_classify");
  // CPU time of the repair's steps, summed over the parallel pieces
  report.cpu.emplace_back("thread.orient_soup", rs.msOrientSoup);
  report.cpu.emplace_back("thread.build_openmesh", rs.msBuildMesh);
  report.cpu.emplace_back("thread.degenerate", rs.msDegenerate);
  report.cpu.emplace_back("thread.snap_tjunctions", rs.msSnap);
  report.cpu.emplace_back("thread.components", rs.msComponents);
  report.cpu.emplace_back("thread.self_intersections", rs.msSelfIntersections);
  report.cpu.emplace_back("thread.orientation", rs.msOrientation);
  report.cpu.emplace_back("thread.normals_out", rs.msNormalsOut);

  // --- output points first, in the input's precision: the bounds below are
  // computed from the coordinates as stored, so they hold them exactly
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataType(input->GetPoints() ? input->GetPoints()->GetDataType() : VTK_FLOAT);
  outPoints->SetNumberOfPoints(static_cast<vtkIdType>(mesh.points.size()));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.points.size(), 16384),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
      {
        const glm::dvec3& p = mesh.points[i];
        outPoints->SetPoint(static_cast<vtkIdType>(i), p.x, p.y, p.z);
        double q[3];
        outPoints->GetPoint(static_cast<vtkIdType>(i), q);
        mesh.points[i] = glm::dvec3(q[0], q[1], q[2]);
      }
    });

  // --- 5. clusters: closed outward pieces by normal bucket (groups 1..6), the rest group 0
  const std::size_t nTri = mesh.triangles.size();
  std::vector<glm::dvec3> corners(3 * nTri);
  std::vector<std::uint8_t> groups(nTri, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nTri, 16384), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        corners[3 * t + k] = mesh.points[mesh.triangles[t][k]];
      }
      if (mesh.pieces[mesh.piece[t]].closedOutward)
      {
        groups[t] = static_cast<std::uint8_t>(1 + ss::NormalBucket(mesh.faceNormals[t]));
      }
    }
  });
  const ss::TriangleClusters clusters =
    ss::ClusterTriangles(corners, groups, static_cast<std::size_t>(this->MaximumClusterTriangles));
  corners.clear();
  const std::size_t nClusters = clusters.Clusters();
  std::vector<ss::ClusterBounds> cb(nClusters);
  const int boxes = this->OrientedBoxes;
  const auto boundCluster = [&](std::size_t c) {
    ss::ClusterBounds& b = cb[c];
    std::vector<glm::dvec3> normals, pts;
    std::vector<std::int64_t> ids;
    bool closed = true;
    for (std::size_t i = clusters.first[c]; i < clusters.first[c + 1]; ++i)
    {
      const std::size_t t = clusters.order[i];
      const ssf::PieceInfo& piece = mesh.pieces[mesh.piece[t]];
      closed = closed && piece.closedOutward;
      b.pieceBounds.Add(piece.bounds);
      normals.push_back(mesh.faceNormals[t]);
      for (int k = 0; k < 3; ++k)
      {
        ids.push_back(mesh.triangles[t][k]);
      }
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (std::int64_t id : ids)
    {
      pts.push_back(mesh.points[id]);
      b.aabb.Add(mesh.points[id]);
    }
    b.closedOutward = closed;
    // a face without a normal (too small for one) leaves the cone unbounded
    const bool allNormals = std::all_of(
      normals.begin(), normals.end(), [](const glm::dvec3& n) { return glm::length(n) > 0.5; });
    b.cone = allNormals ? ss::FitNormalCone(normals) : ss::NormalCone{};
    const std::array<glm::dvec3, 3> world{ glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1) };
    b.obb = ss::FitOrientedBox(world, pts);
    if (boxes != BOXES_AXIS_ALIGNED)
    {
      const ss::OrientedBox fitted = ss::FitOrientedBox(boxes == BOXES_OPTIMAL
          ? ssf::OptimalBoxAxes(pts)
          : ssf::PlaneBoxAxes(pts, b.cone.Full() ? glm::dvec3(0.0) : b.cone.axis),
        pts);
      const auto volume = [](const ss::OrientedBox& o) { return o.half.x * o.half.y * o.half.z; };
      if (volume(fitted) < volume(b.obb))
      {
        b.obb = fitted;
      }
    }
  };
  std::size_t next = 0;
  while (next < nClusters)
  {
    const std::size_t end = std::min(nClusters, next + std::max<std::size_t>(nClusters / 20, 64));
    tbb::parallel_for(next, end, boundCluster);
    next = end;
    this->UpdateProgress(0.6 + 0.3 * static_cast<double>(next) / static_cast<double>(nClusters));
    if (next < nClusters && this->CheckAbort())
    {
      return 1;
    }
  }
  report.Stage("clusters_bounds");

  // --- output cells (cluster order), cell and point data
  output->SetPoints(outPoints);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(nTri) + 1);
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(3 * nTri));
  vtkCellData* inCD = input->GetCellData();
  vtkCellData* outCD = output->GetCellData();
  const bool cellArrays = inCD->GetNumberOfArrays() > 0;
  outCD->CopyNormalsOff();
  outCD->CopyAllocate(inCD, static_cast<vtkIdType>(nTri));
  vtkNew<vtkFloatArray> faceNormals;
  faceNormals->SetName("Normals");
  faceNormals->SetNumberOfComponents(3);
  faceNormals->SetNumberOfTuples(static_cast<vtkIdType>(nTri));
  vtkNew<vtkIdTypeArray> pieceId, inputCellId;
  pieceId->SetName("PieceId");
  pieceId->SetNumberOfTuples(static_cast<vtkIdType>(nTri));
  inputCellId->SetName("InputCellId");
  inputCellId->SetNumberOfTuples(static_cast<vtkIdType>(nTri));
  vtkNew<vtkIntArray> clusterId;
  clusterId->SetName("ClusterId");
  clusterId->SetNumberOfTuples(static_cast<vtkIdType>(nTri));
  vtkNew<vtkUnsignedCharArray> closedOutward;
  closedOutward->SetName("ClosedOutward");
  closedOutward->SetNumberOfTuples(static_cast<vtkIdType>(nTri));
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  float* fn = faceNormals->GetPointer(0);
  vtkIdType* pid = pieceId->GetPointer(0);
  vtkIdType* icid = inputCellId->GetPointer(0);
  int* cid = clusterId->GetPointer(0);
  unsigned char* co = closedOutward->GetPointer(0);
  for (std::size_t c = 0; c < nClusters; ++c)
  {
    for (std::size_t i = clusters.first[c]; i < clusters.first[c + 1]; ++i)
    {
      const std::size_t t = clusters.order[i];
      off[i] = static_cast<vtkIdType>(3 * i);
      for (int k = 0; k < 3; ++k)
      {
        conn[3 * i + k] = static_cast<vtkIdType>(mesh.triangles[t][k]);
        fn[3 * i + k] = static_cast<float>(mesh.faceNormals[t][k]);
      }
      if (cellArrays)
      {
        outCD->CopyData(inCD, mesh.sourceCell[t], static_cast<vtkIdType>(i));
      }
      pid[i] = mesh.piece[t];
      icid[i] = mesh.sourceCell[t];
      cid[i] = static_cast<int>(c);
      co[i] = mesh.pieces[mesh.piece[t]].closedOutward ? 1 : 0;
    }
  }
  off[nTri] = static_cast<vtkIdType>(3 * nTri);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  output->SetPolys(polys);
  outCD->AddArray(pieceId);
  outCD->AddArray(clusterId);
  outCD->AddArray(closedOutward);
  outCD->AddArray(inputCellId);
  outCD->SetNormals(faceNormals);

  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyNormalsOff();
  outPD->CopyAllocate(inPD, static_cast<vtkIdType>(mesh.points.size()));
  vtkNew<vtkFloatArray> pointNormals;
  pointNormals->SetName("Normals");
  pointNormals->SetNumberOfComponents(3);
  pointNormals->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
  vtkNew<vtkIdTypeArray> inputPointId;
  inputPointId->SetName("InputPointId");
  inputPointId->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
  const bool pointArrays = inPD->GetNumberOfArrays() > 0;
  float* pn = pointNormals->GetPointer(0);
  vtkIdType* ipid = inputPointId->GetPointer(0);
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const vtkIdType o = static_cast<vtkIdType>(i);
    if (pointArrays && mesh.sourcePoint[i] >= 0)
    {
      outPD->CopyData(inPD, mesh.sourcePoint[i], o);
    }
    else if (pointArrays)
    {
      outPD->NullData(o);
    }
    for (int k = 0; k < 3; ++k)
    {
      pn[3 * i + k] = static_cast<float>(mesh.pointNormals[i][k]);
    }
    ipid[i] = mesh.sourcePoint[i];
  }
  outPD->SetNormals(pointNormals);
  outPD->AddArray(inputPointId);

  // --- field data: the cluster table and the report
  vtkFieldData* fd = output->GetFieldData();
  vtkNew<vtkIdTypeArray> range;
  range->SetName("ClusterRange");
  range->SetNumberOfComponents(2);
  range->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  vtkNew<vtkDoubleArray> aabb, box, cone, pieceBounds;
  aabb->SetName("ClusterAABB");
  aabb->SetNumberOfComponents(6);
  aabb->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  box->SetName("ClusterOBB");
  box->SetNumberOfComponents(15);
  box->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  cone->SetName("ClusterNormalCone");
  cone->SetNumberOfComponents(4);
  cone->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  pieceBounds->SetName("ClusterPieceBounds");
  pieceBounds->SetNumberOfComponents(6);
  pieceBounds->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  vtkNew<vtkUnsignedCharArray> clusterClosed;
  clusterClosed->SetName("ClusterClosedOutward");
  clusterClosed->SetNumberOfTuples(static_cast<vtkIdType>(nClusters));
  for (std::size_t c = 0; c < nClusters; ++c)
  {
    const vtkIdType o = static_cast<vtkIdType>(c);
    const ss::ClusterBounds& b = cb[c];
    range->SetTypedComponent(o, 0, static_cast<vtkIdType>(clusters.first[c]));
    range->SetTypedComponent(o, 1, static_cast<vtkIdType>(clusters.first[c + 1] - clusters.first[c]));
    const double ab[6] = { b.aabb.min.x, b.aabb.max.x, b.aabb.min.y, b.aabb.max.y, b.aabb.min.z, b.aabb.max.z };
    aabb->SetTypedTuple(o, ab);
    double ob[15];
    for (int k = 0; k < 3; ++k)
    {
      ob[k] = b.obb.center[k];
      ob[3 + k] = b.obb.axis[0][k];
      ob[6 + k] = b.obb.axis[1][k];
      ob[9 + k] = b.obb.axis[2][k];
      ob[12 + k] = b.obb.half[k];
    }
    box->SetTypedTuple(o, ob);
    const double cn[4] = { b.cone.axis.x, b.cone.axis.y, b.cone.axis.z, b.cone.cosAngle };
    cone->SetTypedTuple(o, cn);
    const ss::Box& pb = b.pieceBounds;
    const double pbv[6] = { pb.min.x, pb.max.x, pb.min.y, pb.max.y, pb.min.z, pb.max.z };
    pieceBounds->SetTypedTuple(o, pbv);
    clusterClosed->SetValue(o, b.closedOutward ? 1 : 0);
  }
  fd->AddArray(range);
  fd->AddArray(aabb);
  fd->AddArray(box);
  fd->AddArray(cone);
  fd->AddArray(clusterClosed);
  fd->AddArray(pieceBounds);
  report.Count("Clusters", static_cast<double>(nClusters));
  report.Count("OutputTriangles", static_cast<double>(nTri));
  for (const auto& c : report.counts)
  {
    fd->AddArray(Scalar<vtkIdType, vtkIdTypeArray>(c.first.c_str(), static_cast<vtkIdType>(c.second)));
  }
  fd->AddArray(Scalar<double, vtkDoubleArray>("WeldToleranceAbsolute", tolerance));
  report.Stage("output");
  report.ms.emplace_back("total", Ms(tStart, Clock::now()));
  report.cpu.emplace_back("total", CpuMs() - cpuStart);

  std::ostringstream text, json;
  json << std::setprecision(10) << "{\"counts\": {";
  for (std::size_t i = 0; i < report.counts.size(); ++i)
  {
    text << report.counts[i].first << ": " << static_cast<long long>(report.counts[i].second) << "\n";
    json << (i ? ", " : "") << "\"" << report.counts[i].first
         << "\": " << static_cast<long long>(report.counts[i].second);
  }
  text << "WeldToleranceAbsolute: " << tolerance << "\n";
  json << "}, \"weld_tolerance_absolute\": " << tolerance << ", \"timings_ms\": {";
  for (std::size_t i = 0; i < report.ms.size(); ++i)
  {
    text << "time_ms." << report.ms[i].first << ": " << std::fixed << std::setprecision(1)
         << report.ms[i].second << std::defaultfloat << "\n";
    json << (i ? ", " : "") << "\"" << report.ms[i].first << "\": " << report.ms[i].second;
  }
  json << "}, \"cpu_ms\": {";
  for (std::size_t i = 0; i < report.cpu.size(); ++i)
  {
    text << "cpu_ms." << report.cpu[i].first << ": " << std::fixed << std::setprecision(1)
         << report.cpu[i].second << std::defaultfloat << "\n";
    json << (i ? ", " : "") << "\"" << report.cpu[i].first << "\": " << report.cpu[i].second;
  }
  json << "}}";
  this->Report = text.str();
  this->ReportJSON = json.str();
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkShadowCasterPreparation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeldTolerance: " << this->WeldTolerance << "\n";
  os << indent << "SnapTJunctions: " << this->SnapTJunctions << "\n";
  os << indent << "CheckSelfIntersections: " << this->CheckSelfIntersections << "\n";
  os << indent << "OrientClosedPieces: " << this->OrientClosedPieces << "\n";
  os << indent << "MaximumClusterTriangles: " << this->MaximumClusterTriangles << "\n";
  os << indent << "OrientedBoxes: " << this->OrientedBoxes << "\n";
  os << indent << "Report:\n" << this->Report;
}
