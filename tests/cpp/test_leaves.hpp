// Leaves for the C++ tests: generic hooks (one template serves every model
// of every mission), so the same types drive any generated mission.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <utility>

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

// RandomLeaves that also use the ports of the shipped missions' models: every
// hook reads the model's input ports (location_id, exhibits, response,
// message, destination) and writes its output ports, whatever the model, with
// pseudo-random values. Detection is by member name, so one type serves any
// mission with such ports.
namespace port_detail {
#define BTGEN_TEST_HAS(name, expr)  \
  template <class M, class = void>  \
  struct name : std::false_type {}; \
  template <class M>                \
  struct name<M, std::void_t<decltype(expr)>> : std::true_type {};
BTGEN_TEST_HAS(has_location_id, std::declval<M&>().location_id())
BTGEN_TEST_HAS(has_set_location_id, std::declval<M&>().set_location_id(0))
BTGEN_TEST_HAS(has_exhibits, std::declval<M&>().exhibits())
BTGEN_TEST_HAS(has_set_exhibits, std::declval<M&>().set_exhibits(std::string_view()))
BTGEN_TEST_HAS(has_response, std::declval<M&>().response())
BTGEN_TEST_HAS(has_set_response, std::declval<M&>().set_response(std::string_view()))
BTGEN_TEST_HAS(has_destination, std::declval<M&>().destination())
BTGEN_TEST_HAS(has_set_destination, std::declval<M&>().set_destination(std::string_view()))
BTGEN_TEST_HAS(has_message, std::declval<M&>().message())
#undef BTGEN_TEST_HAS
}  // namespace port_detail

class PortLeaves : public RandomLeaves {
 public:
  explicit PortLeaves(std::uint64_t seed) noexcept : RandomLeaves(seed), state_(seed * 7 + 3) {}

  template <class Model>
  btgen::Status onStart(Model& m, const btgen::NodeInfo& n) noexcept {
    use(m);
    return RandomLeaves::onStart(m, n);
  }
  template <class Model>
  btgen::Status onRunning(Model& m, const btgen::NodeInfo& n) noexcept {
    use(m);
    return RandomLeaves::onRunning(m, n);
  }
  template <class Model>
  btgen::Status check(Model& m, const btgen::NodeInfo& n) noexcept {
    use(m);
    return RandomLeaves::check(m, n);
  }

  std::uint64_t reads = 0, values = 0, writes = 0;

 private:
  template <class Input>
  void seen(const Input& in) noexcept {
    ++reads;
    if (in.has_value()) ++values;
  }
  template <class Model>
  void use(Model& m) noexcept {
    using namespace port_detail;
    static constexpr std::string_view kLists[] = {"101;102;103", "7", "", "1;2;3;4;5;6;7;8;9;10"};
    static constexpr std::string_view kAnswers[] = {"yes", "no", "maybe", "the robotics lab"};
    state_ = state_ * 6364136223846793005u + 1442695040888963407u;
    const std::size_t r = static_cast<std::size_t>(state_ >> 33);
    if constexpr (has_location_id<Model>::value) seen(m.location_id());
    if constexpr (has_exhibits<Model>::value) seen(m.exhibits());
    if constexpr (has_response<Model>::value) seen(m.response());
    if constexpr (has_destination<Model>::value) seen(m.destination());
    if constexpr (has_message<Model>::value) seen(m.message());
    if constexpr (has_set_location_id<Model>::value)
      writes += m.set_location_id(static_cast<std::int32_t>(r % 200)) ? 1 : 0;
    if constexpr (has_set_exhibits<Model>::value) writes += m.set_exhibits(kLists[r % 4]) ? 1 : 0;
    if constexpr (has_set_response<Model>::value) writes += m.set_response(kAnswers[r % 2]) ? 1 : 0;
    if constexpr (has_set_destination<Model>::value) writes += m.set_destination(kAnswers[r % 4]) ? 1 : 0;
  }

  std::uint64_t state_;
};

// Every leaf answers at once: Actions and Conditions SUCCESS.
struct InstantLeaves {
  template <class Model>
  btgen::Status onStart(Model&, const btgen::NodeInfo&) noexcept {
    return btgen::Status::SUCCESS;
  }
  template <class Model>
  btgen::Status onRunning(Model&, const btgen::NodeInfo&) noexcept {
    return btgen::Status::SUCCESS;
  }
  template <class Model>
  void onHalted(Model&, const btgen::NodeInfo&) noexcept {}
  template <class Model>
  btgen::Status check(Model&, const btgen::NodeInfo&) noexcept {
    return btgen::Status::SUCCESS;
  }
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
