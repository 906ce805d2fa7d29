// Leaves for the C++ tests: generic hooks (one template serves every model
// of every mission), so the same types drive any generated mission.
#pragma once

#include <cstddef>
#include <cstdint>

#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen_test {

// Pseudo-random results (xorshift), reproducible from a seed: Actions answer
// SUCCESS, FAILURE or RUNNING, Conditions SUCCESS (mostly) or FAILURE.
class RandomLeaves {
 public:
  explicit RandomLeaves(std::uint64_t seed) noexcept : state_(seed | 1u) {}

  template <class Model>
  btgen::Status onStart(Model&, const btgen::NodeInfo&) noexcept {
    ++starts;
    return action();
  }
  template <class Model>
  btgen::Status onRunning(Model&, const btgen::NodeInfo&) noexcept {
    ++runs;
    return action();
  }
  template <class Model>
  void onHalted(Model&, const btgen::NodeInfo&) noexcept {
    ++halts;
  }
  template <class Model>
  btgen::Status check(Model&, const btgen::NodeInfo&) noexcept {
    ++checks;
    return next() % 8 == 0 ? btgen::Status::FAILURE : btgen::Status::SUCCESS;
  }

  std::uint64_t starts = 0, runs = 0, halts = 0, checks = 0;

 private:
  std::uint64_t next() noexcept {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 7;
    state_ ^= state_ << 17;
    return state_ >> 11;
  }
  btgen::Status action() noexcept {
    switch (next() % 4) {
      case 0: return btgen::Status::FAILURE;
      case 1: return btgen::Status::SUCCESS;
      default: return btgen::Status::RUNNING;
    }
  }
  std::uint64_t state_;
};

// Every leaf answers at once: Actions and Conditions SUCCESS.
struct InstantLeaves {
  template <class Model>
  btgen::Status onStart(Model&, const btgen::NodeInfo&) noexcept { return btgen::Status::SUCCESS; }
  template <class Model>
  btgen::Status onRunning(Model&, const btgen::NodeInfo&) noexcept { return btgen::Status::SUCCESS; }
  template <class Model>
  void onHalted(Model&, const btgen::NodeInfo&) noexcept {}
  template <class Model>
  btgen::Status check(Model&, const btgen::NodeInfo&) noexcept { return btgen::Status::SUCCESS; }
};

// Records status changes in a fixed buffer (no allocation).
struct Recorder {
  struct Event {
    std::uint16_t uid;
    btgen::Status from;
    btgen::Status to;
  };
  static constexpr std::size_t kCapacity = 4096;
  Event events[kCapacity]{};
  std::size_t count = 0;
  std::size_t dropped = 0;
};

struct RecordingObserver {
  Recorder* recorder;
  void on_status_change(const btgen::NodeInfo& node, btgen::Status from, btgen::Status to) noexcept {
    if (recorder->count < Recorder::kCapacity) {
      recorder->events[recorder->count++] = Recorder::Event{node.uid, from, to};
    } else {
      ++recorder->dropped;
    }
  }
};

}  // namespace btgen_test
