// Accuracy-against-time plots, drawn with VTK's charts.
#ifndef ssPlot_h
#define ssPlot_h

#include <string>
#include <vector>

namespace ssapp
{
struct PlotPoint
{
  std::string method; // legend entry
  std::string label;  // settings
  double ms = 0.0;
  double mae = 0.0;
  bool pareto = false;
};

/// A PNG of error against time (log scale) per method, Pareto front dashed.
bool PlotErrorVsTime(const std::string& path, const std::string& title,
  const std::vector<PlotPoint>& points, std::string& message);
}

#endif
