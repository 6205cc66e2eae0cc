#include "ssImageIO.h"

#include "ssImageCheck.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

namespace ssapp
{
bool WriteFileBytes(const std::string& path, const void* data, std::size_t size, std::string& message)
{
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
  {
    message = "cannot write '" + path + "': " + std::strerror(errno);
    return false;
  }
  // Every step is checked: a full disk (or /dev/full) fails at fwrite, at
  // the flush or at the close, and the message says which reason.
  errno = 0;
  bool ok = std::fwrite(data, 1, size, f) == size;
  int err = errno;
  if (ok && std::fflush(f) != 0)
  {
    ok = false;
    err = errno;
  }
  if (std::fclose(f) != 0 && ok)
  {
    ok = false;
    err = errno;
  }
  if (!ok)
  {
    message = "cannot write '" + path + "': " + (err ? std::strerror(err) : "write failed");
    RemovePartial(path);
    return false;
  }
  return true;
}

void RemovePartial(const std::string& path)
{
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec))
  {
    std::filesystem::remove(path, ec);
  }
}

bool WriteTextFile(const std::string& path, const std::string& text, std::string& message)
{
  return WriteFileBytes(path, text.data(), text.size(), message);
}

namespace
{
// OpenImageIO encodes into memory (its PNG writer does not report a failed
// write to the file); the bytes are then written with every step checked.
template <typename T>
bool Write(const std::string& path, const T* data, int w, int h, int ch, OIIO::TypeDesc type,
  std::string& message)
{
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
  {
    message = "cannot write '" + path + "': " + OIIO::geterror();
    return false;
  }
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  if (!out->supports("ioproxy") || !out->set_ioproxy(&memory))
  {
    message = "cannot write '" + path + "': the " + std::string(out->format_name()) +
      " writer cannot encode into memory";
    return false;
  }
  OIIO::ImageSpec spec(w, h, ch, type);
  if (!out->open(path, spec))
  {
    message = "cannot write '" + path + "': " + out->geterror();
    return false;
  }
  // VTK rows are bottom-up: start at the last row with a negative stride.
  const OIIO::stride_t ys = -static_cast<OIIO::stride_t>(w) * ch * static_cast<OIIO::stride_t>(sizeof(T));
  const T* last = data + static_cast<std::size_t>(h - 1) * w * ch;
  if (!out->write_image(type, last, OIIO::AutoStride, ys) || !out->close())
  {
    message = "cannot write '" + path + "': " + out->geterror();
    return false;
  }
  if (bytes.empty())
  {
    message = "cannot write '" + path + "': the image encoder produced no data";
    return false;
  }
  return WriteFileBytes(path, bytes.data(), bytes.size(), message);
}
}

// Debian 12's OpenImageIO (2.4) reads PFM but has no PFM writer (its PNM
// plugin only writes ppm/pgm/pbm), and DESIGN.md requires .pfm output. PFM is
// a three-line header plus raw floats, rows bottom-up like VTK's; everything
// else goes through OpenImageIO, and .pfm files are read back by it.
bool WritePFM(const std::string& path, const float* data, int w, int h, int ch, std::string& message)
{
  if (ch != 1 && ch != 3)
  {
    message = "cannot write '" + path + "': PFM holds 1 or 3 channels, not " + std::to_string(ch);
    return false;
  }
  // a negative scale means little-endian floats (x86)
  std::string bytes = std::string(ch == 3 ? "PF" : "Pf") + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
  const std::size_t header = bytes.size();
  const std::size_t n = static_cast<std::size_t>(w) * h * ch;
  bytes.resize(header + n * sizeof(float));
  std::memcpy(&bytes[header], data, n * sizeof(float));
  return WriteFileBytes(path, bytes.data(), bytes.size(), message);
}

bool WriteFloatImage(const std::string& path, const float* data, int width, int height, int channels,
  std::string& message)
{
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  for (auto& ch : ext)
  {
    ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  }
  if (ext == ".pfm")
  {
    return WritePFM(path, data, width, height, channels, message);
  }
  return Write(path, data, width, height, channels, OIIO::TypeDesc::FLOAT, message);
}

bool WriteRGB8Image(const std::string& path, const unsigned char* data, int width, int height,
  int channels, std::string& message)
{
  return Write(path, data, width, height, channels, OIIO::TypeDesc::UINT8, message);
}

bool ReadFloatImage(const std::string& path, std::vector<float>& data, int& width, int& height,
  int& channels, std::string& message)
{
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  for (auto& ch : ext)
  {
    ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  }
  if (ext == ".pfm")
  {
    // OpenImageIO trusts a PFM header (scale 0, 2e9 x 2e9): checked first
    const ss::io::ImageCheck check = ss::io::CheckPFMFile(path);
    if (!check.Ok)
    {
      message = "cannot read '" + path + "': " + check.Error;
      return false;
    }
  }
  auto in = OIIO::ImageInput::open(path);
  if (!in)
  {
    message = "cannot read '" + path + "': " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  channels = spec.nchannels;
  if (width < 1 || height < 1 || channels < 1 ||
    static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) * static_cast<std::uint64_t>(channels) >
      ss::io::MaximumImageValues)
  {
    message = "cannot read '" + path + "': image of " + std::to_string(width) + " x " + std::to_string(height) +
      " x " + std::to_string(channels) + " values (limit " + std::to_string(ss::io::MaximumImageValues) + ")";
    return false;
  }
  data.resize(static_cast<std::size_t>(width) * height * channels);
  const OIIO::stride_t ys =
    -static_cast<OIIO::stride_t>(width) * channels * static_cast<OIIO::stride_t>(sizeof(float));
  float* last = data.data() + static_cast<std::size_t>(height - 1) * width * channels;
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, last, OIIO::AutoStride, ys))
  {
    message = "cannot read '" + path + "': " + in->geterror();
    return false;
  }
  in->close();
  return true;
}
}
