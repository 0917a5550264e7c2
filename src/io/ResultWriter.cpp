// The reports' entry points and their value formats; the report's keys are in ReportDocument.cpp, the tree that
// writes them as JSON and YAML in DocumentNode.cpp, the human summary in ResultSummary.cpp.
#include "pkm_accuracy/io/ResultWriter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <utility>

#include "ReportDocument.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace io {

double RunInfo::timeOf(double u) const {
  const double t = time_start + u * (time_end - time_start);
  return std::min(std::max(t, time_start), time_end);
}

std::vector<std::pair<double, double>> undecidedTimes(const verify::VerifierResult& result, const RunInfo& info) {
  std::vector<std::pair<double, double>> t;
  for (const auto& b : result.undecided_boxes) {
    if (b.box.size() < 1 || b.box[0].isEmpty()) continue;
    t.emplace_back(info.timeOf(b.box[0].lower()), info.timeOf(b.box[0].upper()));
  }
  std::sort(t.begin(), t.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& iv : t) {
    if (!merged.empty() && iv.first <= merged.back().second) {
      merged.back().second = std::max(merged.back().second, iv.second);
    } else {
      merged.push_back(iv);
    }
  }
  return merged;
}

std::string modeName(verify::Mode mode) { return mode == verify::Mode::MaxError ? "max_error" : "verify"; }

std::string bisectionName(verify::Bisection bisection) {
  switch (bisection) {
    case verify::Bisection::Smear:
      return "smear";
    case verify::Bisection::LargestScaledWidth:
      return "width";
    case verify::Bisection::RoundRobin:
      return "round-robin";
  }
  return "smear";
}

std::string geometrySplittingName(verify::GeometrySplitting splitting) {
  switch (splitting) {
    case verify::GeometrySplitting::Auto:
      return "auto";
    case verify::GeometrySplitting::Never:
      return "never";
    case verify::GeometrySplitting::Always:
      return "always";
  }
  return "auto";
}

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string toJson(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info) {
  std::ostringstream os;
  reportDocument(result, options, info).writeJson(os, 0);
  os << '\n';
  return os.str();
}

std::string toYaml(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info) {
  std::ostringstream os;
  os << "# " << info.tool << " result (units: m and rad; see components / units)\n";
  reportDocument(result, options, info).writeYamlMembers(os, 0);
  return os.str();
}

void writeTextFile(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text << std::flush;
    if (!std::cout) throw InvalidArgument("standard output: write failed");
    return;
  }
  std::ofstream f(path, std::ios::out | std::ios::trunc);
  if (!f) throw InvalidArgument(path + ": cannot open for writing");
  f << text;
  f.close();
  if (!f) throw InvalidArgument(path + ": write failed");
}

}  // namespace io
}  // namespace pkm_accuracy
