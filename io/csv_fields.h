#pragma once
// Field-level helpers for the CSV importers (trajectory_csv, real_log): trimming, header-name matching and
// strict number parsing whose errors name "FILE:LINE: column 'NAME': what". Stateless, thread-safe.
#include <optional>
#include <string>
#include <string_view>

namespace rfidray::io {

// "FILE:LINE: " (LINE 1-based; 0 leaves it out).
std::string located(const std::string& file, int line);

// Without leading/trailing blanks, tabs and '\r'.
std::string trim(std::string_view s);
// Removes a UTF-8 byte order mark from the front of the first line of a file.
void strip_bom(std::string& line);

// A header name reduced for matching: lower case, without blanks, '_', '-', '.', '(', ')', '/'
// ("Phase Angle (deg)" → "phaseangledeg", "EPC-96" → "epc96").
std::string normalized_name(std::string_view name);

// The number in `text` (blanks trimmed, a leading '+' allowed); nullopt when it is not entirely a number.
// A decimal comma is accepted when the field has one comma and no point: ItemTest writes "-77,5" under
// comma-decimal locales (quoted, so the CSV split keeps it whole).
std::optional<double> to_number(std::string_view text);
// to_number, or InputError "FILE:LINE: column 'NAME': not a number ('x')" / "... not finite (...)".
double parse_finite(std::string_view text, const std::string& file, int line, const std::string& column);

}  // namespace rfidray::io
