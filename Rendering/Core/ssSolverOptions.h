// Typed options of a visibility solver, declared once in the solver's own
// files (issue 19): key, type, range or value names, default, label and help.
// The pass (SetSolverOption / enumeration), the CLI's `--option key=value`
// and the ParaView view's properties (generated XML) are all made from these
// descriptors, through the solver registry (ssSolverRegistry).
#ifndef ssSolverOptions_h
#define ssSolverOptions_h

#include <string>
#include <vector>

namespace ss
{
enum class OptionType
{
  Int,    ///< an integer in [Min, Max]
  Double, ///< a finite number in [Min, Max]
  Bool,   ///< 0 or 1
  Enum    ///< the index of one of Names (0 .. Names.size() - 1)
};

struct OptionDescriptor
{
  const char* Key;      ///< the generic key: SetSolverOption, the CLI's --option ("pvsm_quality")
  const char* Property; ///< the VTK/ParaView property name ("PVSMQuality"; Set/Get<Property> on the pass)
  const char* Label;    ///< the GUI label ("PVSM Quality")
  OptionType Type;
  double Min;           ///< Int, Double: the range (Bool: 0, Enum: 0)
  double Max;           ///< (Bool: 1, Enum: Names.size() - 1)
  double Default;       ///< Enum: the index of the default name
  std::vector<std::string> Names; ///< Enum: the value names, in index order
  const char* Help;     ///< one line for --help; the GUI's documentation
};

using OptionList = std::vector<OptionDescriptor>;

/// Helpers to declare a solver's options in one row each.
OptionDescriptor IntOption(const char* key, const char* property, const char* label, int lo, int hi,
  int def, const char* help);
OptionDescriptor DoubleOption(const char* key, const char* property, const char* label, double lo,
  double hi, double def, const char* help);
OptionDescriptor BoolOption(const char* key, const char* property, const char* label, bool def,
  const char* help);
OptionDescriptor EnumOption(const char* key, const char* property, const char* label,
  std::vector<std::string> names, int def, const char* help);

/// "int", "double", "bool" or "enum".
const char* OptionTypeName(OptionType t);

/// What the value may be, for usage lines: "1..32", "0.05..64", "0|1", "edge|lut".
std::string DescribeValues(const OptionDescriptor& d);

/// A number as the usage and the XML print it (shortest form: 0.05, 64, 1e+05).
std::string FormatNumber(double v);

/// Empty when `v` is a valid value of `d`; else the error, naming the key
/// ("pvsm_quality: expected a value in [0.05, 64], got 100").
std::string CheckValue(const OptionDescriptor& d, double v);

/// Parses text for `d`: a number for Int/Double/Bool, a name (or its index)
/// for Enum. Returns the error (naming the key) or "" and sets `v`.
std::string ParseValue(const OptionDescriptor& d, const std::string& text, double& v);

/// The values of a set of options: each starts at its default; a refused
/// value leaves the previous one.
class OptionStore
{
public:
  OptionStore() = default;
  explicit OptionStore(std::vector<const OptionDescriptor*> options);

  std::size_t Size() const { return this->Options.size(); }
  const OptionDescriptor& Descriptor(std::size_t i) const { return *this->Options[i]; }
  /// The index of `key`, or -1.
  int Find(const std::string& key) const;

  /// "" when set, else the error (unknown key, or CheckValue's).
  std::string Set(const std::string& key, double v);
  std::string SetText(const std::string& key, const std::string& text);
  /// The value (NaN for an unknown key).
  double Get(const std::string& key) const;
  double Get(std::size_t i) const { return this->Values[i]; }

private:
  std::vector<const OptionDescriptor*> Options;
  std::vector<double> Values;
};
}

#endif
