#pragma once
// One error type for bad user input. The message always names where the problem is
// (file, line, field) so the CLI can print it as-is and exit non-zero.
#include <stdexcept>
#include <string>

namespace rfidray {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "field 'antennas[0].frequency': must be > 0 (got -1)"
inline InputError field_error(const std::string& field, const std::string& what) {
  return InputError("field '" + field + "': " + what);
}

}  // namespace rfidray
