// libFuzzer target: the STL guard and the guarded read (ssFuzzMesh.h).
#include "ssFuzzMesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return ssfuzz::FuzzMesh(data, size, ss::io::MeshFormat::STL, ".stl");
}
