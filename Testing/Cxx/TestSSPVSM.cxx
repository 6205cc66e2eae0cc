// PVSM numerics (Rendering/Core/ssPVSM.h): the §4.2 kernel convolution
// against a numeric convolution of the two Gaussians, the §5.1 perceptual
// metric, eq. 4-5, the kd-tree tiling invariants, the coverage integral along
// the semi-axis-aligned kernel against a numeric integral over the true
// parallelogram, and the V·A / A tile merge.
#include "ssPVSM.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace ss;

namespace
{
// Gaussian covariance of a parallelogram's ellipse, V = M M^T (§4.2).
glm::dmat2 Variance(const glm::dvec2& u, const glm::dvec2& v)
{
  const glm::dmat2 M(u, v); // columns
  return M * glm::transpose(M);
}
}

TEST(PVSM, ConvolutionIsTheCholeskyFactorOfTheSummedVariances)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-3.0, 3.0);
  for (int it = 0; it < 1000; ++it)
  {
    const glm::dvec2 u0(U(rng), U(rng)), v0(U(rng), U(rng)), u1(U(rng), U(rng)), v1(U(rng), U(rng));
    const KernelAxes h = ConvolveKernels(u0, v0, u1, v1);
    EXPECT_EQ(h.v.x, 0.0); // semi axis aligned: v_h vertical
    EXPECT_GE(h.u.x, 0.0);
    EXPECT_GE(h.v.y, 0.0);
    const glm::dmat2 want = Variance(u0, v0) + Variance(u1, v1);
    const glm::dmat2 got = Variance(h.u, h.v);
    for (int c = 0; c < 2; ++c)
    {
      for (int r = 0; r < 2; ++r)
      {
        EXPECT_NEAR(got[c][r], want[c][r], 1e-9 * (1.0 + std::abs(want[c][r])));
      }
    }
  }
}

TEST(PVSM, ConvolutionMatchesANumericGaussianConvolution)
{
  // The density of X0 + X1 is the convolution of the densities of X0 and X1.
  // G_V(x) = exp(-x^T V^-1 x) is a normal density of covariance V / 2, so
  // X_i = M_i z / sqrt(2) with z standard normal; the sample covariance of the
  // sum must be (L L^T) / 2 for the returned L = [u_h v_h].
  const glm::dvec2 u0(2.0, 0.5), v0(-0.3, 1.0); // a warped pixel footprint
  const glm::dvec2 u1(0.7, 0.0), v1(0.0, 0.4);  // an axis-aligned light filter
  const KernelAxes h = ConvolveKernels(u0, v0, u1, v1);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N(0.0, 1.0);
  const int n = 400000;
  glm::dmat2 cov(0.0);
  const double r = 1.0 / std::sqrt(2.0);
  for (int i = 0; i < n; ++i)
  {
    const glm::dvec2 x0 = (u0 * N(rng) + v0 * N(rng)) * r;
    const glm::dvec2 x1 = (u1 * N(rng) + v1 * N(rng)) * r;
    const glm::dvec2 x = x0 + x1;
    cov += glm::outerProduct(x, x);
  }
  cov /= static_cast<double>(n);
  const glm::dmat2 want = 0.5 * Variance(h.u, h.v);
  const double scale = std::abs(want[0][0]) + std::abs(want[1][1]);
  for (int c = 0; c < 2; ++c)
  {
    for (int rr = 0; rr < 2; ++rr)
    {
      EXPECT_NEAR(cov[c][rr], want[c][rr], 0.01 * scale) << c << "," << rr;
    }
  }
}

TEST(PVSM, ConvolutionOfDegenerateKernelsIsFinite)
{
  // rank-one sums: m11 - l10^2 is 0 up to rounding (the appendix's sqrt of a
  // possibly negative value) and an all-vertical input has m00 = 0
  const KernelAxes a = ConvolveKernels({ 1.0, 1.0 }, { 0, 0 }, { 3.0, 3.0 }, { 0, 0 });
  EXPECT_TRUE(std::isfinite(a.v.y));
  EXPECT_NEAR(a.v.y, 0.0, 1e-7);
  EXPECT_NEAR(a.u.x, std::sqrt(10.0), 1e-12);
  const KernelAxes b = ConvolveKernels({ 0, 1.0 }, { 0, 0 }, { 0, 2.0 }, { 0, 0 });
  EXPECT_EQ(b.u.x, 0.0);
  EXPECT_EQ(b.u.y, 0.0);
  EXPECT_NEAR(b.v.y, std::sqrt(5.0), 1e-12);
  const KernelAxes z = ConvolveKernels({ 0, 0 }, { 0, 0 }, { 0, 0 }, { 0, 0 });
  EXPECT_EQ(z.Area(), 0.0);
}

TEST(PVSM, PerceptualMetricFollowsThePapersFits)
{
  // P_d, P_s of §5.1 at x = log2 n
  EXPECT_NEAR(PerceptualRho(1.0, PerceptualMetric::Dynamic), 0.667, 1e-12);
  EXPECT_NEAR(PerceptualRho(2.0, PerceptualMetric::Dynamic), 0.667 + 0.7794 + 0.3967 - 0.02716, 1e-12);
  EXPECT_NEAR(PerceptualRho(16.0, PerceptualMetric::Dynamic), 0.667 + 0.7794 * 4 + 0.3967 * 16 - 0.02716 * 64, 1e-12);
  EXPECT_NEAR(PerceptualRho(4.0, PerceptualMetric::Static), 0.5477 + 1.406 * 2 - 0.04687 * 4 - 0.003944 * 8, 1e-12);
  EXPECT_NEAR(PerceptualRho(64.0, PerceptualMetric::Static),
    0.5477 + 1.406 * 6 - 0.04687 * 36 - 0.003944 * 216, 1e-12);
  // the static fit asks fewer texels than the dynamic one beyond 2 pixels
  for (double n = 4.0; n <= 256.0; n *= 2.0)
  {
    EXPECT_LT(PerceptualRho(n, PerceptualMetric::Static), PerceptualRho(n, PerceptualMetric::Dynamic)) << n;
  }
  // never decreasing in n (the fits are clamped before they turn down)
  for (auto m : { PerceptualMetric::Dynamic, PerceptualMetric::Static })
  {
    double prev = 0.0;
    for (double n = 0.01; n < 1e7; n *= 1.1)
    {
      const double r = PerceptualRho(n, m);
      EXPECT_GE(r, prev - 1e-12) << n;
      EXPECT_GT(r, 0.0);
      prev = r;
    }
  }
  EXPECT_EQ(PerceptualRho(std::nan(""), PerceptualMetric::Dynamic), PerceptualRho(1.0, PerceptualMetric::Dynamic));
  EXPECT_EQ(PerceptualRho(-5.0, PerceptualMetric::Static), PerceptualRho(1.0, PerceptualMetric::Static));
}

TEST(PVSM, MetricChoice)
{
  EXPECT_EQ(ChooseMetric(0, true), PerceptualMetric::Dynamic);
  EXPECT_EQ(ChooseMetric(0, false), PerceptualMetric::Static);
  EXPECT_EQ(ChooseMetric(1, false), PerceptualMetric::Dynamic);
  EXPECT_EQ(ChooseMetric(2, true), PerceptualMetric::Static);
}

TEST(PVSM, PredictionOfAnAxisAlignedKernel)
{
  // pixels of p shadow-map units: footprint half axes p/2; a kernel of half
  // width K spans 2K/p pixels and needs rho(2K/p) texels over 2K
  const double p = 0.01, K = 0.08;
  KernelAxes h;
  h.u = { K, 0.0 };
  h.v = { 0.0, 0.5 * K };
  const TexelPrediction t = PredictTexelSize(h, { 0.5 * p, 0.0 }, { 0.0, 0.5 * p }, PerceptualMetric::Dynamic, 1.0);
  EXPECT_NEAR(t.n0, 2.0 * K / p, 1e-9);
  EXPECT_NEAR(t.n1, K / p, 1e-9);
  EXPECT_NEAR(t.texel0, 2.0 * K / PerceptualRho(16.0, PerceptualMetric::Dynamic), 1e-12);
  EXPECT_NEAR(t.texel1, K / PerceptualRho(8.0, PerceptualMetric::Dynamic), 1e-12);
  // the quality knob asks proportionally smaller texels
  const TexelPrediction q2 = PredictTexelSize(h, { 0.5 * p, 0.0 }, { 0.0, 0.5 * p }, PerceptualMetric::Dynamic, 2.0);
  EXPECT_NEAR(q2.texel0, 0.5 * t.texel0, 1e-12);
  // a rotated footprint: n is measured along the footprint's own axes
  const double c = std::cos(0.6), s = std::sin(0.6);
  const glm::dvec2 uPhi(0.5 * p * c, 0.5 * p * s), vPhi(-0.5 * p * s, 0.5 * p * c);
  const TexelPrediction r = PredictTexelSize(h, uPhi, vPhi, PerceptualMetric::Dynamic, 1.0);
  EXPECT_NEAR(r.n0, 2.0 * K / p, 1e-9); // rotation keeps lengths
  // a singular footprint (grazing view) does not divide by zero
  const TexelPrediction g = PredictTexelSize(h, { p, 0.0 }, { 2.0 * p, 0.0 }, PerceptualMetric::Dynamic, 1.0);
  EXPECT_TRUE(std::isfinite(g.texel0) && std::isfinite(g.texel1));
}

// The pyramid as the GPU hands it over (all levels, 3e38 for empty) reads
// the same as the one Core builds from level 0; malformed levels give an
// empty pyramid, never a read out of bounds.
TEST(PVSM, PyramidFromLevelsEqualsBuiltPyramid)
{
  const int G = 16;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> U(0.01f, 1.0f);
  std::vector<float> t(2 * G * G);
  for (float& v : t)
  {
    v = (rng() % 4 == 0) ? 3.0e38f : U(rng);
  }
  const TileGridPyramid built(t.data(), G);
  std::vector<std::vector<float>> levels;
  for (int l = 0; l < built.Levels(); ++l)
  {
    const int n = G >> l, b = 1 << l;
    std::vector<float> lv(2 * n * n);
    for (int y = 0; y < n; ++y)
    {
      for (int x = 0; x < n; ++x)
      {
        for (int d = 0; d < 2; ++d)
        {
          const double m = built.MinTexel(d, x * b, y * b, (x + 1) * b, (y + 1) * b);
          lv[2 * (y * n + x) + d] = std::isfinite(m) ? static_cast<float>(m) : 3.0e38f;
        }
      }
    }
    levels.push_back(lv);
  }
  const TileGridPyramid given(levels, G);
  ASSERT_EQ(given.Size(), G);
  ASSERT_EQ(given.Levels(), built.Levels());
  for (int it = 0; it < 500; ++it)
  {
    const int x0 = rng() % G, y0 = rng() % G;
    const int x1 = x0 + 1 + rng() % (G - x0), y1 = y0 + 1 + rng() % (G - y0);
    for (int d = 0; d < 2; ++d)
    {
      EXPECT_EQ(given.MinTexel(d, x0, y0, x1, y1), built.MinTexel(d, x0, y0, x1, y1));
    }
  }
  auto shortLevel = levels;
  shortLevel[2].pop_back();
  EXPECT_EQ(TileGridPyramid(shortLevel, G).Size(), 0);
  auto missing = levels;
  missing.pop_back();
  EXPECT_EQ(TileGridPyramid(missing, G).Size(), 0);
  EXPECT_EQ(TileGridPyramid(levels, 12).Size(), 0);
}

TEST(PVSM, PyramidMinimumEqualsBruteForce)
{
  const int G = 32;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> U(0.01f, 1.0f);
  std::vector<float> t(2 * G * G);
  for (std::size_t i = 0; i < t.size(); ++i)
  {
    t[i] = (rng() % 5 == 0) ? std::numeric_limits<float>::infinity() : U(rng);
  }
  TileGridPyramid P(t.data(), G);
  ASSERT_EQ(P.Levels(), 6);
  for (int it = 0; it < 2000; ++it)
  {
    int x0 = rng() % G, x1 = rng() % G, y0 = rng() % G, y1 = rng() % G;
    if (x0 > x1)
    {
      std::swap(x0, x1);
    }
    if (y0 > y1)
    {
      std::swap(y0, y1);
    }
    ++x1;
    ++y1;
    for (int d = 0; d < 2; ++d)
    {
      double want = std::numeric_limits<double>::infinity();
      for (int y = y0; y < y1; ++y)
      {
        for (int x = x0; x < x1; ++x)
        {
          want = std::min(want, static_cast<double>(t[2 * (y * G + x) + d]));
        }
      }
      EXPECT_EQ(P.MinTexel(d, x0, y0, x1, y1), want);
    }
  }
}

TEST(PVSM, KdTreeTilesCoverEveryCellOnceAtSufficientResolution)
{
  const int G = 64;
  const double extent[4] = { -1.0, -0.5, 1.0, 1.5 };
  const double cw = 2.0 / G, ch = 2.0 / G;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> logT(-14.0, -3.0);
  for (int scene = 0; scene < 40; ++scene)
  {
    std::vector<float> t(2 * G * G, std::numeric_limits<float>::infinity());
    // blobs of pixels: a few regions with a smooth texel size, the rest empty
    const int blobs = 1 + scene % 4;
    for (int b = 0; b < blobs; ++b)
    {
      const int cx = rng() % G, cy = rng() % G, r = 2 + rng() % 20;
      const double base = std::exp2(logT(rng));
      for (int y = std::max(0, cy - r); y < std::min(G, cy + r); ++y)
      {
        for (int x = std::max(0, cx - r); x < std::min(G, cx + r); ++x)
        {
          const double f = 1.0 + 0.3 * std::sin(0.7 * x + 0.3 * y);
          t[2 * (y * G + x)] = std::min(t[2 * (y * G + x)], static_cast<float>(base * f));
          t[2 * (y * G + x) + 1] = std::min(t[2 * (y * G + x) + 1], static_cast<float>(base * f * 1.7));
        }
      }
    }
    TileGridPyramid P(t.data(), G);
    for (int maxTex : { 4096, 512, 64 })
    {
      const auto tiles = BuildShadowTiles(P, extent, maxTex);
      std::vector<int> cover(G * G, 0);
      for (const ShadowTile& tile : tiles)
      {
        EXPECT_LE(tile.resX, maxTex);
        EXPECT_LE(tile.resY, maxTex);
        EXPECT_GE(tile.resX, 1);
        EXPECT_GE(tile.resY, 1);
        EXPECT_NEAR(tile.rect[2] - tile.rect[0], (tile.x1 - tile.x0) * cw, 1e-12);
        EXPECT_NEAR(tile.rect[3] - tile.rect[1], (tile.y1 - tile.y0) * ch, 1e-12);
        bool needsMore = false;
        for (int y = tile.y0; y < tile.y1; ++y)
        {
          for (int x = tile.x0; x < tile.x1; ++x)
          {
            ++cover[y * G + x];
            const double tx = t[2 * (y * G + x)], ty = t[2 * (y * G + x) + 1];
            if (!std::isfinite(tx))
            {
              continue;
            }
            // the tile's texel is no larger than any of its cells asks
            const double haveX = (tile.rect[2] - tile.rect[0]) / tile.resX;
            const double haveY = (tile.rect[3] - tile.rect[1]) / tile.resY;
            if (!tile.clamped)
            {
              EXPECT_LE(haveX, tx * (1.0 + 1e-12));
              EXPECT_LE(haveY, ty * (1.0 + 1e-12));
            }
            needsMore = needsMore || cw / tx > maxTex || ch / ty > maxTex;
          }
        }
        if (tile.clamped)
        {
          // capped only where one cell alone needs more than the maximum
          EXPECT_TRUE(needsMore);
          EXPECT_TRUE(tile.x1 - tile.x0 == 1 || tile.y1 - tile.y0 == 1);
        }
      }
      for (int c = 0; c < G * G; ++c)
      {
        const bool empty = !std::isfinite(t[2 * c]);
        EXPECT_LE(cover[c], 1) << "cell " << c << " in two tiles";
        if (!empty)
        {
          EXPECT_EQ(cover[c], 1) << "cell " << c << " without a tile";
        }
      }
    }
  }
  // nothing to shadow: no tile
  std::vector<float> none(2 * G * G, std::numeric_limits<float>::infinity());
  TileGridPyramid E(none.data(), G);
  EXPECT_TRUE(BuildShadowTiles(E, extent, 4096).empty());
}

// A pixel whose kernel has no extent along an axis (a hard contact seen with a
// degenerate footprint) predicts a texel size of 0. Its cell needs the finest
// tile, not none: before, 0 read as "no pixel", the whole cell lost its tile
// and every kernel in it was resolved as lit (light leaking on the assembly).
TEST(PVSM, ZeroTexelCellGetsTheFinestTileNotNone)
{
  const int G = 16;
  const double extent[4] = { 0.0, 0.0, 1.0, 1.0 };
  std::vector<float> t(2 * G * G, 3.0e38f); // the GPU's clear value: no pixel
  for (int y = 4; y < 12; ++y)
  {
    for (int x = 4; x < 12; ++x)
    {
      t[2 * (y * G + x)] = t[2 * (y * G + x) + 1] = 1e-3f;
    }
  }
  const int zeroBoth = 6 * G + 6, zeroX = 9 * G + 10;
  t[2 * zeroBoth] = t[2 * zeroBoth + 1] = 0.0f;
  t[2 * zeroX] = 0.0f; // only its x axis is degenerate
  const int zeroAlone = 14 * G + 1; // no other pixel near it
  t[2 * zeroAlone] = t[2 * zeroAlone + 1] = 0.0f;
  const TileGridPyramid P(t.data(), G);
  const int maxTex = 2048;
  const auto tiles = BuildShadowTiles(P, extent, maxTex);
  std::vector<const ShadowTile*> owner(G * G, nullptr);
  for (const ShadowTile& tile : tiles)
  {
    for (int y = tile.y0; y < tile.y1; ++y)
    {
      for (int x = tile.x0; x < tile.x1; ++x)
      {
        EXPECT_EQ(owner[y * G + x], nullptr) << "cell in two tiles";
        owner[y * G + x] = &tile;
      }
    }
  }
  for (int y = 4; y < 12; ++y)
  {
    for (int x = 4; x < 12; ++x)
    {
      ASSERT_NE(owner[y * G + x], nullptr) << "cell " << x << "," << y << " without a tile";
    }
  }
  ASSERT_NE(owner[zeroAlone], nullptr) << "the lone zero-size cell has no tile";
  EXPECT_EQ(owner[zeroAlone]->resX, maxTex);
  const ShadowTile& both = *owner[zeroBoth];
  EXPECT_TRUE(both.clamped);
  EXPECT_EQ(both.x1 - both.x0, 1);
  EXPECT_EQ(both.resX, maxTex);
  const ShadowTile& onlyX = *owner[zeroX];
  EXPECT_TRUE(onlyX.clamped);
  EXPECT_EQ(onlyX.resX, maxTex);
  // its y axis still gets what the cells ask (1e-3 per texel), not the cap
  EXPECT_LE((onlyX.rect[3] - onlyX.rect[1]) / onlyX.resY, 1e-3 * (1.0 + 1e-9));
  // the same through the constructor that takes the GPU's pyramid levels
  std::vector<std::vector<float>> levels;
  for (int s = G; s >= 1; s /= 2)
  {
    std::vector<float> lv(2 * s * s, 3.0e38f);
    const int f = G / s;
    for (int y = 0; y < G; ++y)
    {
      for (int x = 0; x < G; ++x)
      {
        for (int d = 0; d < 2; ++d)
        {
          float& c = lv[2 * ((y / f) * s + x / f) + d];
          c = std::min(c, t[2 * (y * G + x) + d]);
        }
      }
    }
    levels.push_back(std::move(lv));
  }
  const TileGridPyramid Q(levels, G);
  EXPECT_EQ(Q.MinTexel(0, 0, 0, G, G), 0.0);
  EXPECT_EQ(BuildShadowTiles(Q, extent, maxTex).size(), tiles.size());
}

namespace
{
// The exact integral of the lit indicator over the true parallelogram
// {c + a u + b v}, by an n x n midpoint rule in (a, b): uniform in area.
double NumericParallelogram(const TileDepthMap& tile, const glm::dvec2& c, const KernelAxes& h, double zr, int n)
{
  const double sx = tile.w / (tile.rect[2] - tile.rect[0]), sy = tile.h / (tile.rect[3] - tile.rect[1]);
  long lit = 0, all = 0;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const double a = -1.0 + (i + 0.5) * 2.0 / n, b = -1.0 + (j + 0.5) * 2.0 / n;
      const glm::dvec2 X = c + a * h.u + b * h.v;
      const int ti = static_cast<int>(std::floor((X.x - tile.rect[0]) * sx));
      const int tj = static_cast<int>(std::floor((X.y - tile.rect[1]) * sy));
      if (ti < 0 || tj < 0 || ti >= tile.w || tj >= tile.h)
      {
        continue; // outside the tile: not this tile's area
      }
      ++all;
      lit += (zr <= tile.depth[tj * tile.w + ti]) ? 1 : 0;
    }
  }
  return all ? static_cast<double>(lit) / all : 1.0;
}
}

TEST(PVSM, CoverageAlongTheKernelMatchesNumericIntegration)
{
  const int w = 48, h = 40;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<float> depth(w * h);
  // a blocky occluder pattern at depth 1, the rest empty; receiver at depth 2
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      depth[j * w + i] = ((i / 3 + j / 5) % 3 == 0) ? 1.0f : 1e30f;
    }
  }
  TileDepthMap tile{ depth.data(), w, h, { 0.0, 0.0, 4.8, 4.0 } }; // texel 0.1 x 0.1
  auto zr = [](double, double) { return 2.0; };
  for (int it = 0; it < 60; ++it)
  {
    const glm::dvec2 c(0.8 + 3.2 * U(rng), 0.8 + 2.4 * U(rng));
    KernelAxes k;
    const bool aligned = it % 2 == 0;
    k.u = { 0.05 + 0.6 * U(rng), aligned ? 0.0 : (U(rng) - 0.5) * 0.4 };
    k.v = { 0.0, 0.05 + 0.6 * U(rng) };
    const CoverageAccum a = FilterKernelInTile(tile, c, k, zr, 0.0, 1 << 20);
    const double want = NumericParallelogram(tile, c, k, 2.0, 1500);
    // area: the panels' boxes have the parallelogram's area where it is inside the tile
    if (c.x - k.u.x > 0.0 && c.x + k.u.x < 4.8 && c.y - std::abs(k.u.y) - k.v.y > 0.0 &&
      c.y + std::abs(k.u.y) + k.v.y < 4.0)
    {
      EXPECT_NEAR(a.area, k.Area(), 1e-9 * k.Area());
    }
    // panels one texel (0.1) wide approximated by boxes: each misplaces two
    // triangles of (slope * 0.05) * 0.05 / 2 area at most
    const double slope = std::abs(k.u.y / k.u.x);
    const double panels = 2.0 * k.u.x / 0.1 + 2.0;
    const double bound = panels * slope * 0.05 * 0.05 / std::max(a.area, 1e-12) + 0.004;
    EXPECT_NEAR(a.Visibility(), want, bound) << "kernel " << it << (aligned ? " aligned" : " slanted");
    if (aligned)
    {
      EXPECT_NEAR(a.Visibility(), want, 0.004);
    }
  }
}

TEST(PVSM, CoverageIsContinuousInTheKernelSize)
{
  // §4.1's point: V changes smoothly as the kernel grows (no banding)
  const int w = 32, h = 32;
  std::vector<float> depth(w * h, 1e30f);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 16; i < w; ++i)
    {
      depth[j * w + i] = 1.0f; // a half-plane occluder
    }
  }
  TileDepthMap tile{ depth.data(), w, h, { 0.0, 0.0, 1.0, 1.0 } };
  auto zr = [](double, double) { return 2.0; };
  double prev = -1.0;
  for (int s = 0; s <= 200; ++s)
  {
    KernelAxes k;
    k.u = { 0.01 + 0.001 * s, 0.0 };
    k.v = { 0.0, 0.05 };
    const double V = FilterKernelInTile(tile, { 0.45, 0.5 }, k, zr, 0.0, 1 << 20).Visibility();
    if (prev >= 0.0)
    {
      EXPECT_LT(std::abs(V - prev), 0.01) << s;
    }
    prev = V;
  }
}

TEST(PVSM, KernelSplitAcrossTilesMergesToTheSingleTileValue)
{
  const int w = 64, h = 32;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<float> depth(w * h);
  for (auto& d : depth)
  {
    d = U(rng) < 0.4 ? static_cast<float>(0.5 + U(rng)) : 1e30f;
  }
  const double rect[4] = { -3.2, 1.0, 3.2, 4.2 }; // texel 0.1
  TileDepthMap whole{ depth.data(), w, h, { rect[0], rect[1], rect[2], rect[3] } };
  // the same texels as two tiles split at column 40
  const int split = 40;
  std::vector<float> left(split * h), right((w - split) * h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      (i < split ? left[j * split + i] : right[j * (w - split) + i - split]) = depth[j * w + i];
    }
  }
  const double xs = rect[0] + split * 0.1;
  TileDepthMap a{ left.data(), split, h, { rect[0], rect[1], xs, rect[3] } };
  TileDepthMap b{ right.data(), w - split, h, { xs, rect[1], rect[2], rect[3] } };
  auto zr = [](double x, double y) { return 1.2 + 0.05 * x - 0.02 * y; };
  for (int maxQuads : { 1 << 20, 4 })
  {
    for (int it = 0; it < 100; ++it)
    {
      const glm::dvec2 c(xs + (U(rng) - 0.5) * 1.0, 2.0 + U(rng) * 1.2);
      KernelAxes k;
      k.u = { 0.05 + 0.5 * U(rng), (U(rng) - 0.5) * 0.3 };
      k.v = { 0.0, 0.05 + 0.3 * U(rng) };
      const CoverageAccum one = FilterKernelInTile(whole, c, k, zr, 0.01, maxQuads);
      CoverageAccum two = FilterKernelInTile(a, c, k, zr, 0.01, maxQuads);
      two.Merge(FilterKernelInTile(b, c, k, zr, 0.01, maxQuads));
      EXPECT_NEAR(two.area, one.area, 1e-9);
      EXPECT_NEAR(two.Visibility(), one.Visibility(), 1e-4) << it;
      // the same with the per-texel reach (what the shader does): both
      // estimates are sums over texels, so they merge the same way
      ReachParams rp;
      rp.lightHalfSize = { 0.3, 0.2 };
      rp.zAvg = 0.9;
      const CoverageAccum oneR = FilterKernelInTile(whole, c, k, zr, 0.01, maxQuads, &rp);
      CoverageAccum twoR = FilterKernelInTile(a, c, k, zr, 0.01, maxQuads, &rp);
      twoR.Merge(FilterKernelInTile(b, c, k, zr, 0.01, maxQuads, &rp));
      EXPECT_NEAR(twoR.backProjected, oneR.backProjected, 1e-9) << it;
      EXPECT_NEAR(twoR.Visibility(), oneR.Visibility(), 1e-4) << it;
    }
  }
}

// A quad of 2^l texels at a tile's last row or column reaches past the tile,
// and its overlap with the kernel lies in the tile. When its (min, max)
// cannot decide it, the children inside the tile share that overlap (those
// beyond are empty); a quarter each, as before, under-counted the blocked
// part of edge quads (V 0.389 here). A 6 x 6 tile with rows 0, 1, 4 and 5
// blocked under a kernel that covers it, in quads of 4 texels: V is the
// unblocked third exactly.
TEST(PVSM, EdgeQuadsShareTheirOverlapAmongChildrenInTheTile)
{
  const int w = 6, h = 6;
  std::vector<float> depth(w * h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      depth[j * w + i] = (j % 4 < 2) ? 0.5f : 1e30f;
    }
  }
  const TileDepthMap tile{ depth.data(), w, h, { 0.0, 0.0, 6.0, 6.0 } }; // one unit a texel
  KernelAxes k;
  k.u = { 4.0, 0.0 };
  k.v = { 0.0, 4.0 }; // the box [-1, 7]^2, 8 texels wide: quads of 4 with maxQuads 2
  const auto zr = [](double, double) { return 1.0; };
  const CoverageAccum a = FilterKernelInTile(tile, { 3.0, 3.0 }, k, zr, 0.0, 2);
  EXPECT_DOUBLE_EQ(a.area, 36.0);
  EXPECT_NEAR(a.Visibility(), 12.0 / 36.0, 1e-12);
}

namespace
{
// A kernel without pixel footprint: the light filter at z_avg (§4 eq. 1).
KernelAxes LightOnlyKernel(const ReachParams& p, double zr)
{
  const glm::dvec2 k = LightFilterHalfAxes(p, zr, p.zAvg);
  KernelAxes h;
  h.u = { k.x, 0.0 };
  h.v = { 0.0, k.y };
  return h;
}
}

TEST(PVSM, ReachPutsABlockerNearerThanZavgWhereItsPenumbraIs)
{
  // A half-plane blocker at z_b = 1.8 over a receiver at z_r = 2, while the
  // kernel was sized by z_avg = 1.2 (say another blocker nearer the light was
  // in the search region). The light (half size 1 world unit) seen through
  // z_b covers [c - r, c + r] with r = (z_r - z_b) / (z_r z_b): a blocker
  // edge at c + d hides (r - d) / 2r of it, exactly what back-projection
  // gives. Plain PCSS spreads the same edge over the wider kernel.
  const int w = 400, h = 400;
  const double texel = 0.0025; // map units; the kernel's half width is 0.333
  ReachParams rp;
  rp.lightHalfSize = { 1.0, 1.0 };
  rp.zAvg = 1.2;
  const double zr = 2.0, zb = 1.8;
  const double r = (zr - zb) / (zr * zb); // 0.0556
  const KernelAxes k = LightOnlyKernel(rp, zr);
  const glm::dvec2 c(0.5, 0.5);
  auto plane = [&](double, double) { return zr; };
  std::vector<float> depth(w * h);
  double worstReach = 0.0, worstPlain = 0.0;
  for (double d : { -0.04, -0.02, 0.0, 0.01, 0.03, 0.05 })
  {
    for (int j = 0; j < h; ++j)
    {
      for (int i = 0; i < w; ++i)
      {
        depth[j * w + i] = (i + 0.5) * texel >= c.x + d ? static_cast<float>(zb) : 1e30f;
      }
    }
    TileDepthMap tile{ depth.data(), w, h, { 0.0, 0.0, w * texel, h * texel } };
    const double want = std::clamp((r + d) / (2.0 * r), 0.0, 1.0);
    const double withReach = FilterKernelInTile(tile, c, k, plane, 0.0, 1 << 20, &rp).Visibility();
    const double plain = FilterKernelInTile(tile, c, k, plane, 0.0, 1 << 20).Visibility();
    worstReach = std::max(worstReach, std::abs(withReach - want));
    worstPlain = std::max(worstPlain, std::abs(plain - want));
    EXPECT_NEAR(withReach, want, 0.03) << "edge at c + " << d;
  }
  // the test would fail with plain PCSS: its edge is 6x too wide
  EXPECT_GT(worstPlain, 0.2);
  EXPECT_LT(worstReach, 0.03);
}

TEST(PVSM, ReachKeepsAConcaveReceiversOwnSurfaceFromShadowingIt)
{
  // A lit concave receiver (pvsm.md, the 16x detail view): its own surface
  // rises above its tangent plane quadratically, z(X) = z_r - a |X - c|^2,
  // up to 0.05 at the kernel's edge, while the kernel was sized by a blocker
  // found nearer the light (z_avg = 1.5, beyond the kernel). Nothing hides
  // the light: a texel rising by dz reaches only dz / (z_r z_b) around
  // itself, less than its distance from c. Plain PCSS counts every texel
  // above the plane.
  const int w = 256, h = 256;
  ReachParams rp;
  rp.lightHalfSize = { 0.5, 0.5 };
  rp.zAvg = 1.5;
  const double zr = 2.0;
  const KernelAxes k = LightOnlyKernel(rp, zr); // half width 0.0833
  const double texel = 0.002;
  const glm::dvec2 c(0.256, 0.256);
  const double a = 0.05 / (k.u.x * k.u.x);
  std::vector<float> depth(w * h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      const glm::dvec2 X((i + 0.5) * texel, (j + 0.5) * texel);
      const glm::dvec2 e = X - c;
      depth[j * w + i] = static_cast<float>(zr - a * glm::dot(e, e));
    }
  }
  TileDepthMap tile{ depth.data(), w, h, { 0.0, 0.0, w * texel, h * texel } };
  auto plane = [&](double, double) { return zr; };
  for (int maxQuads : { 1 << 20, 8 })
  {
    const double withReach = FilterKernelInTile(tile, c, k, plane, 1e-4, maxQuads, &rp).Visibility();
    const double plain = FilterKernelInTile(tile, c, k, plane, 1e-4, maxQuads).Visibility();
    EXPECT_GT(withReach, 0.99) << maxQuads;
    EXPECT_LT(plain, 0.5) << maxQuads; // the streaks: the test fails without the reach
  }
}

TEST(PVSM, ReachIsTheKernelForBlockersAtZavg)
{
  // Blockers at z_avg: the reach is the kernel (same footprint, same light
  // filter), so a blocker at z_avg is filtered as plain §4.1 does.
  ReachParams rp;
  rp.lightHalfSize = { 0.4, 0.25 };
  rp.zAvg = 1.1;
  const double zr = 1.7;
  KernelAxes fp; // a slanted pixel footprint
  fp.u = { 0.01, 0.004 };
  fp.v = { -0.002, 0.008 };
  KernelAxes light = LightOnlyKernel(rp, zr);
  const KernelAxes h = ConvolveKernels(fp.u, fp.v, light.u, light.v);
  const KernelAxes r = ReachAt(h, rp, zr, rp.zAvg);
  EXPECT_NEAR(r.u.x, h.u.x, 1e-12);
  EXPECT_NEAR(r.u.y, h.u.y, 1e-12);
  EXPECT_NEAR(r.v.y, h.v.y, 1e-12);
  // nearer the light the reach grows, nearer the receiver it shrinks to the footprint
  EXPECT_GT(ReachAt(h, rp, zr, 0.9).Area(), h.Area());
  const KernelAxes atReceiver = ReachAt(h, rp, zr, zr);
  EXPECT_NEAR(atReceiver.Area(), fp.Area(), 1e-9);
  // a blocker behind the light's plane or a NaN depth gives no NaN
  EXPECT_TRUE(std::isfinite(ReachAt(h, rp, zr, -1.0).Area()));
  std::vector<float> depth(64 * 64, static_cast<float>(rp.zAvg));
  depth[5] = std::numeric_limits<float>::quiet_NaN();
  TileDepthMap tile{ depth.data(), 64, 64, { 0.0, 0.0, 0.64, 0.64 } };
  auto plane = [&](double, double) { return zr; };
  const CoverageAccum acc = FilterKernelInTile(tile, { 0.32, 0.32 }, h, plane, 0.0, 16, &rp);
  EXPECT_TRUE(std::isfinite(acc.backProjected));
  EXPECT_NEAR(acc.Visibility(), 0.0, 1e-9); // a blocker plane over the whole kernel: umbra
}

TEST(PVSM, FilterHandlesBadInput)
{
  std::vector<float> depth(16, 1.0f);
  TileDepthMap t{ depth.data(), 4, 4, { 0, 0, 1, 1 } };
  auto zr = [](double, double) { return 2.0; };
  KernelAxes k;
  k.u = { std::nan(""), 0.0 };
  EXPECT_EQ(FilterKernelInTile(t, { 0.5, 0.5 }, k, zr, 0.0, 16).area, 0.0);
  // a point kernel is widened to a sliver, not dropped: fully shadowed here
  KernelAxes p;
  const CoverageAccum acc = FilterKernelInTile(t, { 0.5, 0.5 }, p, zr, 0.0, 16);
  EXPECT_GT(acc.area, 0.0);
  EXPECT_EQ(acc.Visibility(), 0.0);
  TileDepthMap empty{ nullptr, 0, 0, { 0, 0, 1, 1 } };
  EXPECT_EQ(FilterKernelInTile(empty, { 0.5, 0.5 }, p, zr, 0.0, 16).area, 0.0);
  EXPECT_EQ(CoverageAccum{}.Visibility(), 1.0);
}
