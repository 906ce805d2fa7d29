// The Lab Tour on a Cortex-M4 (MPS2+ AN386, in QEMU): the generated mission,
// simulated leaves (robot.hpp), the SysTick clock, a tick every 20 ms, and a
// log of every leaf's status changes on the UART. Exits 0 when the tour
// succeeds.
#include <cstdint>

#include "btgen_bsp.hpp"
#include "lab_tour.hpp"
#include "robot.hpp"

namespace {

constexpr std::uint32_t kTickPeriodMs = 20;
constexpr std::uint32_t kMaxTicks = 2000;

void write_padded(std::uint64_t v, int width) {
  char buf[20];
  int n = 0;
  do {
    buf[n++] = static_cast<char>('0' + static_cast<int>(v % 10u));
    v /= 10u;
  } while (v != 0);
  for (int i = n; i < width; ++i) btgen_bsp::write(" ");
  while (n > 0) btgen_bsp::write(&buf[--n], 1);
}

// The mission's observer: leaves' status changes, timestamped.
struct UartLog {
  void on_status_change(const btgen::NodeInfo& node, btgen::Status from, btgen::Status to) const noexcept {
    if (node.kind != btgen::NodeKind::Action && node.kind != btgen::NodeKind::Condition) return;
    btgen_bsp::write("[");
    write_padded(btgen_bsp::millis(), 6);
    btgen_bsp::write(" ms] ");
    btgen_bsp::write(node.name);
    btgen_bsp::write(" ");
    btgen_bsp::write(btgen::to_string(from));
    btgen_bsp::write(" -> ");
    btgen_bsp::write(btgen::to_string(to));
    btgen_bsp::write("\n");
  }
  void on_error(const btgen::RuntimeError& e) const noexcept {
    btgen_bsp::write("error: ");
    btgen_bsp::write(e.where);
    btgen_bsp::write(": ");
    btgen_bsp::write(e.message);
    btgen_bsp::write("\n");
  }
};

using Mission = lab_tour::LabTour<robot::SimulatedRobot, btgen_bsp::SysTickClock, UartLog>;

robot::SimulatedRobot leaves;
Mission mission(leaves);

}  // namespace

int main() {
  btgen_bsp::init();
  btgen_bsp::write("Lab Tour on a Cortex-M4: ");
  btgen_bsp::write_unsigned(Mission::node_count());
  btgen_bsp::write(" nodes, mission object ");
  btgen_bsp::write_unsigned(sizeof(Mission));
  btgen_bsp::write(" bytes\n");
  btgen::Status result = btgen::Status::RUNNING;
  std::uint32_t ticks = 0;
  std::uint64_t next = btgen_bsp::millis();
  while (ticks < kMaxTicks) {
    while (btgen_bsp::millis() < next) __asm volatile("wfi");
    next += kTickPeriodMs;
    result = mission.tick();
    ++ticks;
    if (btgen::is_completed(result)) break;
  }
  btgen_bsp::write("mission ");
  btgen_bsp::write(btgen::to_string(result));
  btgen_bsp::write(" after ");
  btgen_bsp::write_unsigned(ticks);
  btgen_bsp::write(" ticks; errors ");
  btgen_bsp::write_unsigned(mission.errors());
  btgen_bsp::write("; stack used ");
  btgen_bsp::write_unsigned(btgen_bsp::stack_used());
  btgen_bsp::write(" bytes\n");
  return result == btgen::Status::SUCCESS && mission.errors() == 0 ? 0 : 1;
}
