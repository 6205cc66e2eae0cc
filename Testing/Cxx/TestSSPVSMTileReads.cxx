// What of each PVSM tile the filter pass reads (ss::PVSMTileReads): the
// pass clears, draws and reduces a tile only in those regions and filters it
// only over those pixels, so the regions must hold every read. Over random
// kernel buffers (tiny to tile-wide kernels, sheared ones, kernels of other
// views, pixels that need no filter) and random tiles of a view, with the
// filter's loop mirrored in float from ssPVSMFilterFS.glsl: every pixel it
// does not discard lies in the tile's screen box; every texel it reads (the
// quad at its level, the children inside the tile, the centre texels) lies
// in that level's region; each region's texels have their four children
// (clamped as ssMinReduceFS.glsl reads them) in the region below; and a tile
// whose regions are empty is read by no pixel.
#include "ssPVSMTileReads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace ss;

namespace
{
struct Read
{
  int level, x, y;
};

// ssPVSMFilterFS.glsl main(): whether the pixel is filtered, and the texels
// (level, x, y) its loop reads, in float as the shader computes.
bool ShaderReads(const float* k0, const float* k1, int view, const float tr[4], int resX, int resY, int tileLevels,
  int maxQuads, std::vector<Read>& reads)
{
  reads.clear();
  if (k0[3] != 1.0f || static_cast<int>(k1[2]) != view)
  {
    return false;
  }
  const float hw = std::max(std::abs(k0[0]), 0.0f);
  const float hh = std::abs(k0[1]) + std::abs(k0[2]);
  const float cx = k1[0], cy = k1[1];
  if (cx + hw < tr[0] || cx - hw > tr[2] || cy + hh < tr[1] || cy - hh > tr[3])
  {
    return false;
  }
  const float tpx = float(resX) / (tr[2] - tr[0]), tpy = float(resY) / (tr[3] - tr[1]);
  const float Tx = (cx - tr[0]) * tpx, Ty = (cy - tr[1]) * tpy;
  float ux = k0[0] * tpx, uy = k0[1] * tpy, hv = std::abs(k0[2]) * tpy;
  if (ux < 0.0f)
  {
    ux = -ux;
    uy = -uy;
  }
  float slope = 0.0f;
  if (ux < 1e-3f)
  {
    hv += std::abs(uy);
    ux = 1e-3f;
  }
  else
  {
    slope = uy / ux;
  }
  hv = std::max(hv, 1e-3f);
  const float extentT = std::max(2.0f * ux, 2.0f * (hv + std::abs(uy)));
  int level = 0;
  while (extentT / std::exp2(float(level)) > float(maxQuads) && level < tileLevels - 1)
  {
    ++level;
  }
  const float s = std::exp2(float(level));
  const int qx0 = std::max(0, int(std::floor((Tx - ux) / s)));
  const int qx1 = std::min(int((float(resX) - 1.0f) / s), int(std::floor((Tx + ux) / s)));
  const int qyMax = int((float(resY) - 1.0f) / s);
  for (int qx = qx0; qx <= qx1; ++qx)
  {
    const float a = std::max(std::max(float(qx) * s, Tx - ux), 0.0f);
    const float b = std::min(std::min(float(qx + 1) * s, Tx + ux), float(resX));
    if (!(b > a))
    {
      continue;
    }
    const float yc = Ty + slope * (0.5f * (a + b) - Tx);
    const float y0 = std::max(yc - hv, 0.0f), y1 = std::min(yc + hv, float(resY));
    if (!(y1 > y0))
    {
      continue;
    }
    const int qy0 = std::max(0, int(std::floor(y0 / s))), qy1 = std::min(qyMax, int(std::floor(y1 / s)));
    for (int qy = qy0; qy <= qy1; ++qy)
    {
      const float oy = std::min(float(qy + 1) * s, y1) - std::max(float(qy) * s, y0);
      if (oy <= 0.0f)
      {
        continue;
      }
      // quadBlocked(): every texel it may fetch, whichever branch it takes
      if (level == 0)
      {
        if (qx < resX && qy < resY)
        {
          reads.push_back({ 0, qx, qy });
        }
        continue;
      }
      reads.push_back({ level, qx, qy });
      const float h = 0.5f * s;
      auto centre = [&](float bx, float by, float size) {
        const int tx = std::min(int(bx + 0.5f * size), resX - 1), ty = std::min(int(by + 0.5f * size), resY - 1);
        reads.push_back({ 0, tx, ty });
      };
      centre(float(qx) * s, float(qy) * s, s);
      const int bw = (resX + (1 << (level - 1)) - 1) >> (level - 1);
      const int bh = (resY + (1 << (level - 1)) - 1) >> (level - 1);
      for (int c = 0; c < 4; ++c)
      {
        const int chx = 2 * qx + (c & 1), chy = 2 * qy + (c >> 1);
        if (chx >= bw || chy >= bh)
        {
          continue; // beyond the tile: not read
        }
        reads.push_back({ level - 1, chx, chy });
        centre(float(chx) * h, float(chy) * h, h);
      }
    }
  }
  return true;
}

bool Inside(const LevelRegion& r, int x, int y)
{
  return x >= r[0] && x < r[2] && y >= r[1] && y < r[3];
}

int LevelsOf(int resX, int resY, int arrayLevels)
{
  int levels = 1;
  while ((std::max(resX, resY) >> levels) > 0 && levels < arrayLevels)
  {
    ++levels;
  }
  return levels;
}
}

TEST(PVSMTileReads, RegionsHoldEveryRead)
{
  std::mt19937 rng(2211);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int arrayLevels = 13; // a 4096 tile texture
  double regionTexels = 0.0, tileTexels = 0.0;
  std::size_t skipped = 0, totalTiles = 0, readsChecked = 0;
  for (int scene = 0; scene < 60; ++scene)
  {
    const int W = 24 + static_cast<int>(U(rng) * 40), H = 16 + static_cast<int>(U(rng) * 30);
    const int views = 1 + static_cast<int>(U(rng) * 2);
    const int view = static_cast<int>(U(rng) * views);
    const double ex0 = -0.6 + 0.4 * U(rng), ey0 = -0.6 + 0.4 * U(rng);
    const double span = 0.05 + 1.5 * U(rng);
    // a regular split of the view into tiles of random resolutions
    const int nx = 1 + static_cast<int>(U(rng) * 5), ny = 1 + static_cast<int>(U(rng) * 5);
    std::vector<TileReadInput> tiles;
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        TileReadInput t;
        t.rect[0] = ex0 + span * i / nx;
        t.rect[1] = ey0 + span * j / ny;
        t.rect[2] = ex0 + span * (i + 1) / nx;
        t.rect[3] = ey0 + span * (j + 1) / ny;
        t.resX = 1 + static_cast<int>(std::pow(U(rng), 2.0) * 4095);
        t.resY = 1 + static_cast<int>(std::pow(U(rng), 2.0) * 4095);
        t.levels = LevelsOf(t.resX, t.resY, arrayLevels);
        tiles.push_back(t);
      }
    }
    // kernels: centres in and around a part of the view (the receivers a
    // close-up sees), half sizes from far below a texel to wider than the
    // view, sheared
    const double wx = 0.1 + 0.9 * U(rng), wy = 0.1 + 0.9 * U(rng);
    const double cx0 = ex0 - 0.1 * span + (1.2 - wx) * span * U(rng), cy0 = ey0 - 0.1 * span + (1.2 - wy) * span * U(rng);
    std::vector<float> k0(4 * W * H), k1(4 * W * H);
    for (int p = 0; p < W * H; ++p)
    {
      const double size = span * std::pow(10.0, -6.0 + 5.5 * U(rng));
      const double r = U(rng);
      k0[4 * p] = static_cast<float>((U(rng) < 0.1 ? 0.0 : size) * (U(rng) < 0.5 ? -1.0 : 1.0));
      k0[4 * p + 1] = static_cast<float>(size * (2.0 * U(rng) - 1.0) * (U(rng) < 0.3 ? 3.0 : 0.5));
      k0[4 * p + 2] = static_cast<float>(size * (U(rng) < 0.1 ? 0.0 : U(rng)) * (U(rng) < 0.5 ? -1.0 : 1.0));
      k0[4 * p + 3] = r < 0.1 ? -1.0f : (r < 0.2 ? 0.0f : 1.0f);
      k1[4 * p] = static_cast<float>(cx0 + wx * span * U(rng));
      k1[4 * p + 1] = static_cast<float>(cy0 + wy * span * U(rng));
      k1[4 * p + 2] = static_cast<float>(U(rng) < 0.2 ? (view + 1) % std::max(views, 2) : view);
      k1[4 * p + 3] = 1.0f;
    }
    const int maxQuads = 2 + static_cast<int>(U(rng) * 40);
    const KernelBuffer kb{ k0.data(), k1.data(), W, H };
    const std::vector<TileReadRegion> regions = PVSMTileReads(kb, view, tiles, maxQuads, arrayLevels);
    ASSERT_EQ(regions.size(), tiles.size());
    std::vector<Read> reads;
    for (std::size_t t = 0; t < tiles.size(); ++t)
    {
      const TileReadInput& T = tiles[t];
      const TileReadRegion& R = regions[t];
      ASSERT_EQ(R.levels.size(), static_cast<std::size_t>(arrayLevels));
      const float tr[4] = { float(T.rect[0]), float(T.rect[1]), float(T.rect[2]), float(T.rect[3]) };
      std::size_t filtered = 0;
      bool anyRead = false;
      for (int y = 0; y < H; ++y)
      {
        for (int x = 0; x < W; ++x)
        {
          const int p = y * W + x;
          if (!ShaderReads(&k0[4 * p], &k1[4 * p], view, tr, T.resX, T.resY, T.levels, maxQuads, reads))
          {
            continue;
          }
          ++filtered;
          ASSERT_TRUE(x >= R.screen[0] && x <= R.screen[2] && y >= R.screen[1] && y <= R.screen[3])
            << "scene " << scene << " tile " << t << ": filtered pixel (" << x << ", " << y << ") outside the box";
          for (const Read& rd : reads)
          {
            anyRead = true;
            ++readsChecked;
            ASSERT_TRUE(Inside(R.levels[rd.level], rd.x, rd.y))
              << "scene " << scene << " tile " << t << " (" << T.resX << " x " << T.resY << "), pixel (" << x
              << ", " << y << "): level " << rd.level << " texel (" << rd.x << ", " << rd.y << ") outside ["
              << R.levels[rd.level][0] << ", " << R.levels[rd.level][2] << ") x [" << R.levels[rd.level][1]
              << ", " << R.levels[rd.level][3] << ")";
          }
        }
      }
      EXPECT_GE(R.pixels, filtered) << "scene " << scene << " tile " << t;
      if (!(R.Texels() > 0.0))
      {
        EXPECT_FALSE(anyRead) << "scene " << scene << " tile " << t << ": skipped but read";
        ++skipped;
      }
      // nesting: a region's texels find their children (clamped to the
      // level below, as the reduction reads them) in the region below
      for (int l = 1; l < arrayLevels; ++l)
      {
        const LevelRegion& g = R.levels[l];
        if (!(g[2] > g[0] && g[3] > g[1]))
        {
          continue;
        }
        const int bw = std::max(1, (T.resX + (1 << (l - 1)) - 1) >> (l - 1));
        const int bh = std::max(1, (T.resY + (1 << (l - 1)) - 1) >> (l - 1));
        for (const int cx : { 2 * g[0], std::min(2 * g[2] - 1, bw - 1) })
        {
          for (const int cy : { 2 * g[1], std::min(2 * g[3] - 1, bh - 1) })
          {
            ASSERT_TRUE(Inside(R.levels[l - 1], cx, cy)) << "scene " << scene << " tile " << t << " level " << l;
          }
        }
      }
      regionTexels += R.Texels();
      tileTexels += static_cast<double>(T.resX) * T.resY;
      ++totalTiles;
    }
  }
  std::cout << readsChecked << " reads checked; regions hold " << regionTexels / tileTexels
            << " of the tiles' texels; " << skipped << " of " << totalTiles << " tiles skipped\n";
  EXPECT_GT(readsChecked, 100000u);
  // the regions must also cut: else the test shows nothing about the pass
  EXPECT_LT(regionTexels, 0.9 * tileTexels);
  EXPECT_GT(skipped, 0u);
}

// A non-finite kernel runs the shader's loop with undefined bounds: the
// whole tile is read, at every level.
TEST(PVSMTileReads, NonFiniteKernelReadsTheWholeTile)
{
  std::vector<float> k0 = { std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, 1.0f };
  std::vector<float> k1 = { 0.1f, 0.1f, 0.0f, 1.0f };
  TileReadInput t;
  t.rect[0] = 0.5;
  t.rect[1] = 0.5;
  t.rect[2] = 0.6;
  t.rect[3] = 0.6;
  t.resX = 300;
  t.resY = 17;
  t.levels = LevelsOf(t.resX, t.resY, 13);
  const auto r = PVSMTileReads(KernelBuffer{ k0.data(), k1.data(), 1, 1 }, 0, { t }, 24, 13);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].pixels, 1u);
  EXPECT_EQ(r[0].Texels(), 300.0 * 17.0);
  EXPECT_EQ(r[0].levels[4][2], (300 + 15) / 16);
  EXPECT_EQ(r[0].levels[4][3], 2);
}
