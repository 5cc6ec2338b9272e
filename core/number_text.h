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

}  // namespace rfidray
