#ifndef ssCoverage_h
#define ssCoverage_h

#include <functional>

namespace ss
{
/// An axis-aligned rectangle [x0,x1] x [y0,y1].
struct Rect
{
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double Area() const;
};

/// Length of [a0,a1] ∩ [b0,b1] (>= 0).
double Overlap1D(double a0, double a1, double b0, double b1);
double RectOverlapArea(const Rect& a, const Rect& b);

/// PVSM §4.1 eq. 2: texel (i,j) is the quad [i,i+1]x[j,j+1] (texel units) of
/// constant depth depth[j*w+i]; V = sum c(t) o(t) / area(kernel), c the overlap
/// of the quad with the kernel box and o(t) = 1 when the receiver is lit
/// (receiverDepth - bias <= depth). Texels outside the map count as lit. A
/// zero-area kernel is a point lookup of the texel holding its centre.
double CoverageFilter(const float* depth, int w, int h, const Rect& kernel, double receiverDepth, double bias);
/// The same with a receiver depth per texel centre (receiver-plane depth).
double CoverageFilter(const float* depth, int w, int h, const Rect& kernel,
  const std::function<double(double, double)>& receiverDepthAt, double bias);
/// The same integral over quads of `stride` texels (a power of two): a quad uses
/// the depth of its centre texel. This is how the GPU bounds the cost of big kernels.
double CoverageFilterStrided(const float* depth, int w, int h, const Rect& kernel,
  double receiverDepth, double bias, int stride);
}

#endif
