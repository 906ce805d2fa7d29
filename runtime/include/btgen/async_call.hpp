// btgen runtime: run one blocking call (a ROS service call, a driver
// request) off the tick thread and poll it from a leaf, the role of
// BehaviorTree.CPP's ThreadedAction, without allocating per call.
//
// An AsyncCall<R> owns one worker thread, started by its constructor and
// joined by its destructor (the only allocations: the thread's own). The
// call is a callable `R fn(const btgen::CancelToken&)`, stored in place
// (at most `Capacity` bytes: a lambda capturing a few pointers), so
// start() allocates nothing; the result lives in the AsyncCall. One call at
// a time:
//
//   struct Leaves {
//     btgen::AsyncCall<bool> plan;                      // one per node instance that can run
//     Status onStart(leaf::Plan& m, const btgen::NodeInfo&) {
//       const auto goal = m.goal();
//       if (!goal) return Status::FAILURE;
//       const double g = *goal;
//       plan.start([this, g](const btgen::CancelToken& t) { return planner.compute(g, t); });
//       return Status::RUNNING;
//     }
//     Status onRunning(leaf::Plan&, const btgen::NodeInfo&) {
//       if (plan.poll() == btgen::CallState::kRunning) return Status::RUNNING;
//       return plan.succeeded() && *plan.result() ? Status::SUCCESS : Status::FAILURE;
//     }
//     void onHalted(leaf::Plan&, const btgen::NodeInfo&) { plan.cancel(); }
//   };
//
// cancel() (what onHalted calls) asks the call to stop through its
// CancelToken and waits until it has returned, as ThreadedAction::halt()
// waits for its thread: after it, nothing of the call runs and a new one
// can start. A call that never looks at its token delays the halt until it
// returns by itself. The callable must not throw (with exceptions enabled a
// throw ends the call in kFailed).
//
// Thread safety: start(), poll(), result(), cancel() and the destructor
// are for the one thread that ticks the tree; the callable runs on the
// worker and only touches what it captured and its token.
#pragma once

#ifdef BTGEN_BARE_METAL
#error \
    "btgen/async_call.hpp needs an operating system (threads): it is not built for bare-metal targets (mcu/README.md)"
#endif

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <new>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

namespace btgen {

// What the call sees of a cancellation request; poll it in long calls.
class CancelToken {
 public:
  [[nodiscard]] bool cancelled() const noexcept { return flag_->load(std::memory_order_acquire); }
  explicit CancelToken(const std::atomic<bool>& flag) noexcept : flag_(&flag) {}

 private:
  const std::atomic<bool>* flag_;
};

enum class CallState : unsigned char {
  kIdle,     // no call started since construction or the last cancel()
  kRunning,  // the worker is running the call
  kDone,     // the call returned; result() holds what it returned
  kFailed,   // the call threw (only with exceptions enabled); no result
};

template <class R, std::size_t Capacity = 64>
class AsyncCall {
  static_assert(!std::is_reference_v<R> && !std::is_void_v<R>, "AsyncCall<R>: R is a value type");

 public:
  AsyncCall() : worker_([this] { work(); }) {}
  ~AsyncCall() {
    cancel();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    worker_.join();
  }
  AsyncCall(const AsyncCall&) = delete;
  AsyncCall& operator=(const AsyncCall&) = delete;

  // Starts `fn(token)` on the worker: false (and nothing started) while a
  // call is running. A previous result is discarded.
  template <class F>
  bool start(F&& fn) noexcept(std::is_nothrow_constructible_v<std::decay_t<F>, F&&>) {
    using Fn = std::decay_t<F>;
    static_assert(sizeof(Fn) <= Capacity,
                  "AsyncCall: the callable is larger than Capacity bytes; capture less "
                  "(a pointer to your state) or raise Capacity");
    static_assert(alignof(Fn) <= alignof(std::max_align_t), "AsyncCall: over-aligned callable");
    static_assert(std::is_invocable_r_v<R, Fn&, const CancelToken&>,
                  "AsyncCall<R>: the callable is R fn(const btgen::CancelToken&)");
    std::lock_guard<std::mutex> lock(mutex_);
    if (state_.load(std::memory_order_relaxed) == CallState::kRunning) return false;
    result_.reset();
    ::new (static_cast<void*>(storage_)) Fn(std::forward<F>(fn));
    invoke_ = &invoke_as<Fn>;
    cancel_.store(false, std::memory_order_relaxed);
    state_.store(CallState::kRunning, std::memory_order_release);
    pending_ = true;
    wake_.notify_one();
    return true;
  }

  // The call's state, without waiting.
  [[nodiscard]] CallState poll() const noexcept { return state_.load(std::memory_order_acquire); }
  [[nodiscard]] bool running() const noexcept { return poll() == CallState::kRunning; }
  [[nodiscard]] bool succeeded() const noexcept { return poll() == CallState::kDone; }

  // What the call returned: empty unless poll() is kDone.
  [[nodiscard]] std::optional<R>& result() noexcept {
    static_cast<void>(poll());  // acquire: the worker's writes to result_ are visible
    return result_;
  }

  // Asks a running call to stop (its token turns true) and waits until it
  // has returned; then, running or not, forgets the call and its result
  // (kIdle). What onHalted calls.
  void cancel() noexcept {
    std::unique_lock<std::mutex> lock(mutex_);
    if (state_.load(std::memory_order_relaxed) == CallState::kRunning) {
      cancel_.store(true, std::memory_order_release);
      finished_.wait(lock, [this] { return state_.load(std::memory_order_relaxed) != CallState::kRunning; });
    }
    result_.reset();
    state_.store(CallState::kIdle, std::memory_order_release);
  }

  // Asks a running call to stop without waiting; poll() tells when it has.
  void request_cancel() noexcept { cancel_.store(true, std::memory_order_release); }

 private:
  using Invoke = void (*)(void* fn, std::optional<R>& out, const CancelToken& token);

  template <class Fn>
  static void invoke_as(void* fn, std::optional<R>& out, const CancelToken& token) {
    Fn& f = *static_cast<Fn*>(fn);
    struct Destroy {
      Fn& f;
      ~Destroy() { f.~Fn(); }
    } destroy{f};
    out.emplace(f(token));
  }

  void work() noexcept {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || pending_; });
      if (stop_) return;
      pending_ = false;
      const Invoke invoke = invoke_;
      lock.unlock();
      CallState end = CallState::kDone;
      const CancelToken token(cancel_);
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
      try {
        invoke(storage_, result_, token);
      } catch (...) {
        result_.reset();
        end = CallState::kFailed;
      }
#else
      invoke(storage_, result_, token);
#endif
      lock.lock();
      state_.store(end, std::memory_order_release);
      finished_.notify_all();
    }
  }

  alignas(std::max_align_t) unsigned char storage_[Capacity]{};
  Invoke invoke_ = nullptr;
  std::optional<R> result_;
  std::atomic<CallState> state_{CallState::kIdle};
  std::atomic<bool> cancel_{false};
  bool pending_ = false;
  bool stop_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable finished_;
  std::thread worker_;  // last: starts after everything it uses is constructed
};

}  // namespace btgen
