// `softshadows bench`, and the pieces of `render` it shares.
#ifndef ssBench_h
#define ssBench_h

#include "vtkSmartPointer.h"

#include <stdexcept>
#include <string>
#include <vector>

class vtkRenderPass;
class vtkSoftShadowPass;

namespace ssapp
{
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// Applies one --option key=value to the pass (throws UsageError).
void ApplyOption(vtkSoftShadowPass* pass, const std::string& keyValue);
/// VTK's own shadow pass, set up as in VTK's TestShadowMapPass.
vtkSmartPointer<vtkRenderPass> MakeVTKShadowPass();
double Median(std::vector<double> v);
/// Integer in [lo, hi] (throws UsageError naming `what`).
int ParseInt(const std::string& s, const std::string& what, int lo, int hi);
/// The value after the flag args[i] (advances i; throws UsageError when missing).
std::string FlagValue(const std::vector<std::string>& args, std::size_t& i);
/// WxH (throws UsageError).
void ParseSize(const std::string& s, int& width, int& height);

/// softshadows bench [--smoke] [--scenes a.json,b.json] [--out DIR] [--frames N]
///   [--size WxH] [--reference-samples K]
int Bench(const std::vector<std::string>& args);
/// softshadows bench --gears [--smoke] --scenes a.json,... [--sizes 512x512,1024x1024]
///   [--samples 16,32] [--out DIR]: GEARS against the reference at identical samples.
int BenchGEARS(const std::vector<std::string>& args);
/// softshadows bench --pvsm [--smoke] --scenes a.json,... [--out DIR] [--frames N] [--size WxH]
///   [--reference-samples K]: PVSM against fixed-resolution PCSS and the average
///   of 8x8 hard shadow maps, overview and close-up cameras, large and small
///   light, and PVSM soft against PVSM with a point light (PVSM §6).
int BenchPVSM(const std::vector<std::string>& args);
/// softshadows bench --vpcss [--smoke] --scenes a.json,... [--out DIR] [--frames N] [--size WxH]
///   [--reference-samples K]: VPCSS against hard AVSM, PCSS and the reference's
///   transmittance: time, error, AVSM memory (ssBenchVPCSS.cxx).
int BenchVPCSS(const std::vector<std::string>& args);
/// softshadows bench --asm [--smoke] --scenes a.json,... [--out DIR] [--frames N] [--size WxH]:
///   ASM at 8 and 16 MB against one 2048² map over a scripted walkthrough
///   (ssBenchASM.cxx).
int BenchASM(const std::vector<std::string>& args);
}

#endif
