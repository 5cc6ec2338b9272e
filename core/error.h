#pragma once
// One error type for bad user input. The message always names where the problem is
// (file, line, field) so the CLI can print it as-is and exit non-zero.
#include <stdexcept>
#include <string>
#include <string_view>

namespace rfidray {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "field 'antennas[0].frequency': must be > 0 (got -1)"
inline InputError field_error(const std::string& field, const std::string& what) {
  return InputError("field '" + field + "': " + what);
}

// A user-supplied value echoed in a message, cut to `max_chars` bytes with "…" (a 100 kB field must not
// flood the terminal); never splits a UTF-8 sequence.
inline std::string clip(std::string_view value, size_t max_chars = 80) {
  if (value.size() <= max_chars) return std::string(value);
  size_t n = max_chars;
  while (n > 0 && (static_cast<unsigned char>(value[n]) & 0xC0) == 0x80) --n;
  return std::string(value.substr(0, n)) + "… (" + std::to_string(value.size()) + " bytes)";
}

}  // namespace rfidray
