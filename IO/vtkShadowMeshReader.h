/**
 * @class   vtkShadowMeshReader
 * @brief   Reads a surface mesh (.stl .ply .obj .off .vtk .vtp) and refuses a
 *          damaged file with one clear error instead of crashing, hanging or
 *          returning part of a mesh.
 *
 * VTK's and OpenMesh's readers trust their input. Before one of them sees
 * the file, this reader walks it the way that reader will (ss::io::CheckMesh):
 * header counts against the file's size, every index in range (OBJ relative
 * indices too), line lengths against the readers' buffers, no data missing or
 * left over, and a size limit. After the read it checks every cell index of
 * the result. .stl .ply .obj .vtk .vtp are read by VTK's readers; .off by
 * OpenMesh. A .vtk file may hold any dataset: its outer surface is returned.
 *
 * A bad file gives one error through vtkErrorMacro (an ErrorEvent that an
 * observer can catch), "FILE: what is wrong", an empty output, and
 * GetErrorMessage() returns the same line; the process goes on. Triangles with
 * a non-finite vertex are kept (the shadow pass drops them with a warning);
 * for STL, point merging is then turned off, since VTK's point locator needs
 * finite bounds.
 */
#ifndef vtkShadowMeshReader_h
#define vtkShadowMeshReader_h

#include "SoftShadowsIOModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <string>

class SOFTSHADOWSIO_EXPORT vtkShadowMeshReader : public vtkPolyDataAlgorithm
{
public:
  static vtkShadowMeshReader* New();
  vtkTypeMacro(vtkShadowMeshReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The mesh file; the format comes from its extension (case-insensitive).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /**
   * Files larger than this many bytes are refused before anything is read
   * (default 4 GiB). The error names the limit.
   */
  vtkSetClampMacro(MaximumFileSize, vtkTypeInt64, 1, VTK_TYPE_INT64_MAX);
  vtkGetMacro(MaximumFileSize, vtkTypeInt64);
  ///@}

  /**
   * The error of the last update ("FILE: what is wrong"), or "" after a good
   * read.
   */
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

  /**
   * Whether the extension is one this reader takes (.stl .ply .obj .off .vtk
   * .vtp); the file itself is not opened.
   */
  static bool IsSupportedFileName(const char* name);

protected:
  vtkShadowMeshReader();
  ~vtkShadowMeshReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  vtkTypeInt64 MaximumFileSize = vtkTypeInt64(4) << 30;
  std::string ErrorMessage;

private:
  vtkShadowMeshReader(const vtkShadowMeshReader&) = delete;
  void operator=(const vtkShadowMeshReader&) = delete;
};

#endif
