// Typed solver options (Rendering/Core ssSolverOptions): validation, the
// errors naming the key, the store keeping the previous value.
#include "ssSolverOptions.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
const ss::OptionList& Options()
{
  static const ss::OptionList list = {
    ss::IntOption("k_int", "KInt", "K Int", 1, 32, 16, "an int"),
    ss::DoubleOption("k_double", "KDouble", "K Double", 0.05, 64.0, 1.0, "a double"),
    ss::BoolOption("k_bool", "KBool", "K Bool", true, "a bool"),
    ss::EnumOption("k_enum", "KEnum", "K Enum", { "auto", "dynamic", "static" }, 0, "an enum"),
  };
  return list;
}

ss::OptionStore Store()
{
  std::vector<const ss::OptionDescriptor*> d;
  for (const auto& o : Options())
  {
    d.push_back(&o);
  }
  return ss::OptionStore(d);
}
}

TEST(SolverOptions, DescriptorsDescribeTheirValues)
{
  const auto& o = Options();
  EXPECT_EQ(ss::DescribeValues(o[0]), "1..32");
  EXPECT_EQ(ss::DescribeValues(o[1]), "0.05..64");
  EXPECT_EQ(ss::DescribeValues(o[2]), "0|1");
  EXPECT_EQ(ss::DescribeValues(o[3]), "auto|dynamic|static");
  EXPECT_EQ(o[3].Max, 2.0);
  EXPECT_EQ(o[2].Default, 1.0);
  EXPECT_STREQ(ss::OptionTypeName(o[1].Type), "double");
}

TEST(SolverOptions, StoreStartsAtDefaultsAndRefusesOutOfRange)
{
  ss::OptionStore s = Store();
  EXPECT_EQ(s.Get("k_int"), 16.0);
  EXPECT_EQ(s.Get("k_double"), 1.0);
  EXPECT_EQ(s.Get("k_bool"), 1.0);
  EXPECT_EQ(s.Get("k_enum"), 0.0);
  EXPECT_TRUE(std::isnan(s.Get("nope")));

  EXPECT_EQ(s.Set("k_int", 32), "");
  EXPECT_EQ(s.Get("k_int"), 32.0);
  EXPECT_EQ(s.Set("k_int", 33), "k_int: expected an integer in [1, 32], got 33");
  EXPECT_EQ(s.Set("k_int", 2.5), "k_int: expected an integer in [1, 32], got 2.5");
  EXPECT_EQ(s.Get("k_int"), 32.0); // kept
  EXPECT_EQ(s.Set("k_double", 0.0), "k_double: expected a value in [0.05, 64], got 0");
  EXPECT_NE(s.Set("k_double", NAN), "");
  EXPECT_EQ(s.Get("k_double"), 1.0);
  EXPECT_EQ(s.Set("k_double", 0.05), "");
  EXPECT_EQ(s.Set("k_bool", 2), "k_bool: expected an integer in [0, 1], got 2");
  EXPECT_EQ(s.Set("k_enum", 3), "k_enum: expected auto, dynamic or static, got 3");
  EXPECT_EQ(s.Set("nope", 1), "unknown solver option 'nope'");
}

TEST(SolverOptions, TextParsesNamesAndNumbers)
{
  ss::OptionStore s = Store();
  EXPECT_EQ(s.SetText("k_enum", "static"), "");
  EXPECT_EQ(s.Get("k_enum"), 2.0);
  EXPECT_EQ(s.SetText("k_enum", "fast"), "k_enum: expected auto, dynamic or static, got 'fast'");
  EXPECT_EQ(s.Get("k_enum"), 2.0);
  EXPECT_EQ(s.SetText("k_int", "64"), "k_int: expected an integer in [1, 32], got '64'");
  EXPECT_EQ(s.SetText("k_int", "big"), "k_int: expected an integer in [1, 32], got 'big'");
  EXPECT_EQ(s.SetText("k_int", "3.5"), "k_int: expected an integer in [1, 32], got '3.5'");
  EXPECT_EQ(s.SetText("k_int", "7"), "");
  EXPECT_EQ(s.Get("k_int"), 7.0);
  EXPECT_EQ(s.SetText("k_bool", "yes"), "k_bool: expected an integer in [0, 1], got 'yes'");
  EXPECT_EQ(s.SetText("k_double", "0.5x"), "k_double: expected a value in [0.05, 64], got '0.5x'");
  EXPECT_EQ(s.SetText("k_double", "2.5"), "");
  EXPECT_EQ(s.Get("k_double"), 2.5);
}
