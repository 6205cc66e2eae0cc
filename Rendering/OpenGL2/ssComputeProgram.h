// One compute shader compiled and linked into a program (GL 4.3), for the
// solvers that dispatch their own kernels (GEARS GL, the AVSM build).
#ifndef ssComputeProgram_h
#define ssComputeProgram_h

#include "vtk_glew.h"

#include <string>

namespace ss
{
/// The program of `source`, or 0 with `error` set to "does not compile: LOG"
/// or "does not link: LOG" (the caller prefixes what it was building).
GLuint CompileComputeProgram(const std::string& source, std::string& error);
}

#endif
