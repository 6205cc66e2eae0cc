// What every mesh fuzz target does with one input: the format guard alone
// (instrumented, fast), then, when it accepts the bytes, the whole guarded
// read (vtkShadowMeshReader: guard, VTK's or OpenMesh's reader, the check of
// the result) from a file. A crash, a sanitizer report, or an accepted file
// whose output has a cell index out of range is a finding.
#ifndef ssFuzzMesh_h
#define ssFuzzMesh_h

#include "ssMeshCheck.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPolyData.h"
#include "vtkShadowMeshReader.h"
#include "vtkSmartPointer.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace ssfuzz
{
class Quiet : public vtkCommand
{
public:
  static Quiet* New() { return new Quiet; }
  void Execute(vtkObject*, unsigned long, void*) override {}
};

inline std::string TempPath(const char* ext)
{
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/ssfuzz-" + std::to_string(::getpid()) + ext;
}

inline void CheckIds(vtkCellArray* cells, vtkIdType n)
{
  auto it = vtk::TakeSmartPointer(cells->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    it->GetCurrentCell(npts, ids);
    for (vtkIdType k = 0; k < npts; ++k)
    {
      if (ids[k] < 0 || ids[k] >= n)
      {
        std::fprintf(stderr, "accepted file gave a cell index %lld of %lld points\n",
          static_cast<long long>(ids[k]), static_cast<long long>(n));
        std::abort();
      }
    }
  }
}

inline int FuzzMesh(const std::uint8_t* data, std::size_t size, ss::io::MeshFormat format, const char* ext)
{
  vtkObject::GlobalWarningDisplayOff();
  const ss::io::MeshCheck check = ss::io::CheckMesh(format, reinterpret_cast<const char*>(data), size);
  if (!check.Ok)
  {
    if (check.Error.empty())
    {
      std::abort(); // a refusal always says why
    }
    return 0;
  }
  const std::string path = TempPath(ext);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
  {
    return 0;
  }
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  vtkNew<vtkShadowMeshReader> reader;
  vtkNew<Quiet> quiet;
  reader->AddObserver(vtkCommand::ErrorEvent, quiet);
  reader->AddObserver(vtkCommand::WarningEvent, quiet);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* out = reader->GetOutput();
  if (reader->GetErrorMessage()[0] == '\0')
  {
    if (out->GetNumberOfPoints() == 0 || out->GetNumberOfCells() == 0)
    {
      std::fprintf(stderr, "no error and no surface\n");
      std::abort();
    }
    CheckIds(out->GetPolys(), out->GetNumberOfPoints());
    CheckIds(out->GetStrips(), out->GetNumberOfPoints());
    CheckIds(out->GetLines(), out->GetNumberOfPoints());
    CheckIds(out->GetVerts(), out->GetNumberOfPoints());
  }
  else if (out->GetNumberOfCells() != 0)
  {
    std::fprintf(stderr, "an error and a partial mesh\n");
    std::abort();
  }
  std::remove(path.c_str());
  return 0;
}
}

#endif
