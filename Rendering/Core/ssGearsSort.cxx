// GEARS [Wang et al. 2014, §4.2]: the (item, cell) pairs sorted by cell, as
// a stable parallel counting sort (chunk histograms, their prefix sum,
// scatter), and the per-cell ranges.
#include "ssGearsInternal.h"

#include <tbb/parallel_for.h>

namespace ss
{
namespace gears
{
void SortPairsByCell(const std::uint32_t* item, const std::uint32_t* cell, std::size_t count, std::size_t NC,
  std::vector<std::uint32_t>& hist, std::vector<std::uint32_t>& cellBegin, std::vector<std::uint32_t>& sorted)
{
  const std::size_t chunks = std::max<std::size_t>(1, std::min<std::size_t>(64, count / 65536 + 1));
  const std::size_t chunkSize = (count + chunks - 1) / chunks;
  hist.assign(chunks * NC, 0);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
    const std::size_t a = ch * chunkSize, b = std::min(count, a + chunkSize);
    std::uint32_t* h = &hist[ch * NC];
    for (std::size_t q = a; q < b; ++q)
    {
      ++h[cell[q]];
    }
  });
  cellBegin.assign(NC + 1, 0);
  std::size_t run = 0;
  for (std::size_t c = 0; c < NC; ++c)
  {
    cellBegin[c] = static_cast<std::uint32_t>(run);
    for (std::size_t ch = 0; ch < chunks; ++ch)
    {
      const std::uint32_t cnt = hist[ch * NC + c];
      hist[ch * NC + c] = static_cast<std::uint32_t>(run);
      run += cnt;
    }
  }
  cellBegin[NC] = static_cast<std::uint32_t>(run);
  sorted.resize(count);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
    const std::size_t a = ch * chunkSize, b = std::min(count, a + chunkSize);
    std::uint32_t* h = &hist[ch * NC];
    for (std::size_t q = a; q < b; ++q)
    {
      sorted[h[cell[q]]++] = item[q];
    }
  });
}
}
}
