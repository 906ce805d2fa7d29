// Built with -fno-exceptions -fno-rtti: the engine and generated code need neither.
// Ticks the control_flow mission and exits 0 when it ran and ended IDLE after halt().
#include "btgen/clock.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"

int main() {
  btgen_test::RandomLeaves leaves(77);
  static control_flow::ControlFlow<btgen_test::RandomLeaves, btgen::ManualClock> mission(leaves);
  for (int i = 0; i < 10000; ++i) {
    mission.clock().advance(3);
    (void)mission.tick();
  }
  mission.halt();
  for (std::size_t i = 0; i < mission.node_count(); ++i) {
    if (mission.status(i) != btgen::Status::IDLE) return 1;
  }
  return leaves.starts > 0 ? 0 : 1;
}
