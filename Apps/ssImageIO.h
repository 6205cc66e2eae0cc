// Image output through OpenImageIO (format by extension: .png .pfm .exr .tif ...).
#ifndef ssImageIO_h
#define ssImageIO_h

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
/// Reads a float image (any channel count), returned bottom-up like VTK.
bool ReadFloatImage(const std::string& path, std::vector<float>& data, int& width, int& height,
  int& channels, std::string& message);
}

#endif
