#include "uav/shared/decimal.hpp"

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>

namespace uav {
namespace {

bool Digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// Length of the decimal number's syntax at the start of `s` (0: none).
std::size_t DecimalSyntax(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && Digit(s[i])) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && Digit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    std::size_t exp_digits = 0;
    while (j < s.size() && Digit(s[j])) ++j, ++exp_digits;
    if (exp_digits == 0) return 0;
    i = j;
  }
  return i;
}

}  // namespace

std::optional<double> ParseDecimal(std::string_view text) {
  if (text.empty() || DecimalSyntax(text) != text.size()) return std::nullopt;
  const std::string s(text);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::vector<double>> ParseDecimalList(std::string_view text, std::size_t count, char separator) {
  std::vector<double> out;
  while (true) {
    const std::size_t end = text.find(separator);
    const std::optional<double> v = ParseDecimal(text.substr(0, end));
    if (!v) return std::nullopt;
    out.push_back(*v);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  if (out.size() != count) return std::nullopt;
  return out;
}

void RequireDecimalNumbers(CLI::App& app) {
  for (CLI::Option* opt : app.get_options(std::function<bool(CLI::Option*)>{})) {
    // The type name carries each validator's description after a colon ("FLOAT:FLOAT in [1 -
    // 100]"); CLI::Range lets NaN through (every comparison with it is false), so an option with
    // a range needs this check as much as one without.
    const std::string full = opt->get_type_name();
    const std::string type = full.substr(0, full.find(':'));
    const bool whole = type == "INT" || type == "UINT";
    if (!whole && type != "FLOAT") continue;
    opt->check(CLI::Validator(
        [whole](std::string& value) -> std::string {
          const auto v = ParseDecimal(value);
          if (!v) return "'" + value + "' is not a finite number (decimal digits only)";
          if (whole && *v != std::floor(*v)) return "'" + value + "' is not a whole number";
          return "";
        },
        whole ? "DECIMAL INTEGER" : "DECIMAL", "decimal number"));
  }
  for (CLI::App* sub : app.get_subcommands(std::function<bool(CLI::App*)>{})) RequireDecimalNumbers(*sub);
}

}  // namespace uav
