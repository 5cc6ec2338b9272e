#pragma once
// A number in a message or a text file: the shortest decimal text that reads back (strtod, std::from_chars) as
// exactly the same double — std::to_chars without a format or precision ([charconv.to.chars] of C++17: the
// shortest round-trip representation, fixed or scientific, whichever is shorter). 0.1 → "0.1", 866e6 →
// "8.66e+08", 0.1 + 0.2 → "0.30000000000000004" (a message shows the value that was really given or computed,
// never a rounded one that looks in range); ±infinity → "inf" / "-inf", NaN → "nan" / "-nan".
// Independent of the locale; thread-safe; throws only std::bad_alloc.
#include <string>

namespace rfidray {

std::string num(double v);

// An estimate or a display value, rounded to `significant_digits` (printf %.*g): 1.408e7 at 4 digits →
// "1.408e+07". For numbers that are approximate by nature ("about N triangles", "0.0671 GB"); values a user gave
// or a result computed exactly are num()'s.
std::string rounded_text(double v, int significant_digits);

}  // namespace rfidray
