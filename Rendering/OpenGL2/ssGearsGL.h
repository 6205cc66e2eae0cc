// GEARS on the GPU: the GL 4.3 compute backend of the GEARS solver.
#ifndef ssGearsGL_h
#define ssGearsGL_h

#include "SoftShadowsRenderingOpenGL2Module.h"
#include "ssGEARS.h"

#include <memory>
#include <string>
#include <vector>

namespace ss
{
/// The GEARS solver's GL compute backend (GL 4.3: compute shaders, SSBOs,
/// atomics, double precision). It runs every stage of the paper on the GPU
/// [§3, §4.2]: pixel samples to grid cells with per-cell far depths (atomics),
/// the summed-area table and the range-maximum table of the grid, shadow-volume
/// boxes with P_far (pass 1), a prefix sum, the (triID, cellID) pairs (pass 2),
/// a counting sort on the cell (atomics + prefix sum) and the per-pixel k x k
/// bitmasks, with the CPU backend's winding count where it applies (members
/// decided per cell, their contour edges' steps per pixel; declined pixels and
/// the rest of each list rasterised). The bitmask arithmetic repeats the CPU backend's double
/// operations in the same order, so both give identical bitmasks on the same
/// inputs (tested on Mesa).
///
/// Only the grid camera's few numbers (from reductions done on the GPU) are
/// set on the CPU, with the same code as the CPU backend (GearsFaceCamera,
/// GearsFitGrid). The triangles come from a GearsSolver (its selection and
/// frame), uploaded once per SetTriangles.
///
/// A GL context of version 4.3 or later must be current for every call.
class SOFTSHADOWSRENDERINGOPENGL2_EXPORT GearsGL
{
public:
  GearsGL();
  ~GearsGL();
  GearsGL(const GearsGL&) = delete;
  GearsGL& operator=(const GearsGL&) = delete;

  /// Whether the current context can run the backend (GL >= 4.3 with
  /// compute shaders, SSBOs and doubles); if not, why not.
  static bool Supported(std::string* why = nullptr);

  /// Same contract as GearsSolver::Solve for solver's triangles. Returns
  /// false and says why for what it does not run, so that the caller can use
  /// the CPU backend: LUT rasterisation (GLSL has no double-precision atan2,
  /// so the table lookups would differ from the CPU's), translucent casters
  /// (their per-sample transmittance cannot persist between the chunked
  /// bitmask dispatches), grids above 240 cells per side, a context without
  /// compute shaders, or buffers beyond the context's SSBO size limit.
  ///
  /// No kernel loops without bound: Mesa's llvmpipe silently ends an
  /// invocation after 65535 loop iterations in all, so the bitmask kernel
  /// takes each cell's triangle list in chunks of 384 (state kept in a
  /// buffer between dispatches).
  bool Solve(const GearsSolver& solver, const LightFrame& light, const glm::dvec3& origin,
    const float* positions, const float* normals, std::size_t n, const GearsOptions& options,
    std::vector<float>& V, GearsStats* stats = nullptr, std::vector<GearsMask>* masks = nullptr,
    std::string* why = nullptr);

  /// Frees the programs and buffers (the context they were made in must be
  /// current).
  void ReleaseGraphicsResources();

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};
}

#endif
