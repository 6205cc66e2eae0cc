#include "vtkShadowMeshReader.h"

#include "ssMeshCheck.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellTypes.h"
#include "vtkCommand.h"
#include "vtkDataSetReader.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkExecutive.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkObjectFactory.h"
#include "vtkPLYReader.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSTLReader.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataReader.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <exception>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkShadowMeshReader);

namespace
{
// The first error or warning an inner reader (or its executive) reports, as
// one line; observing it also keeps the reader from printing it.
class FirstMessage : public vtkCommand
{
public:
  static FirstMessage* New() { return new FirstMessage; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    if (!data)
    {
      return;
    }
    const std::string m = ss::io::OneLineMessage(static_cast<const char*>(data));
    if (event == vtkCommand::ErrorEvent && this->Error.empty())
    {
      this->Error = m;
    }
    else if (event == vtkCommand::WarningEvent && this->Warning.empty())
    {
      this->Warning = m;
    }
  }
  std::string Error;
  std::string Warning;
};

template <typename Reader>
void Observe(Reader* r, FirstMessage* m)
{
  r->AddObserver(vtkCommand::ErrorEvent, m);
  r->AddObserver(vtkCommand::WarningEvent, m);
  r->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, m);
}

// Runs one of VTK's polydata readers on `file`, its messages observed.
template <typename Reader>
vtkSmartPointer<vtkPolyData> ReadWith(Reader* r, const std::string& file, FirstMessage* m)
{
  Observe(r, m);
  r->SetFileName(file.c_str());
  r->Update();
  return r->GetOutput();
}

// Every point id of every cell in [0, npts).
bool CellsInRange(vtkCellArray* cells, vtkIdType npts, std::string& what)
{
  if (!cells)
  {
    return true;
  }
  auto it = vtk::TakeSmartPointer(cells->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      if (ids[k] < 0 || ids[k] >= npts)
      {
        what = "cell " + std::to_string(it->GetCurrentCellId()) + " refers to point " + std::to_string(ids[k]) +
          " of " + std::to_string(npts);
        return false;
      }
    }
  }
  return true;
}

bool PolyDataInRange(vtkPolyData* pd, std::string& what)
{
  const vtkIdType n = pd->GetNumberOfPoints();
  return CellsInRange(pd->GetVerts(), n, what) && CellsInRange(pd->GetLines(), n, what) &&
    CellsInRange(pd->GetPolys(), n, what) && CellsInRange(pd->GetStrips(), n, what);
}

vtkSmartPointer<vtkPolyData> ReadOFF(const std::string& path, std::string& error, std::string& warning,
  std::uint64_t declaredFaces)
{
  // OpenMesh reports problems on its own streams; the error names the file.
  omerr().disable();
  omlog().disable();
  omout().disable();
  OpenMesh::PolyMesh_ArrayKernelT<> mesh;
  if (!OpenMesh::IO::read_mesh(mesh, path))
  {
    error = "OpenMesh could not read the OFF file";
    return nullptr;
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(mesh.n_vertices()));
  for (auto v : mesh.vertices())
  {
    const auto p = mesh.point(v);
    pts->SetPoint(v.idx(), p[0], p[1], p[2]);
  }
  vtkNew<vtkCellArray> polys;
  std::vector<vtkIdType> ids;
  for (auto f : mesh.faces())
  {
    ids.clear();
    for (auto fv : mesh.fv_range(f))
    {
      ids.push_back(fv.idx());
    }
    polys->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  if (mesh.n_faces() < declaredFaces)
  {
    warning = "OpenMesh kept " + std::to_string(mesh.n_faces()) + " of the " + std::to_string(declaredFaces) +
      " faces (it cannot add a face that repeats a vertex)";
  }
  return pd;
}
}

vtkShadowMeshReader::vtkShadowMeshReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkShadowMeshReader::~vtkShadowMeshReader()
{
  this->SetFileName(nullptr);
}

bool vtkShadowMeshReader::IsSupportedFileName(const char* name)
{
  return name && ss::io::FormatFromPath(name) != ss::io::MeshFormat::Unknown;
}

int vtkShadowMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  output->Initialize();
  this->ErrorMessage.clear();
  const std::string file = this->FileName ? this->FileName : "";
  auto fail = [&](const std::string& what) {
    this->ErrorMessage = (file.empty() ? std::string("(no file name)") : file) + ": " + what;
    output->Initialize();
    vtkErrorMacro(<< this->ErrorMessage);
    return 1;
  };
  if (file.empty())
  {
    return fail("no FileName set");
  }
  const ss::io::MeshFormat format = ss::io::FormatFromPath(file);
  if (format == ss::io::MeshFormat::Unknown)
  {
    return fail("unsupported mesh format (expected .vtp .vtk .stl .ply .obj .off)");
  }
  ss::io::MeshLimits limits;
  limits.MaximumFileBytes = static_cast<std::uint64_t>(this->MaximumFileSize);
  const ss::io::MeshCheck check = ss::io::CheckMeshFile(file, format, limits);
  if (!check.Ok)
  {
    return fail(std::string(ss::io::FormatName(format)) + ": " + check.Error);
  }

  vtkSmartPointer<vtkPolyData> result;
  vtkNew<FirstMessage> messages;
  std::string offWarning;
  try
  {
    switch (format)
    {
      case ss::io::MeshFormat::STL:
      {
        vtkNew<vtkSTLReader> r;
        r->SetMerging(check.NonFiniteVertices == 0);
        result = ReadWith(r.Get(), file, messages);
        break;
      }
      case ss::io::MeshFormat::PLY:
        result = ReadWith(vtkNew<vtkPLYReader>().Get(), file, messages);
        break;
      case ss::io::MeshFormat::OBJ:
        result = ReadWith(vtkNew<vtkOBJReader>().Get(), file, messages);
        break;
      case ss::io::MeshFormat::VTP:
        result = ReadWith(vtkNew<vtkXMLPolyDataReader>().Get(), file, messages);
        break;
      case ss::io::MeshFormat::LegacyVTK:
      {
        vtkNew<vtkDataSetReader> r;
        Observe(r.Get(), messages);
        r->SetFileName(file.c_str());
        r->Update();
        if (!messages->Error.empty())
        {
          break;
        }
        vtkDataSet* ds = vtkDataSet::SafeDownCast(r->GetOutputDataObject(0));
        if (!ds)
        {
          return fail("legacy VTK: the file holds no dataset");
        }
        // indices checked before the surface filter walks the cells
        std::string what;
        if (auto* pd = vtkPolyData::SafeDownCast(ds))
        {
          if (!PolyDataInRange(pd, what))
          {
            return fail("legacy VTK: " + what);
          }
        }
        else if (auto* ug = vtkUnstructuredGrid::SafeDownCast(ds))
        {
          if (!CellsInRange(ug->GetCells(), ug->GetNumberOfPoints(), what))
          {
            return fail("legacy VTK: " + what);
          }
          for (vtkIdType c = 0; c < ug->GetNumberOfCells(); ++c)
          {
            const int t = ug->GetCellType(c);
            if (t <= 0 || t >= VTK_NUMBER_OF_CELL_TYPES)
            {
              return fail("legacy VTK: cell " + std::to_string(c) + " has the unknown cell type " + std::to_string(t));
            }
          }
        }
        vtkNew<vtkDataSetSurfaceFilter> surf;
        Observe(surf.Get(), messages);
        surf->SetInputData(ds);
        surf->Update();
        result = surf->GetOutput();
        break;
      }
      case ss::io::MeshFormat::OFF:
      {
        std::string error;
        result = ReadOFF(file, error, offWarning, check.Faces);
        if (!result)
        {
          return fail("OFF: " + error);
        }
        break;
      }
      default:
        break;
    }
  }
  catch (const std::exception& e)
  {
    return fail(std::string(ss::io::FormatName(format)) + ": reading failed: " + e.what());
  }
  if (!messages->Error.empty())
  {
    return fail(std::string(ss::io::FormatName(format)) + ": " + messages->Error);
  }
  if (!result || result->GetNumberOfPoints() == 0 || result->GetNumberOfCells() == 0)
  {
    return fail(std::string(ss::io::FormatName(format)) + ": no surface in the file" +
      (messages->Warning.empty() ? std::string() : " (" + messages->Warning + ")"));
  }
  std::string what;
  if (!PolyDataInRange(result, what))
  {
    return fail(std::string(ss::io::FormatName(format)) + ": " + what);
  }
  // the reader must have read what the file declares
  if (format == ss::io::MeshFormat::PLY &&
    (static_cast<std::uint64_t>(result->GetNumberOfPoints()) != check.Vertices ||
      static_cast<std::uint64_t>(result->GetNumberOfPolys()) != check.Faces))
  {
    return fail("PLY: VTK read " + std::to_string(result->GetNumberOfPoints()) + " vertices and " +
      std::to_string(result->GetNumberOfPolys()) + " faces of the " + std::to_string(check.Vertices) + " and " +
      std::to_string(check.Faces) + " the file holds");
  }
  if (format == ss::io::MeshFormat::OBJ && static_cast<std::uint64_t>(result->GetNumberOfPolys()) != check.Faces)
  {
    return fail("OBJ: VTK read " + std::to_string(result->GetNumberOfPolys()) + " of the " +
      std::to_string(check.Faces) + " faces the file holds");
  }
  if (!offWarning.empty())
  {
    vtkWarningMacro(<< file << ": " << offWarning);
  }
  output->ShallowCopy(result);
  return 1;
}

void vtkShadowMeshReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "MaximumFileSize: " << this->MaximumFileSize << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}
