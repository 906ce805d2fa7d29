// The robot's own code, shared by both programs: what a ROS node handle or a driver would be.
// The first drive fails (a blocked path), the next one takes two ticks.
#pragma once

#include <cstdio>
#include <string>

struct Robot {
  int battery_percent = 57;
  int drives = 0;
  int ticks_to_go = 0;

  bool start_drive(const std::string& goal) {
    std::printf("robot: driving to %s\n", goal.c_str());
    if (++drives == 1) return false;
    ticks_to_go = 2;
    return true;
  }
  bool arrived() { return --ticks_to_go <= 0; }
  void stop() { std::printf("robot: stopped\n"); }
  void say(const std::string& text) { std::printf("robot: says \"%s\"\n", text.c_str()); }
};
