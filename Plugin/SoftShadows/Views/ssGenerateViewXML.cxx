// Build-time generator of the Soft Shadow View's server-manager XML (issue
// 19): copies Views/SoftShadowView.xml and fills its three markers from the
// solver registry, through vtkSoftShadowPass's enumeration, so that a
// method's options are declared once, in its solver's files:
//   <!-- @METHOD_ENTRIES@ -->  the Method menu: one Entry per registered method
//   <!-- @METHOD_RANGE@ -->    the range of those entries: other values are refused
//   <!-- @SOLVER_OPTIONS@ -->  one property per solver option (name: its VTK
//        property name, so state files saved before still load; command: its
//        key, applied by vtkSISoftShadowProperty through
//        vtkPVSoftShadowView::SetSolverOption), and their property group.
// Usage: ssGenerateViewXML IN.xml OUT.xml (run by Plugin/SoftShadows/CMakeLists.txt).
#include "vtkNew.h"
#include "vtkSoftShadowPass.h"

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
std::string Escape(const std::string& s)
{
  std::string o;
  for (char c : s)
  {
    switch (c)
    {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

// The shortest text that reads back as v (0.05, not 0.050000000000000003).
std::string Number(double v)
{
  for (int digits : { 6, 17 })
  {
    std::ostringstream o;
    o.precision(digits);
    o << v;
    if (digits == 17 || std::stod(o.str()) == v)
    {
      return o.str();
    }
  }
  return {};
}

std::string MethodEntries(const std::string& indent)
{
  std::ostringstream o;
  vtkNew<vtkSoftShadowPass> pass; // no window: only its registry's range
  for (int m = vtkSoftShadowPass::AUTO; m <= pass->GetMethodMaxValue(); ++m)
  {
    o << indent << "<Entry text=\"" << vtkSoftShadowPass::GetMethodName(m) << "\" value=\"" << m
      << "\"/>\n";
  }
  return o.str();
}

// "allowed": values outside the menu are refused and the last valid value
// kept (vtkSMSoftShadowIntRangeDomain); the Properties panel makes the widget
// of the last domain by name, so "bool" and "enum" keep their check box and menu.
std::string Allowed(const std::string& indent, int last)
{
  std::ostringstream o;
  o << indent << "<SoftShadowIntRangeDomain name=\"allowed\" min=\"0\" max=\"" << last << "\"/>\n";
  return o.str();
}

std::string MethodRange(const std::string& indent)
{
  vtkNew<vtkSoftShadowPass> pass;
  return Allowed(indent, pass->GetMethodMaxValue());
}

std::string SolverOptions(const std::string& in)
{
  using P = vtkSoftShadowPass;
  std::ostringstream o;
  for (int i = 0; i < P::GetNumberOfSolverOptions(); ++i)
  {
    const std::string type = P::GetSolverOptionType(i);
    const std::string element = type == "double" ? "DoubleVectorProperty" : "IntVectorProperty";
    o << in << "<" << element << " name=\"" << P::GetSolverOptionPropertyName(i) << "\" label=\""
      << Escape(P::GetSolverOptionLabel(i)) << "\" command=\"" << P::GetSolverOptionKey(i)
      << "\" si_class=\"vtkSISoftShadowProperty\"\n"
      << in << "    number_of_elements=\"1\" default_values=\"" << Number(P::GetSolverOptionDefault(i))
      << "\" panel_visibility=\"advanced\">\n";
    if (type == "bool")
    {
      o << Allowed(in + "  ", 1) << in << "  <BooleanDomain name=\"bool\"/>\n";
    }
    else if (type == "enum")
    {
      o << Allowed(in + "  ", P::GetSolverOptionNumberOfNames(i) - 1) << in << "  <EnumerationDomain name=\"enum\">\n";
      for (int n = 0; n < P::GetSolverOptionNumberOfNames(i); ++n)
      {
        o << in << "    <Entry text=\"" << Escape(P::GetSolverOptionName(i, n)) << "\" value=\"" << n
          << "\"/>\n";
      }
      o << in << "  </EnumerationDomain>\n";
    }
    else
    {
      o << in << "  <SoftShadow" << (type == "double" ? "Double" : "Int") << "RangeDomain name=\"range\" min=\""
        << Number(P::GetSolverOptionMinimum(i)) << "\" max=\"" << Number(P::GetSolverOptionMaximum(i))
        << "\"/>\n";
    }
    o << in << "  <Documentation>" << Escape(P::GetSolverOptionHelp(i)) << " (methods: "
      << Escape(P::GetSolverOptionMethods(i)) << "; key " << P::GetSolverOptionKey(i)
      << " of vtkSoftShadowPass::SetSolverOption and softshadows --option)</Documentation>\n";
    o << in << "</" << element << ">\n";
  }
  o << in << "<PropertyGroup label=\"Soft Shadow Methods\">\n";
  for (int i = 0; i < P::GetNumberOfSolverOptions(); ++i)
  {
    o << in << "  <Property name=\"" << P::GetSolverOptionPropertyName(i) << "\"/>\n";
  }
  o << in << "</PropertyGroup>\n";
  return o.str();
}

// Replaces the line holding `marker` by text(indent of that line).
bool Fill(std::string& xml, const std::string& marker, std::string (*text)(const std::string&))
{
  const auto at = xml.find(marker);
  if (at == std::string::npos)
  {
    return false;
  }
  const auto lineStart = xml.rfind('\n', at) + 1;
  const auto lineEnd = xml.find('\n', at);
  const std::string indent = xml.substr(lineStart, at - lineStart);
  xml.replace(lineStart, lineEnd + 1 - lineStart, text(indent));
  return true;
}
}

int main(int argc, char* argv[])
{
  if (argc != 3)
  {
    std::cerr << "usage: ssGenerateViewXML IN.xml OUT.xml\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string xml = buffer.str();
  if (!in || xml.empty())
  {
    std::cerr << "ssGenerateViewXML: cannot read '" << argv[1] << "'\n";
    return 1;
  }
  if (!Fill(xml, "<!-- @METHOD_ENTRIES@ -->", MethodEntries) || !Fill(xml, "<!-- @METHOD_RANGE@ -->", MethodRange) ||
    !Fill(xml, "<!-- @SOLVER_OPTIONS@ -->", SolverOptions))
  {
    std::cerr << "ssGenerateViewXML: '" << argv[1]
              << "' lacks a marker (@METHOD_ENTRIES@, @METHOD_RANGE@, @SOLVER_OPTIONS@)\n";
    return 1;
  }
  std::ofstream out(argv[2]);
  out << xml;
  out.close();
  if (!out)
  {
    std::cerr << "ssGenerateViewXML: cannot write '" << argv[2] << "'\n";
    return 1;
  }
  return 0;
}
