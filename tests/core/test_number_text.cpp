// num(): one number formatter for messages and text files, the shortest text that reads back as the same double.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>

#include "core/limits.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

TEST(NumberText, ShortestTextThatReadsBack) {
  EXPECT_EQ(num(0.1), "0.1");
  EXPECT_EQ(num(866e6), "8.66e+08");
  EXPECT_EQ(num(-2.5), "-2.5");
  EXPECT_EQ(num(0.0), "0");
  EXPECT_EQ(num(1e308), "1e+308");
  EXPECT_EQ(num(1e-300), "1e-300");
  EXPECT_EQ(num(123456789.0), "123456789");  // %.6g would print 1.23457e+08
  EXPECT_EQ(num(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(num(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(num(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(num(std::numeric_limits<double>::quiet_NaN()).find("nan") != std::string::npos, true);
}

// Every double, whatever its magnitude, reads back bit for bit (strtod is the C library's reader, independent
// of to_chars).
TEST(NumberText, RoundTripsRandomDoubles) {
  std::mt19937_64 rng(31);
  for (int i = 0; i < 100000; ++i) {
    uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    const std::string text = num(v);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
  }
  EXPECT_EQ(std::strtod(num(std::numeric_limits<double>::denorm_min()).c_str(), nullptr),
            std::numeric_limits<double>::denorm_min());
}

TEST(NumberText, RoundedTextIsForEstimates) {
  EXPECT_EQ(rounded_text(14080000.0, 6), "1.408e+07");
  EXPECT_EQ(rounded_text(0.067108864, 3), "0.0671");
  EXPECT_EQ(num(14080000.0), "14080000");  // the exact value, for contrast
}

// A range message shows the value given, not a rounded one that looks in range.
TEST(NumberText, RangeMessagesShowTheExactValue) {
  try {
    limits::check_range(100.00000001, 0.0, 100.0, "--x", "m");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("must be in [0, 100] m (got 100.00000001)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfidray
