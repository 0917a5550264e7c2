// Small helpers of the command-line tools: argument values parsed strictly, errors as InvalidArgument whose message
// starts with the argument's name ("--thresholds: ...").
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace tools {

[[noreturn]] inline void badArgument(const std::string& arg, const std::string& what) {
  throw InvalidArgument(arg + ": " + what);
}

inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

/// A short human form of a double for messages ("nan", "inf", "-1", "0.0001").
inline std::string shortNumber(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  for (int digits = 15; digits <= 17; ++digits) {  // the shortest form that reads back to x
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

/// Any double strtod accepts (including inf / nan: the callers check the range and say what they got), the whole
/// text and nothing else.
inline double parseNumber(const std::string& arg, const std::string& text) {
  const std::string t = trim(text);
  if (t.empty()) badArgument(arg, "expected a number, got an empty value");
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size()) badArgument(arg, "expected a number, got '" + text + "'");
  return v;
}

/// A finite number >= lo (or > lo if strict).
inline double parseBounded(const std::string& arg, const std::string& text, double lo, bool strict,
                           const std::string& unit = "") {
  const double v = parseNumber(arg, text);
  if (!std::isfinite(v) || v < lo || (strict && v == lo)) {
    badArgument(arg, std::string("expected a finite number ") + (strict ? "> " : ">= ") + shortNumber(lo) +
                         (unit.empty() ? "" : " (" + unit + ")") + ", got '" + trim(text) + "'");
  }
  return v;
}

/// A non-negative integer (decimal), at most `hi`.
inline long long parseCount(const std::string& arg, const std::string& text,
                            long long hi = std::numeric_limits<long long>::max()) {
  const std::string t = trim(text);
  bool digits = !t.empty();
  for (char c : t) digits = digits && c >= '0' && c <= '9';
  if (!digits) badArgument(arg, "expected a non-negative integer, got '" + text + "'");
  errno = 0;
  const long long v = std::strtoll(t.c_str(), nullptr, 10);
  if (errno == ERANGE || v > hi) badArgument(arg, "expected an integer <= " + std::to_string(hi) + ", got " + t);
  return v;
}

/// Splits "a,b,c" at commas (empty items are kept, so that "1,,2" is rejected by the number parser).
inline std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

}  // namespace tools
}  // namespace pkm_accuracy
