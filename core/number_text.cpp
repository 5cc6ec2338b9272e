#include "core/number_text.h"

#include <charconv>
#include <cstdio>

namespace rfidray {

std::string num(double v) {
  char buf[32];  // the longest shortest form is 24 characters ("-2.2250738585072014e-308")
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec;  // cannot fail: 32 characters hold every double
  return std::string(buf, end);
}

std::string rounded_text(double v, int significant_digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", significant_digits, v);
  return buf;
}

}  // namespace rfidray
