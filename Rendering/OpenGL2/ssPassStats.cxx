#include "ssPassStats.h"

#include "ssEffectPlanner.h"

#include "vtk_glew.h"

#include <sstream>

namespace ss
{
double Milliseconds(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

void StageTimings::Finish() const
{
  if (this->Measure)
  {
    glFinish();
  }
}

double StageTimings::Get(const std::string& stage) const
{
  const auto it = this->Stages.find(stage);
  return it == this->Stages.end() ? 0.0 : it->second;
}

std::string StatsToJSON(const FrameStats& s)
{
  std::ostringstream o;
  o.precision(17);
  o << "{\"plan\": " << s.PlanJSON << ", \"timings_ms\": {";
  bool first = true;
  if (s.Timings)
  {
    for (const auto& t : s.Timings->All())
    {
      o << (first ? "" : ", ") << '"' << t.first << "\": " << t.second;
      first = false;
    }
  }
  o << "}, \"memory_bytes\": " << s.MemoryBytes << ", \"caster_triangles\": " << s.CasterTriangles
    << ", \"skipped_triangles\": " << s.SkippedTriangles;
  for (const auto& f : s.Solvers)
  {
    o << ", \"" << f.first << "\": " << f.second;
  }
  o << ", \"shadow_map_size\": " << s.ShadowMapSize << ", \"shadow_map_size_note\": \""
    << JSONEscape(s.ShadowMapSizeNote) << "\", \"lights\": [";
  first = true;
  for (const auto& l : s.Lights)
  {
    o << (first ? "" : ", ") << l;
    first = false;
  }
  o << "]}";
  return o.str();
}
}
