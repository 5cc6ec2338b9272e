#include "io/csv_fields.h"

#include <cctype>
#include <charconv>
#include <cmath>

#include "core/error.h"

namespace rfidray::io {

std::string located(const std::string& file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
}

std::string trim(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return std::string(s.substr(b, e - b));
}

void strip_bom(std::string& line) {
  if (line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
}

std::string normalized_name(std::string_view name) {
  std::string out;
  for (char c : name) {
    if (c == ' ' || c == '\t' || c == '\r' || c == '_' || c == '-' || c == '.' || c == '(' || c == ')' || c == '/')
      continue;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

std::optional<double> to_number(std::string_view text) {
  std::string t = trim(text);
  if (!t.empty() && t[0] == '+') t.erase(0, 1);
  if (t.empty()) return std::nullopt;
  if (t.find('.') == std::string::npos) {
    const size_t comma = t.find(',');
    if (comma != std::string::npos && t.find(',', comma + 1) == std::string::npos) t[comma] = '.';
  }
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

double parse_finite(std::string_view text, const std::string& file, int line, const std::string& column) {
  const std::optional<double> v = to_number(text);
  if (!v)
    throw InputError(located(file, line) + "column '" + column + "': " +
                     (trim(text).empty() ? std::string("empty value") : "not a number ('" + trim(text) + "')"));
  if (!std::isfinite(*v))
    throw InputError(located(file, line) + "column '" + column + "': not finite ('" + trim(text) + "')");
  return *v;
}

}  // namespace rfidray::io
