// A user port type for the tests of `btgen compile --type Pose2D=nav::Pose2D@nav/pose2d.hpp`:
// a trivially copyable struct and its conversion, as BehaviorTree.CPP's convertFromString<T>
// but allocation- and exception-free (found by argument-dependent lookup).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <string_view>

namespace nav {

struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

// How many times convertFromString ran (the tests check literals convert once).
inline int convert_calls = 0;

// "x;y;theta", three numbers separated by ';' (as BehaviorTree.CPP's tutorials write a Pose2D).
inline bool convertFromString(std::string_view text, Pose2D& out) {
  ++convert_calls;
  double parts[3] = {0.0, 0.0, 0.0};
  std::size_t part = 0;
  while (part < 3) {
    const std::size_t end = text.find(';');
    const std::string_view field = text.substr(0, end);
    char buffer[64];
    if (field.empty() || field.size() >= sizeof buffer) return false;
    for (std::size_t i = 0; i < field.size(); ++i) buffer[i] = field[i];
    buffer[field.size()] = '\0';
    char* stop = nullptr;
    parts[part++] = std::strtod(buffer, &stop);
    if (stop != buffer + field.size()) return false;
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  if (part != 3 || text.find(';') != std::string_view::npos) return false;
  out = Pose2D{parts[0], parts[1], parts[2]};
  return true;
}

}  // namespace nav
