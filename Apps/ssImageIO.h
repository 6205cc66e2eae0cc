// Image output through OpenImageIO (format by extension: .png .pfm .exr .tif ...).
#ifndef ssImageIO_h
#define ssImageIO_h

#include <cstddef>
#include <string>
#include <vector>

namespace ssapp
{
/// Writes `channels` interleaved values per pixel, rows given bottom-up (as
/// VTK stores them); the file is written top row first. Returns false and a
/// message on failure.
bool WriteFloatImage(const std::string& path, const float* data, int width, int height, int channels,
  std::string& message);
bool WriteRGB8Image(const std::string& path, const unsigned char* data, int width, int height,
  int channels, std::string& message);
/// Writes bytes to `path`, checking the open, every write, the flush and the
/// close; the message names the path and the reason (errno). A write that
/// fails part-way leaves no file (RemovePartial).
bool WriteFileBytes(const std::string& path, const void* data, std::size_t size, std::string& message);
bool WriteTextFile(const std::string& path, const std::string& text, std::string& message);
/// After a failed write: removes what was written of `path`, if it is a
/// regular file (a link to /dev/full, say, stays). A full disk left the first
/// kilobytes of a picture or a .vtp behind.
void RemovePartial(const std::string& path);
/// Reads a float image (any channel count), returned bottom-up like VTK.
bool ReadFloatImage(const std::string& path, std::vector<float>& data, int& width, int& height,
  int& channels, std::string& message);
}

#endif
