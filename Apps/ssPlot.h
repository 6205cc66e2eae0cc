// Accuracy-against-time plots, drawn with VTK's charts.
#ifndef ssPlot_h
#define ssPlot_h

#include <string>
#include <vector>

class vtkRenderWindow;

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

/// One line of PlotLines: y against x, on the left or right axis.
struct PlotSeries
{
  std::string name;
  std::vector<double> x, y;
  unsigned char rgb[3] = { 0, 0, 0 };
  bool rightAxis = false, dashed = false;
};

/// A PNG of lines against a common x (e.g. error and memory per frame).
bool PlotLines(const std::string& path, const std::string& title, const std::string& xTitle,
  const std::string& leftTitle, const std::string& rightTitle, const std::vector<PlotSeries>& series,
  std::string& message);

/// The render window's picture (RGB) as a PNG through OpenImageIO.
bool WriteWindowPNG(vtkRenderWindow* win, const std::string& path, std::string& message);
}

#endif
