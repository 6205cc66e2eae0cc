#include "ssPVSMTileReads.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace ss
{
double TileReadRegion::Texels() const
{
  if (this->levels.empty())
  {
    return 0.0;
  }
  const LevelRegion& r = this->levels[0];
  return (r[2] > r[0] && r[3] > r[1]) ? static_cast<double>(r[2] - r[0]) * (r[3] - r[1]) : 0.0;
}

namespace
{
// The GPU works in float on the same inputs; these pads (relative 1e-5,
// far above float rounding of a few operations, plus 1e-3 texel) make every
// test here accept whatever the shader's rounding might accept.
constexpr double kRel = 1e-5;
constexpr double kAbsTexels = 1e-3;

void Grow(LevelRegion& r, int x0, int y0, int x1, int y1)
{
  r[0] = std::min(r[0], x0);
  r[1] = std::min(r[1], y0);
  r[2] = std::max(r[2], x1);
  r[3] = std::max(r[3], y1);
}

struct Tile
{
  float rect[4]; // the uniform tileRect
  double tpu[2]; // texels per shadow-map unit
  int res[2];
  int topLevel; // the shader's largest quad level: tileLevels - 1
};

struct Acc
{
  std::vector<TileReadRegion> tiles;
};
}

std::vector<TileReadRegion> PVSMTileReads(
  const KernelBuffer& kb, int view, const std::vector<TileReadInput>& in, int maxQuads, int pyramidLevels)
{
  const int L = std::max(pyramidLevels, 1);
  const LevelRegion none = { 1 << 30, 1 << 30, -(1 << 30), -(1 << 30) };
  std::vector<Tile> tiles(in.size());
  for (std::size_t t = 0; t < in.size(); ++t)
  {
    Tile& T = tiles[t];
    for (int i = 0; i < 4; ++i)
    {
      T.rect[i] = static_cast<float>(in[t].rect[i]);
    }
    T.res[0] = std::max(in[t].resX, 1);
    T.res[1] = std::max(in[t].resY, 1);
    T.tpu[0] = T.res[0] / (double(T.rect[2]) - T.rect[0]);
    T.tpu[1] = T.res[1] / (double(T.rect[3]) - T.rect[1]);
    T.topLevel = std::clamp(in[t].levels - 1, 0, L - 1);
  }
  auto fresh = [&]() {
    Acc a;
    a.tiles.resize(in.size());
    for (auto& r : a.tiles)
    {
      r.screen[0] = r.screen[1] = 1 << 30;
      r.screen[2] = r.screen[3] = -1;
      r.levels.assign(static_cast<std::size_t>(L), none);
    }
    return a;
  };
  tbb::enumerable_thread_specific<Acc> local(fresh);
  const int W = kb.width, H = kb.height;
  tbb::parallel_for(tbb::blocked_range<int>(0, std::max(H, 0), 8), [&](const tbb::blocked_range<int>& rows) {
    Acc& acc = local.local();
    for (int y = rows.begin(); y != rows.end(); ++y)
    {
      for (int x = 0; x < W; ++x)
      {
        const std::size_t p = 4 * (static_cast<std::size_t>(y) * W + x);
        const float* k0 = kb.kernel0 + p;
        const float* k1 = kb.kernel1 + p;
        // the shader's first test, exactly: k0.w != 1.0 || int(k1.z) != view discards
        if (k0[3] != 1.0f)
        {
          continue;
        }
        if (std::isfinite(k1[2]) && std::abs(k1[2]) < 1e9f && static_cast<int>(k1[2]) != view)
        {
          continue;
        }
        const bool finite = std::isfinite(k0[0]) && std::isfinite(k0[1]) && std::isfinite(k0[2]) &&
          std::isfinite(k1[0]) && std::isfinite(k1[1]);
        const double hw = std::abs(double(k0[0])), hh = std::abs(double(k0[1])) + std::abs(double(k0[2]));
        const double cx = k1[0], cy = k1[1];
        for (std::size_t t = 0; t < tiles.size(); ++t)
        {
          const Tile& T = tiles[t];
          TileReadRegion& R = acc.tiles[t];
          if (finite)
          {
            // the kernel's bounding box against the tile, padded
            const double ex = kRel * (std::abs(cx) + hw + std::abs(T.rect[0]) + std::abs(T.rect[2]));
            const double ey = kRel * (std::abs(cy) + hh + std::abs(T.rect[1]) + std::abs(T.rect[3]));
            if (cx + hw < T.rect[0] - ex || cx - hw > T.rect[2] + ex || cy + hh < T.rect[1] - ey ||
              cy - hh > T.rect[3] + ey)
            {
              continue;
            }
          }
          ++R.pixels;
          R.screen[0] = std::min(R.screen[0], x);
          R.screen[1] = std::min(R.screen[1], y);
          R.screen[2] = std::max(R.screen[2], x);
          R.screen[3] = std::max(R.screen[3], y);
          if (!finite)
          {
            // NaN passes every discard test in the shader and its loop bounds are undefined
            for (int l = 0; l < L; ++l)
            {
              Grow(R.levels[l], 0, 0, (T.res[0] + (1 << l) - 1) >> l, (T.res[1] + (1 << l) - 1) >> l);
            }
            continue;
          }
          // the kernel in tile texels, as the shader builds it
          const double Tx = (cx - T.rect[0]) * T.tpu[0], Ty = (cy - T.rect[1]) * T.tpu[1];
          double ux = std::abs(double(k0[0])) * T.tpu[0];
          const double uy = std::abs(double(k0[1])) * T.tpu[1];
          double hv = std::abs(double(k0[2])) * T.tpu[1];
          double extentT;
          if (ux < 1e-3)
          {
            hv = std::max(hv + uy, 1e-3);
            extentT = std::max(2e-3, 2.0 * (hv + uy));
            ux = 1e-3;
          }
          else
          {
            hv = std::max(hv, 1e-3);
            extentT = std::max(2.0 * ux, 2.0 * (hv + uy));
          }
          // rows at most hv around a centre line within uy of T.y
          const double hy = hv + uy;
          int level = 0;
          while (extentT / std::ldexp(1.0, level) > maxQuads && level < T.topLevel)
          {
            ++level;
          }
          // one level more covers a float rounding that tips the shader's
          // choice upwards (a box aligned to 2^(l+1) holds one aligned to 2^l)
          level = std::min(level + 1, T.topLevel);
          const int s = 1 << level;
          const double px = kRel * ((std::abs(cx) + std::abs(T.rect[0]) + std::abs(T.rect[2]) + hw) * T.tpu[0] +
                                     std::abs(Tx) + ux) + kAbsTexels;
          const double py = kRel * ((std::abs(cy) + std::abs(T.rect[1]) + std::abs(T.rect[3]) + hh) * T.tpu[1] +
                                     std::abs(Ty) + hy) + kAbsTexels;
          const double fx0 = std::floor((Tx - ux - px) / s), fx1 = std::floor((Tx + ux + px) / s);
          const double fy0 = std::floor((Ty - hy - py) / s), fy1 = std::floor((Ty + hy + py) / s);
          // quads in the tile (the shader clamps its loops to them)
          const double qx0 = std::max(fx0, 0.0), qy0 = std::max(fy0, 0.0);
          const double qx1 = std::min(fx1, std::floor((T.res[0] - 1.0) / s));
          const double qy1 = std::min(fy1, std::floor((T.res[1] - 1.0) / s));
          if (!(qx1 >= qx0 && qy1 >= qy0))
          {
            continue; // reaches the tile's rectangle but none of its quads
          }
          const int x0 = static_cast<int>(qx0) * s, x1 = (static_cast<int>(qx1) + 1) * s;
          const int y0 = static_cast<int>(qy0) * s, y1 = (static_cast<int>(qy1) + 1) * s;
          for (int l = 0; l <= level; ++l)
          {
            Grow(R.levels[l], x0 >> l, y0 >> l, x1 >> l, y1 >> l);
          }
        }
      }
    }
  });
  Acc out = fresh();
  for (const Acc& a : local)
  {
    for (std::size_t t = 0; t < in.size(); ++t)
    {
      TileReadRegion& R = out.tiles[t];
      const TileReadRegion& r = a.tiles[t];
      R.pixels += r.pixels;
      R.screen[0] = std::min(R.screen[0], r.screen[0]);
      R.screen[1] = std::min(R.screen[1], r.screen[1]);
      R.screen[2] = std::max(R.screen[2], r.screen[2]);
      R.screen[3] = std::max(R.screen[3], r.screen[3]);
      for (int l = 0; l < L; ++l)
      {
        Grow(R.levels[l], r.levels[l][0], r.levels[l][1], r.levels[l][2], r.levels[l][3]);
      }
    }
  }
  for (std::size_t t = 0; t < in.size(); ++t)
  {
    TileReadRegion& R = out.tiles[t];
    if (!R.pixels)
    {
      R.screen[0] = R.screen[1] = 0;
      R.screen[2] = R.screen[3] = -1;
    }
    for (int l = 0; l < L; ++l)
    {
      // clipped to the level's size, ceil(res / 2^l) as the pyramid builds it
      LevelRegion& g = R.levels[l];
      const int w = std::max(1, (tiles[t].res[0] + (1 << l) - 1) >> l);
      const int h = std::max(1, (tiles[t].res[1] + (1 << l) - 1) >> l);
      g = { std::max(g[0], 0), std::max(g[1], 0), std::min(g[2], w), std::min(g[3], h) };
      if (!(g[2] > g[0] && g[3] > g[1]))
      {
        g = { 0, 0, 0, 0 };
      }
    }
  }
  return out.tiles;
}
}
