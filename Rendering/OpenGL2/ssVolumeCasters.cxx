#include "ssVolumeCasters.h"

#include "ssCasterSet.h"

#include "vtkAbstractVolumeMapper.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkSetGet.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtk_glew.h"

#include <algorithm>
#include <cmath>

namespace ss
{
bool VolumeCasters::MakeGrid(vtkVolume* volume, VolumeGrid& grid, std::string& why)
{
  auto* mapper = vtkAbstractVolumeMapper::SafeDownCast(volume->GetMapper());
  auto* image = mapper ? vtkImageData::SafeDownCast(mapper->GetInputDataObject(0, 0)) : nullptr;
  vtkVolumeProperty* property = volume->GetProperty();
  if (!image || !property)
  {
    why = "a volume whose mapper does not read image data casts no shadow";
    return false;
  }
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(image, mapper->GetScalarMode(), mapper->GetArrayAccessMode(),
    mapper->GetArrayId(), mapper->GetArrayName(), cellFlag);
  if (!scalars || cellFlag != 0)
  {
    why = "a volume without point scalars casts no shadow";
    return false;
  }
  if (scalars->GetNumberOfComponents() > 1 && !property->GetIndependentComponents())
  {
    why = "a volume of dependent components (RGBA) casts no shadow";
    return false;
  }
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  const double unit = property->GetScalarOpacityUnitDistance(0);
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || !opacity)
  {
    why = "an empty volume casts no shadow";
    return false;
  }
  // average blocks of s^3 points down to at most kMaxVoxels
  int s = 1;
  while (static_cast<long long>((dims[0] + s - 1) / s) * ((dims[1] + s - 1) / s) * ((dims[2] + s - 1) / s) > kMaxVoxels)
  {
    ++s;
  }
  grid.dims = { (dims[0] + s - 1) / s, (dims[1] + s - 1) / s, (dims[2] + s - 1) / s };
  grid.sigma.assign(static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2], 0.0f);
  std::vector<int> hits(grid.sigma.size(), 0);
  const int nc = scalars->GetNumberOfComponents();
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const vtkIdType id = (static_cast<vtkIdType>(k) * dims[1] + j) * dims[0] + i;
        const double v = scalars->GetComponent(id, 0);
        (void)nc;
        const double sigma = std::isfinite(v) ? ExtinctionFromOpacity(opacity->GetValue(v), unit) : 0.0;
        const std::size_t g = (static_cast<std::size_t>(k / s) * grid.dims[1] + j / s) * grid.dims[0] + i / s;
        grid.sigma[g] += static_cast<float>(sigma);
        ++hits[g];
      }
    }
  }
  for (std::size_t g = 0; g < grid.sigma.size(); ++g)
  {
    grid.sigma[g] = hits[g] ? grid.sigma[g] / static_cast<float>(hits[g]) : 0.0f;
  }
  grid.UpdateUniform();
  // world: the prop's matrix times (origin + direction * (spacing * index))
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  vtkMatrix3x3* dir = image->GetDirectionMatrix();
  vtkMatrix4x4* m = volume->GetMatrix();
  glm::dmat3 M3, D;
  glm::dvec3 t;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      M3[c][r] = m->GetElement(r, c);
      D[c][r] = dir->GetElement(r, c);
    }
    t[r] = m->GetElement(r, 3);
  }
  const glm::dvec3 o(origin[0], origin[1], origin[2]);
  grid.origin = M3 * o + t;
  glm::dmat3 step(0.0);
  for (int a = 0; a < 3; ++a)
  {
    step[a][a] = spacing[a] * s;
  }
  grid.axes = M3 * D * step;
  // a grid of one point along an axis has no extent there: it casts nothing
  if (std::abs(glm::determinant(grid.axes)) < 1e-300)
  {
    why = "a volume with no extent (zero spacing or scale) casts no shadow";
    return false;
  }
  return true;
}

void VolumeCasters::Update(const CasterSet& casters, vtkObject* reporter)
{
  if (this->HaveVersion && this->Version == casters.VolumeVersion)
  {
    return;
  }
  this->HaveVersion = true;
  this->Version = casters.VolumeVersion;
  this->GridList.clear();
  std::string warning;
  for (vtkVolume* v : casters.Volumes)
  {
    VolumeGrid g;
    std::string why;
    if (MakeGrid(v, g, why))
    {
      this->GridList.push_back(std::move(g));
    }
    else if (warning.find(why) == std::string::npos)
    {
      warning += (warning.empty() ? "" : "; ") + why;
    }
  }
  if (this->GridList.size() > static_cast<std::size_t>(kMaxGPUVolumes))
  {
    warning += (warning.empty() ? "" : "; ") + std::string("only the first ") + std::to_string(kMaxGPUVolumes) +
      " volumes cast shadows on the GPU";
  }
  if (!warning.empty() && warning != this->Warned)
  {
    vtkWarningWithObjectMacro(reporter, "Volume shadows: " << warning << ".");
  }
  this->Warned = warning;
}

Box VolumeCasters::Bounds() const
{
  Box b;
  for (const auto& g : this->GridList)
  {
    b.Add(g.Bounds());
  }
  return b;
}

const std::vector<vtkSmartPointer<vtkTextureObject>>& VolumeCasters::Textures(vtkOpenGLRenderWindow* win, int max3D)
{
  const std::size_t n = std::min<std::size_t>(this->GridList.size(), kMaxGPUVolumes);
  if (this->GPU.size() == n && this->UploadedVersion == this->Version && n > 0)
  {
    return this->GPU;
  }
  this->ReleaseGraphicsResources(win);
  for (std::size_t i = 0; i < n; ++i)
  {
    VolumeGrid g = this->GridList[i];
    // a grid wider than the GL allows is averaged down like a large volume
    int s = 1;
    while ((g.dims[0] + s - 1) / s > max3D || (g.dims[1] + s - 1) / s > max3D || (g.dims[2] + s - 1) / s > max3D)
    {
      ++s;
    }
    std::vector<float> data = g.sigma;
    std::array<int, 3> dims = g.dims;
    if (s > 1)
    {
      dims = { (g.dims[0] + s - 1) / s, (g.dims[1] + s - 1) / s, (g.dims[2] + s - 1) / s };
      data.assign(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0.0f);
      std::vector<int> hits(data.size(), 0);
      for (int k = 0; k < g.dims[2]; ++k)
      {
        for (int j = 0; j < g.dims[1]; ++j)
        {
          for (int x = 0; x < g.dims[0]; ++x)
          {
            const std::size_t d = (static_cast<std::size_t>(k / s) * dims[1] + j / s) * dims[0] + x / s;
            data[d] += g.sigma[(static_cast<std::size_t>(k) * g.dims[1] + j) * g.dims[0] + x];
            ++hits[d];
          }
        }
      }
      for (std::size_t d = 0; d < data.size(); ++d)
      {
        data[d] /= static_cast<float>(std::max(hits[d], 1));
      }
    }
    auto tex = vtkSmartPointer<vtkTextureObject>::New();
    tex->SetContext(win);
    tex->SetInternalFormat(GL_R32F);
    tex->SetFormat(GL_RED);
    tex->SetDataType(GL_FLOAT);
    tex->SetWrapS(vtkTextureObject::ClampToEdge);
    tex->SetWrapT(vtkTextureObject::ClampToEdge);
    tex->SetWrapR(vtkTextureObject::ClampToEdge);
    tex->SetMinificationFilter(vtkTextureObject::Linear);
    tex->SetMagnificationFilter(vtkTextureObject::Linear);
    if (!tex->Create3DFromRaw(static_cast<unsigned>(dims[0]), static_cast<unsigned>(dims[1]),
          static_cast<unsigned>(dims[2]), 1, VTK_FLOAT, data.data()))
    {
      continue;
    }
    this->GPU.push_back(tex);
    VolumeGrid geometry;
    geometry.dims = dims;
    geometry.origin = g.origin;
    geometry.axes = g.axes * static_cast<double>(s);
    this->GPUGeometry.push_back(geometry);
  }
  this->UploadedVersion = this->Version;
  return this->GPU;
}

long long VolumeCasters::Bytes() const
{
  long long b = 0;
  for (const auto& t : this->GPU)
  {
    b += static_cast<long long>(t->GetWidth()) * t->GetHeight() * t->GetDepth() * 4;
  }
  return b;
}

int VolumeCasters::CountGraphicsResources() const
{
  return static_cast<int>(this->GPU.size());
}

void VolumeCasters::ReleaseGraphicsResources(vtkWindow* w)
{
  for (auto& t : this->GPU)
  {
    t->ReleaseGraphicsResources(w);
  }
  this->GPU.clear();
  this->GPUGeometry.clear();
}
}
