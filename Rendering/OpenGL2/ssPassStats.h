// What vtkSoftShadowPass reports about a frame (GetStatsJSON): per-stage
// timings, and the stats object assembled from the pass's own numbers and the
// solvers' fragments.
#ifndef ssPassStats_h
#define ssPassStats_h

#include <chrono>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ss
{
using Clock = std::chrono::steady_clock;

/// Milliseconds from a to b.
double Milliseconds(Clock::time_point a, Clock::time_point b);

/// The timings_ms of one frame, one entry per stage. With Measure on, Finish()
/// waits for the GPU (glFinish) so that a stage's time includes its GPU work
/// (vtkSoftShadowPass::MeasureTimings).
class StageTimings
{
public:
  void Clear() { this->Stages.clear(); }
  void SetMeasure(bool measure) { this->Measure = measure; }
  bool GetMeasure() const { return this->Measure; }
  /// glFinish when measuring; nothing otherwise.
  void Finish() const;
  void Set(const std::string& stage, double ms) { this->Stages[stage] = ms; }
  void Add(const std::string& stage, double ms) { this->Stages[stage] += ms; }
  /// 0 when the stage did not run this frame.
  double Get(const std::string& stage) const;
  const std::map<std::string, double>& All() const { return this->Stages; }

private:
  std::map<std::string, double> Stages;
  bool Measure = false;
};

/// The numbers GetStatsJSON reports, gathered by the pass.
struct FrameStats
{
  std::string PlanJSON;
  const StageTimings* Timings = nullptr;
  long long MemoryBytes = 0;
  std::size_t CasterTriangles = 0;
  std::size_t SkippedTriangles = 0;
  /// (key, JSON object) of every solver that reports stats, in registry order.
  std::vector<std::pair<std::string, std::string>> Solvers;
  int ShadowMapSize = 0;
  std::string ShadowMapSizeNote;
  /// one JSON object per light of the renderer
  std::vector<std::string> Lights;
};

/// {"plan": ..., "timings_ms": {...}, "memory_bytes": ..., <solver fragments>, "lights": [...]}
std::string StatsToJSON(const FrameStats& stats);
}

#endif
