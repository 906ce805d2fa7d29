// The scenario runner's main for one generated mission. Compile with
//   -DBTGEN_MISSION_HEADER='"lab_tour.hpp"' -DBTGEN_MISSION_TEMPLATE=lab_tour::LabTour
// (btgen's cppengine and btgen_add_mission(... SCENARIO_RUNNER ...) do).
#ifndef BTGEN_MISSION_HEADER
#error "define BTGEN_MISSION_HEADER as the generated header, e.g. -DBTGEN_MISSION_HEADER='\"lab_tour.hpp\"'"
#endif
#ifndef BTGEN_MISSION_TEMPLATE
#error "define BTGEN_MISSION_TEMPLATE as the mission class template, e.g. -DBTGEN_MISSION_TEMPLATE=lab_tour::LabTour"
#endif

#include BTGEN_MISSION_HEADER

#include "btgen/harness/driver.hpp"

int main(int argc, char** argv) { return btgen::run_scenario_main<BTGEN_MISSION_TEMPLATE>(argc, argv); }
