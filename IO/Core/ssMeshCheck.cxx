#include "ssMeshCheck.h"

#include "ssCheckText.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ss
{
namespace io
{
MeshFormat FormatFromPath(const std::string& path)
{
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
  {
    return MeshFormat::Unknown;
  }
  std::string ext = path.substr(dot + 1);
  for (char& c : ext)
  {
    c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  }
  if (ext == "stl")
    return MeshFormat::STL;
  if (ext == "ply")
    return MeshFormat::PLY;
  if (ext == "obj")
    return MeshFormat::OBJ;
  if (ext == "off")
    return MeshFormat::OFF;
  if (ext == "vtk")
    return MeshFormat::LegacyVTK;
  if (ext == "vtp")
    return MeshFormat::VTP;
  return MeshFormat::Unknown;
}

const char* FormatName(MeshFormat f)
{
  switch (f)
  {
    case MeshFormat::STL:
      return "STL";
    case MeshFormat::PLY:
      return "PLY";
    case MeshFormat::OBJ:
      return "OBJ";
    case MeshFormat::OFF:
      return "OFF";
    case MeshFormat::LegacyVTK:
      return "legacy VTK";
    case MeshFormat::VTP:
      return "VTK XML PolyData";
    default:
      return "unknown";
  }
}

std::string OneLineMessage(std::string m)
{
  const auto where = m.find(", line ");
  const auto addr = m.find("): ");
  if (where != std::string::npos && addr != std::string::npos && where < addr)
  {
    m = m.substr(addr + 3);
  }
  for (char& c : m)
  {
    c = c == '\n' ? ' ' : c;
  }
  while (!m.empty() && (m.back() == ' ' || m.back() == '\r'))
  {
    m.pop_back();
  }
  return m;
}

MeshCheck CheckMesh(MeshFormat f, const char* data, std::size_t size, const MeshLimits& limits)
{
  if (size > limits.MaximumFileBytes)
  {
    return detail::Fail("the file is " + std::to_string(size) + " bytes, above the limit of " +
      std::to_string(limits.MaximumFileBytes) + " bytes (MaximumFileBytes)");
  }
  if (size == 0)
  {
    return detail::Fail("empty file");
  }
  switch (f)
  {
    case MeshFormat::STL:
      return CheckSTL(data, size);
    case MeshFormat::PLY:
      return CheckPLY(data, size);
    case MeshFormat::OBJ:
      return CheckOBJ(data, size);
    case MeshFormat::OFF:
      return CheckOFF(data, size);
    case MeshFormat::LegacyVTK:
      return CheckLegacyVTK(data, size);
    case MeshFormat::VTP:
      return CheckVTP(data, size);
    default:
      return detail::Fail("unsupported mesh format (expected .vtp .vtk .stl .ply .obj .off)");
  }
}

MeshCheck CheckMeshFile(const std::string& path, MeshFormat f, const MeshLimits& limits)
{
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
  {
    return detail::Fail(std::string("cannot open: ") + std::strerror(errno));
  }
  struct stat st;
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
  {
    ::close(fd);
    return detail::Fail("not a regular file");
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > limits.MaximumFileBytes)
  {
    ::close(fd);
    return detail::Fail("the file is " + std::to_string(size) + " bytes, above the limit of " +
      std::to_string(limits.MaximumFileBytes) + " bytes (MaximumFileBytes)");
  }
  if (size == 0)
  {
    ::close(fd);
    return detail::Fail("empty file");
  }
  void* map = ::mmap(nullptr, static_cast<std::size_t>(size), PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (map == MAP_FAILED)
  {
    return detail::Fail(std::string("cannot map the file: ") + std::strerror(errno));
  }
  MeshCheck r = CheckMesh(f, static_cast<const char*>(map), static_cast<std::size_t>(size), limits);
  ::munmap(map, static_cast<std::size_t>(size));
  return r;
}
}
}
