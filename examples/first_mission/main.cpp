// The first page's example: the leaves of deliver.xml and the loop that ticks it.
#include <cstdio>

#include "deliver.hpp"  // btgen compile deliver.xml -o . (or btgen_add_mission in CMake)

using btgen::NodeInfo;
using btgen::Status;
namespace leaf = deliver::leaf;

struct Leaves {  // one overload per model of <TreeNodesModel>; no base class, no registration
  int battery = 80;
  Status check(leaf::BatteryAbove& n, const NodeInfo&) {
    return n.percent() && battery > *n.percent() ? Status::SUCCESS : Status::FAILURE;
  }
  Status onStart(leaf::NavigateTo&, const NodeInfo&) { return Status::RUNNING; }  // driving...
  Status onRunning(leaf::NavigateTo& n, const NodeInfo&) {
    return n.set_reached(*n.goal()) ? Status::SUCCESS : Status::FAILURE;  // ...arrived
  }
  void onHalted(leaf::NavigateTo&, const NodeInfo&) {}
  Status tick(leaf::Say& n, const NodeInfo&) {
    std::printf("robot says: %.*s\n", int(n.text()->size()), n.text()->data());
    return Status::SUCCESS;
  }
};

int main() {
  Leaves leaves;
  deliver::Deliver<Leaves> mission(leaves);  // static, allocation-free: no heap, no XML at run time
  Status s = Status::RUNNING;
  for (int tick = 1; s == Status::RUNNING; ++tick) {
    s = mission.tick();
    std::printf("tick %d: %s\n", tick, s == Status::SUCCESS ? "SUCCESS" : s == Status::FAILURE ? "FAILURE" : "RUNNING");
  }
  return s == Status::SUCCESS ? 0 : 1;
}
