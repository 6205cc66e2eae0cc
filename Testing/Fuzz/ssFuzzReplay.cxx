// Replays a corpus through a libFuzzer target without libFuzzer: the GCC
// build of every target runs its committed corpus as a ctest test (the same
// LLVMFuzzerTestOneInput the clang build fuzzes). Arguments: files or
// directories (every file inside, in name order).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

int main(int argc, char** argv)
{
  if (LLVMFuzzerInitialize)
  {
    LLVMFuzzerInitialize(&argc, &argv);
  }
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::filesystem::path p = argv[i];
    if (std::filesystem::is_directory(p))
    {
      for (const auto& e : std::filesystem::directory_iterator(p))
      {
        if (e.is_regular_file())
        {
          files.push_back(e.path());
        }
      }
    }
    else
    {
      files.push_back(p);
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
  {
    std::fprintf(stderr, "no corpus files given\n");
    return 1;
  }
  for (const auto& f : files)
  {
    std::ifstream in(f, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("replayed %zu inputs\n", files.size());
  return 0;
}
