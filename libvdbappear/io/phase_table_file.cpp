#include "libvdbappear/io/phase_table_file.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace vdbappear {
namespace {

std::vector<double> parseJson(const std::string& text, const std::string& path) {
  try {
    const nlohmann::json json = nlohmann::json::parse(text);
    const nlohmann::json& values = json.is_object() ? json.at("table") : json;
    return values.get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw MediumError(fmt::format("{}: not a phase table (expected a JSON array or an object with a \"table\" array: {})", path, e.what()));
  }
}

std::vector<double> parseText(std::string text, const std::string& path) {
  std::istringstream lines(text);
  std::vector<double> values;
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    line = line.substr(0, line.find('#'));
    for (char& c : line) if (c == ',') c = ' ';
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      std::size_t used = 0;
      double value = 0;
      try {
        value = std::stod(word, &used);
      } catch (const std::exception&) {
      }
      if (used != word.size() || word.empty())
        throw MediumError(fmt::format("{}: line {}: '{}' is not a number", path, number, word));
      values.push_back(value);
    }
  }
  return values;
}

}  // namespace

std::vector<double> readPhaseTableFile(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw MediumError(fmt::format("{}: cannot open the phase table", path));
  std::stringstream buffer;
  buffer << file.rdbuf();
  const std::string text = buffer.str();
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const bool json = first != std::string::npos && (text[first] == '{' || text[first] == '[');
  const std::vector<double> values = json ? parseJson(text, path) : parseText(text, path);
  if (values.size() < 2) throw MediumError(fmt::format("{}: a phase table needs at least 2 bins, found {}", path, values.size()));
  double sum = 0;
  for (std::size_t b = 0; b < values.size(); ++b) {
    if (!std::isfinite(values[b]) || values[b] < 0)
      throw MediumError(fmt::format("{}: bin {}: value {} is negative or not finite", path, b, values[b]));
    sum += values[b];
  }
  if (!(sum > 0)) throw MediumError(fmt::format("{}: the phase table is zero everywhere", path));
  return values;
}

}  // namespace vdbappear
