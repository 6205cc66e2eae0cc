#include "vtkLightVisibilityFilter.h"

#include "ssCasterClusters.h"
#include "ssGEARS.h"
#include "ssLightFrame.h"
#include "ssPolyDataTriangles.h"
#include "ssReference.h"
#include "ssTriangleSet.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkSoftShadowLight.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkLightVisibilityFilter);

namespace
{
// Points per Solve call: progress and abort between calls; large enough that
// GEARS's per-call work on the casters (shadow-volume boxes, pair sort) stays
// a small part of the whole.
constexpr std::size_t kChunkPoints = 65536;

struct BakeLight
{
  int index = 0; // position in the collection: the array's name
  ss::LightFrame frame;
};

// The point array of light `index`: LightVisibility_0, LightVisibility_1, ...
std::string VisibilityArrayName(int index)
{
  return "LightVisibility_" + std::to_string(index);
}

// The frame of a vtkLight as vtkSoftShadowPass builds it (world coordinates).
bool FrameOf(vtkLight* light, ss::LightFrame& frame, std::string& why)
{
  try
  {
    frame = vtkSoftShadowLight::MakeLightFrame(light);
  }
  catch (const std::exception& e)
  {
    why = e.what();
    return false;
  }
  return true;
}

// World triangles (3 vertices each) and opacities of a caster surface; a
// surface without the opacity array is opaque (`found` tells whether it had it).
void AppendCasters(vtkPolyData* pd, const char* opacityName, std::vector<glm::dvec3>& tris,
  std::vector<float>& opacity, bool& found)
{
  if (!pd || pd->GetNumberOfPoints() == 0)
  {
    return;
  }
  const bool named = opacityName && *opacityName;
  vtkDataArray* op = named ? pd->GetCellData()->GetArray(opacityName) : nullptr;
  found = found || op;
  const ssf::PolyTriangles pt = ssf::Triangulate(pd, {});
  for (std::size_t t = 0; t < pt.tris.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      double p[3];
      pd->GetPoint(pt.tris[t][k], p);
      tris.emplace_back(p[0], p[1], p[2]);
    }
    opacity.push_back(op ? static_cast<float>(op->GetComponent(pt.cell[t], 0)) : 1.0f);
  }
}
}

//------------------------------------------------------------------------------
vtkLightVisibilityFilter::vtkLightVisibilityFilter()
  : Lights(vtkLightCollection::New())
{
  this->SetNumberOfInputPorts(2);
}

vtkLightVisibilityFilter::~vtkLightVisibilityFilter()
{
  this->Lights->Delete();
  this->SetOpacityArrayName(nullptr);
}

int vtkLightVisibilityFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

void vtkLightVisibilityFilter::AddLight(vtkLight* light)
{
  if (light)
  {
    this->Lights->AddItem(light);
    this->Modified();
  }
}

void vtkLightVisibilityFilter::RemoveAllLights()
{
  this->Lights->RemoveAllItems();
  this->Modified();
}

void vtkLightVisibilityFilter::SetLights(vtkLightCollection* lights)
{
  this->Lights->RemoveAllItems();
  if (lights)
  {
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    while (vtkLight* l = lights->GetNextLight(it))
    {
      this->Lights->AddItem(l);
    }
  }
  this->Modified();
}

vtkMTimeType vtkLightVisibilityFilter::GetMTime()
{
  vtkMTimeType t = std::max(this->Superclass::GetMTime(), this->Lights->GetMTime());
  vtkCollectionSimpleIterator it;
  this->Lights->InitTraversal(it);
  while (vtkLight* l = this->Lights->GetNextLight(it))
  {
    t = std::max(t, l->GetMTime());
    if (l->GetInformation())
    {
      t = std::max(t, l->GetInformation()->GetMTime());
    }
  }
  return t;
}

//------------------------------------------------------------------------------
int vtkLightVisibilityFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* casters = inputVector[1]->GetNumberOfInformationObjects() > 0
    ? vtkPolyData::GetData(inputVector[1])
    : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("vtkLightVisibilityFilter needs a vtkPolyData input.");
    return 0;
  }
  output->ShallowCopy(input);
  const vtkIdType n = input->GetNumberOfPoints();

  // --- lights
  std::vector<BakeLight> lights;
  if (this->Lights->GetNumberOfItems() == 0)
  {
    // (a negative size is refused like a NaN one; before, both sides <= 0
    // silently baked a point light)
    if (!(this->LightSize[0] >= 0.0 && this->LightSize[1] >= 0.0 && std::isfinite(this->LightSize[0]) &&
          std::isfinite(this->LightSize[1])))
    {
      vtkErrorMacro("LightSize: must be two finite non-negative numbers (got " << this->LightSize[0] << " x "
                                                                                << this->LightSize[1] << ").");
      return 0;
    }
    BakeLight b;
    try
    {
      b.frame = (this->LightSize[0] > 0.0 || this->LightSize[1] > 0.0)
        ? ss::MakeRectLightFrame(glm::dvec3(this->LightCenter[0], this->LightCenter[1], this->LightCenter[2]),
            glm::dvec3(this->LightNormal[0], this->LightNormal[1], this->LightNormal[2]),
            glm::dvec3(this->LightUp[0], this->LightUp[1], this->LightUp[2]),
            glm::dvec2(this->LightSize[0], this->LightSize[1]))
        : ss::MakePointLightFrame(glm::dvec3(this->LightCenter[0], this->LightCenter[1], this->LightCenter[2]));
    }
    catch (const std::exception& e)
    {
      vtkErrorMacro("LightCenter/LightNormal/LightUp/LightSize: " << e.what());
      return 0;
    }
    lights.push_back(b);
  }
  else
  {
    vtkCollectionSimpleIterator it;
    this->Lights->InitTraversal(it);
    int index = 0;
    while (vtkLight* l = this->Lights->GetNextLight(it))
    {
      const int i = index++;
      if (l->GetSwitch() <= 0 || l->LightTypeIsHeadlight() || !vtkSoftShadowLight::GetCastsShadows(l))
      {
        continue;
      }
      BakeLight b;
      b.index = i;
      std::string why;
      if (!FrameOf(l, b.frame, why))
      {
        vtkErrorMacro("light " << i << ": " << why);
        return 0;
      }
      lights.push_back(b);
    }
  }
  // A light beyond 1e30 (the render pass's largest light size too): the
  // solvers' squares of such coordinates leave the float and then the double
  // range, and the shadow silently vanished (GEARS from 1e37, both solvers
  // from 1e155). A sun is a directional light.
  // A rect light's side beyond 1e30 is shadowed as one of 1e30, the same
  // shadow, as the render pass does (ss::ClampRectLightSize): from about
  // 1e155 the reference's sample distances overflowed when squared, its rays
  // had no direction and hit nothing (V = 1 where GEARS gives 0.48).
  for (BakeLight& b : lights)
  {
    ss::ClampRectLightSize(b.frame);
    const glm::dvec3& c = b.frame.center;
    if (b.frame.type != ss::LightType::Directional &&
      !(std::abs(c.x) <= 1e30 && std::abs(c.y) <= 1e30 && std::abs(c.z) <= 1e30))
    {
      vtkErrorMacro(<< (this->Lights->GetNumberOfItems() == 0 ? std::string("LightCenter")
                                                               : "light " + std::to_string(b.index))
        << ": farther than 1e30 from the origin (" << c.x << ", " << c.y << ", " << c.z
        << "); a light that far is a directional light.");
      return 0;
    }
  }
  if (n == 0)
  {
    // no points: the arrays, empty, so that a pipeline colouring or
    // thresholding by them finds them (stop 53: they were missing)
    for (const BakeLight& l : lights)
    {
      vtkNew<vtkFloatArray> v;
      v->SetName(VisibilityArrayName(l.index).c_str());
      output->GetPointData()->AddArray(v);
    }
    return 1;
  }

  // --- casters
  std::vector<glm::dvec3> tris;
  std::vector<float> opacity;
  bool foundOpacity = false;
  if (this->InputCastsShadows)
  {
    AppendCasters(input, this->OpacityArrayName, tris, opacity, foundOpacity);
  }
  AppendCasters(casters, this->OpacityArrayName, tris, opacity, foundOpacity);
  if (this->OpacityArrayName && *this->OpacityArrayName && !foundOpacity)
  {
    vtkErrorMacro("OpacityArrayName: no caster surface has a cell array '" << this->OpacityArrayName << "'.");
    return 0;
  }

  // --- receivers: positions relative to the centre of their bounds, normals
  vtkDataArray* normals = input->GetPointData()->GetNormals();
  vtkSmartPointer<vtkPolyData> withNormals;
  if (!normals)
  {
    vtkNew<vtkPolyDataNormals> pn;
    pn->SetInputData(input);
    pn->SplittingOff();
    pn->ConsistencyOn();
    pn->ComputePointNormalsOn();
    pn->ComputeCellNormalsOff();
    pn->Update();
    withNormals = pn->GetOutput();
    // vtkPolyDataNormals keeps the points (no splitting)
    if (withNormals->GetNumberOfPoints() == n)
    {
      normals = withNormals->GetPointData()->GetNormals();
    }
  }
  // The float origin: the centre of the points the solvers can take (finite,
  // within 1e30, as the lights); the others get NaN. Before (stop 45's
  // Python sweep) it was the bounds' centre, so one infinite point put the
  // origin at infinity and every output value was NaN.
  auto usable = [](const double* p) { return ss::WithinSolverReach(glm::dvec3(p[0], p[1], p[2])); };
  glm::dvec3 lo(HUGE_VAL), hi(-HUGE_VAL);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    if (usable(p))
    {
      lo = glm::min(lo, glm::dvec3(p[0], p[1], p[2]));
      hi = glm::max(hi, glm::dvec3(p[0], p[1], p[2]));
    }
  }
  const glm::dvec3 origin = lo.x <= hi.x ? 0.5 * lo + 0.5 * hi : glm::dvec3(0.0);
  // Morton order in chunks: each Solve call gets a compact set of points (a
  // tight GEARS grid) and progress is reported between calls.
  std::vector<glm::dvec3> asTriangles(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    if (!usable(p))
    {
      p[0] = origin.x; // (ordered with the others; solved as NaN)
      p[1] = origin.y;
      p[2] = origin.z;
    }
    asTriangles[3 * i] = asTriangles[3 * i + 1] = asTriangles[3 * i + 2] = glm::dvec3(p[0], p[1], p[2]);
  }
  const ss::TriangleClusters chunks = ss::ClusterTriangles(asTriangles, kChunkPoints);
  asTriangles.clear();
  std::vector<float> positions(3 * static_cast<std::size_t>(n)), nrm(3 * static_cast<std::size_t>(n), 0.0f);
  for (std::size_t i = 0; i < chunks.order.size(); ++i)
  {
    const vtkIdType id = static_cast<vtkIdType>(chunks.order[i]);
    double p[3];
    input->GetPoint(id, p);
    for (int k = 0; k < 3; ++k)
    {
      positions[3 * i + k] = usable(p) ? static_cast<float>(p[k] - origin[k]) : std::nanf("");
    }
    if (normals)
    {
      double q[3];
      normals->GetTuple(id, q);
      for (int k = 0; k < 3; ++k)
      {
        nrm[3 * i + k] = static_cast<float>(q[k]);
      }
    }
  }

  // --- solve, light by light, chunk by chunk
  ss::GearsSolver gears;
  ss::ReferenceSolver reference;
  if (this->Method == METHOD_GEARS)
  {
    gears.SetTriangles(tris, opacity);
  }
  else
  {
    reference.SetTriangles(tris, opacity);
  }
  tris.clear();
  ss::GearsOptions go;
  go.k = this->Samples;
  ss::ReferenceOptions ro;
  ro.k = this->Samples;
  ro.pattern = ss::LightSamplePattern::Regular;
  const std::size_t steps = std::max<std::size_t>(1, lights.size() * chunks.Clusters());
  std::size_t step = 0;
  for (const BakeLight& l : lights)
  {
    vtkNew<vtkFloatArray> v;
    v->SetName(VisibilityArrayName(l.index).c_str());
    v->SetNumberOfTuples(n);
    for (std::size_t c = 0; c < chunks.Clusters(); ++c)
    {
      const std::size_t first = chunks.first[c], count = chunks.first[c + 1] - first;
      const float* pc = positions.data() + 3 * first;
      const float* nc = nrm.data() + 3 * first;
      const std::vector<float> vis = this->Method == METHOD_GEARS
        ? gears.Solve(l.frame, origin, pc, normals ? nc : nullptr, count, go)
        : reference.Solve(l.frame, origin, pc, normals ? nc : nullptr, count, ro);
      for (std::size_t i = 0; i < count; ++i)
      {
        v->SetValue(static_cast<vtkIdType>(chunks.order[first + i]), vis[i]);
      }
      this->UpdateProgress(static_cast<double>(++step) / static_cast<double>(steps));
      if (this->CheckAbort())
      {
        return 1;
      }
    }
    output->GetPointData()->AddArray(v);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkLightVisibilityFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << (this->Method == METHOD_GEARS ? "GEARS" : "Reference") << "\n";
  os << indent << "Samples: " << this->Samples << "\n";
  os << indent << "InputCastsShadows: " << this->InputCastsShadows << "\n";
  os << indent << "OpacityArrayName: " << (this->OpacityArrayName ? this->OpacityArrayName : "(none)") << "\n";
  os << indent << "Lights: " << this->Lights->GetNumberOfItems() << "\n";
  os << indent << "LightCenter: " << this->LightCenter[0] << " " << this->LightCenter[1] << " "
     << this->LightCenter[2] << "\n";
  os << indent << "LightNormal: " << this->LightNormal[0] << " " << this->LightNormal[1] << " "
     << this->LightNormal[2] << "\n";
  os << indent << "LightUp: " << this->LightUp[0] << " " << this->LightUp[1] << " " << this->LightUp[2] << "\n";
  os << indent << "LightSize: " << this->LightSize[0] << " " << this->LightSize[1] << "\n";
}
