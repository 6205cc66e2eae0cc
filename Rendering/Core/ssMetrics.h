#ifndef ssMetrics_h
#define ssMetrics_h

#include <cstddef>
#include <vector>

namespace ss
{
/// Error statistics of a visibility buffer against a reference on the same pixels.
struct ErrorStats
{
  std::size_t pixels = 0;
  double mae = 0.0, rmse = 0.0, max = 0.0, p99 = 0.0;
};

struct VisibilityErrors
{
  ErrorStats all;      ///< pixels where both are finite
  ErrorStats penumbra; ///< the same restricted to 0.01 < reference < 0.99
  /// |A - R| times the diffuse factor the renderer multiplies V with (the
  /// error in the light's contribution to the picture, in units of its
  /// unshadowed irradiance); only when weights were given, over the pixels
  /// where the weight is finite as well
  ErrorStats shaded;
  std::size_t nonFinite = 0;          ///< Inf in A, or NaN in A where the reference is finite
  std::size_t backgroundMismatch = 0; ///< finite in one, NaN in the other
};

/// Compares A with the reference R (same size; NaN is background). weights
/// (optional, n values): the per-pixel factor V enters the picture with
/// (ss::DiffuseCosine), for VisibilityErrors::shaded.
VisibilityErrors CompareVisibility(
  const float* a, const float* reference, std::size_t n, const float* weights = nullptr);

/// The mean of each s x s block of a (width*s) x (height*s) image (row-major,
/// rows of width*s values): a supersampled buffer brought back to width x
/// height. A block with a non-finite value (background, or a NaN) gives NaN, so
/// pixels on the scene's outline are left out rather than mixed with the
/// background. Returns an empty vector when the sizes do not fit.
std::vector<float> BoxDownsample(const float* fine, std::size_t fineCount, int width, int height, int s);
}

#endif
