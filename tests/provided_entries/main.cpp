// Sets the entries the application provides (btgen --entry) with the generated setters,
// then ticks: prints the root's status and what Wait read from its port.
#include <cstdio>
#include <cstdlib>

#include "nav_entries.hpp"

namespace leaf = nav_entries::leaf;

struct Leaves {
  long timeout = -1;
  btgen::Status tick(leaf::Wait& m, const btgen::NodeInfo&) {
    timeout = m.timeout().value_or(-2);
    return btgen::Status::SUCCESS;
  }
};

int main(int argc, char** argv) {
  Leaves leaves;
  nav_entries::NavEntries<Leaves> mission(leaves);
  if (argc > 1) {  // set them all; without arguments, none (the scripts then fail)
    mission.provide_server_timeout(std::atoi(argv[1]));
    if (!mission.provide_node("bt_navigator")) return 3;
    mission.provide_wait_for_service_timeout(1000);
    mission.provide_Sub_bt_loop_duration(10);
  }
  const btgen::Status s = mission.tick();
  std::printf("%s %ld\n",
              s == btgen::Status::SUCCESS   ? "SUCCESS"
              : s == btgen::Status::FAILURE ? "FAILURE"
                                            : "OTHER",
              leaves.timeout);
  return 0;
}
