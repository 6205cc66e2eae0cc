#include "ssPlot.h"

#include "ssImageIO.h"

#include "vtkAxis.h"
#include "vtkChartLegend.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPen.h"
#include "vtkPlot.h"
#include "vtkPlotPoints.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkTextProperty.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <map>

namespace ssapp
{
namespace
{
// An off-screen 900 x `height` chart view, white, with a titled chart and its legend.
void SetUpChart(vtkContextView* view, vtkChartXY* chart, const std::string& title, int height)
{
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetMultiSamples(0);
  view->GetRenderWindow()->SetSize(900, height);
  view->GetRenderer()->SetBackground(1, 1, 1);
  view->GetScene()->AddItem(chart);
  chart->SetTitle(title);
  chart->GetTitleProperties()->SetFontSize(16);
  chart->SetShowLegend(true);
}

// A two-column table (time, error) of the given points: one plotted series.
vtkSmartPointer<vtkTable> Series(const std::string& name, const std::vector<const PlotPoint*>& pts)
{
  auto table = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkFloatArray> x, y;
  x->SetName("ms");
  y->SetName(name.c_str());
  for (const auto* p : pts)
  {
    x->InsertNextValue(static_cast<float>(p->ms));
    y->InsertNextValue(static_cast<float>(p->mae));
  }
  table->AddColumn(x);
  table->AddColumn(y);
  return table;
}
}

bool PlotErrorVsTime(const std::string& path, const std::string& title,
  const std::vector<PlotPoint>& points, std::string& message)
{
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  SetUpChart(view, chart, title, 600);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time per frame (ms, log scale)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(true);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("mean absolute visibility error vs reference");

  // one point series per method
  std::map<std::string, std::vector<const PlotPoint*>> byMethod;
  for (const auto& p : points)
  {
    byMethod[p.method].push_back(&p);
  }
  // Tableau 10: eight methods (vtk included) each get their own colour; with
  // seven, gears and vtk were both blue
  const unsigned char colors[][3] = { { 31, 119, 180 }, { 255, 127, 14 }, { 44, 160, 44 },
    { 214, 39, 40 }, { 148, 103, 189 }, { 140, 86, 75 }, { 227, 119, 194 }, { 127, 127, 127 },
    { 188, 189, 34 }, { 23, 190, 207 } };
  const int numColors = static_cast<int>(sizeof(colors) / sizeof(colors[0]));
  int ci = 0;
  for (const auto& m : byMethod)
  {
    vtkPlot* plot = chart->AddPlot(vtkChart::POINTS);
    plot->SetInputData(Series(m.first, m.second), 0, 1);
    const auto* c = colors[ci++ % numColors];
    plot->SetColor(c[0], c[1], c[2], 255);
    if (auto* pts = vtkPlotPoints::SafeDownCast(plot))
    {
      pts->SetMarkerStyle(vtkPlotPoints::CIRCLE);
      pts->SetMarkerSize(10);
    }
  }
  // the Pareto front: no other point is both faster and more accurate
  std::vector<const PlotPoint*> front;
  for (const auto& p : points)
  {
    if (p.pareto)
    {
      front.push_back(&p);
    }
  }
  std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->ms < b->ms; });
  if (front.size() >= 2)
  {
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(Series("Pareto front", front), 0, 1);
    line->SetColor(0, 0, 0, 255);
    line->SetWidth(2.0);
    line->GetPen()->SetLineType(vtkPen::DASH_LINE);
  }
  view->GetRenderWindow()->Render();
  return WriteWindowPNG(view->GetRenderWindow(), path, message);
}

bool PlotLines(const std::string& path, const std::string& title, const std::string& xTitle,
  const std::string& leftTitle, const std::string& rightTitle, const std::vector<PlotSeries>& series,
  std::string& message)
{
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  SetUpChart(view, chart, title, 560);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::CENTER);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(xTitle);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(leftTitle);
  chart->GetAxis(vtkAxis::RIGHT)->SetTitle(rightTitle);
  for (const auto& s : series)
  {
    auto table = vtkSmartPointer<vtkTable>::New();
    vtkNew<vtkFloatArray> x, y;
    x->SetName("x");
    y->SetName(s.name.c_str());
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
    {
      x->InsertNextValue(static_cast<float>(s.x[i]));
      y->InsertNextValue(static_cast<float>(s.y[i]));
    }
    table->AddColumn(x);
    table->AddColumn(y);
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    line->SetColor(s.rgb[0], s.rgb[1], s.rgb[2], 255);
    line->SetWidth(s.dashed ? 1.5 : 2.5);
    if (s.dashed)
    {
      line->GetPen()->SetLineType(vtkPen::DASH_LINE);
    }
    if (s.rightAxis)
    {
      chart->SetPlotCorner(line, 1);
    }
  }
  view->GetRenderWindow()->Render();
  return WriteWindowPNG(view->GetRenderWindow(), path, message);
}

bool WriteWindowPNG(vtkRenderWindow* win, const std::string& path, std::string& message)
{
  vtkNew<vtkWindowToImageFilter> w2i;
  w2i->SetInput(win);
  w2i->SetInputBufferTypeToRGB();
  w2i->ReadFrontBufferOff();
  w2i->Update();
  int dims[3];
  w2i->GetOutput()->GetDimensions(dims);
  auto* rgb = vtkUnsignedCharArray::SafeDownCast(w2i->GetOutput()->GetPointData()->GetScalars());
  if (!rgb)
  {
    message = "no picture in the window";
    return false;
  }
  return WriteRGB8Image(path, rgb->GetPointer(0), dims[0], dims[1], 3, message);
}
}
