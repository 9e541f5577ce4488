// Numbers in error messages as Python prints them (repr of a float: the shortest text that reads back the same).
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace nubot_control {

inline std::string format_float(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), value).ptr;
  std::string text(buffer, end);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";  // 3 -> 3.0, as Python writes a float
  return text;
}

}  // namespace nubot_control
