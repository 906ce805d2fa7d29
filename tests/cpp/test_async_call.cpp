// btgen::AsyncCall (btgen/async_call.hpp): one blocking call at a time on a
// fixed worker thread, polled from the tick thread, cancelled cleanly, with
// no allocation per call. Also built under ThreadSanitizer
// (btgen_async_call_tsan) where the toolchain supports it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "btgen/async_call.hpp"
#ifndef BTGEN_TEST_NO_ALLOC_COUNTER
#include "btgen/testing/alloc_counter.hpp"
#endif

namespace {

TEST(AsyncCall, StartPollResult) {
  btgen::AsyncCall<int> call;
  EXPECT_EQ(call.poll(), btgen::CallState::kIdle);
  std::atomic<bool> go{false};
  ASSERT_TRUE(call.start([&go](const btgen::CancelToken&) {
    while (!go.load()) std::this_thread::yield();
    return 42;
  }));
  EXPECT_TRUE(call.running());
  EXPECT_FALSE(call.start([](const btgen::CancelToken&) { return 0; }));  // busy
  EXPECT_FALSE(call.result().has_value());
  go = true;
  while (call.running()) std::this_thread::yield();
  EXPECT_EQ(call.poll(), btgen::CallState::kDone);
  ASSERT_TRUE(call.result().has_value());
  EXPECT_EQ(*call.result(), 42);
  ASSERT_TRUE(call.start([](const btgen::CancelToken&) { return 7; }));  // a new call discards the old result
  while (call.running()) std::this_thread::yield();
  EXPECT_EQ(*call.result(), 7);
  call.cancel();  // not running: forgets the result
  EXPECT_EQ(call.poll(), btgen::CallState::kIdle);
  EXPECT_FALSE(call.result().has_value());
}

TEST(AsyncCall, CancelStopsABlockedCall) {
  btgen::AsyncCall<int> call;
  std::atomic<bool> inside{false};
  ASSERT_TRUE(call.start([&inside](const btgen::CancelToken& t) {
    inside = true;
    while (!t.cancelled()) std::this_thread::sleep_for(std::chrono::microseconds(50));
    return -1;
  }));
  while (!inside.load()) std::this_thread::yield();
  call.cancel();
  EXPECT_EQ(call.poll(), btgen::CallState::kIdle);
  EXPECT_FALSE(call.result().has_value());
}

TEST(AsyncCall, DestructorCancelsARunningCall) {
  std::atomic<bool> stopped{false};
  {
    btgen::AsyncCall<int> call;
    ASSERT_TRUE(call.start([&stopped](const btgen::CancelToken& t) {
      while (!t.cancelled()) std::this_thread::yield();
      stopped = true;
      return 0;
    }));
  }
  EXPECT_TRUE(stopped.load());
}

#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
TEST(AsyncCall, AThrowingCallEndsFailed) {
  btgen::AsyncCall<int> call;
  ASSERT_TRUE(call.start([](const btgen::CancelToken&) -> int { throw 1; }));
  while (call.running()) std::this_thread::yield();
  EXPECT_EQ(call.poll(), btgen::CallState::kFailed);
  EXPECT_FALSE(call.result().has_value());
}
#endif

#ifndef BTGEN_TEST_NO_ALLOC_COUNTER
TEST(AsyncCall, NoAllocationPerCall) {
  btgen::AsyncCall<double> call;  // the worker thread is created here, outside the scope
  btgen_test::AllocationScope scope;
  double total = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double x = i;
    ASSERT_TRUE(call.start([x](const btgen::CancelToken&) { return x + 0.5; }));
    while (call.running()) std::this_thread::yield();
    total += *call.result();
    if (i % 10 == 0) call.cancel();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_DOUBLE_EQ(total, 200 * 199 / 2.0 + 100.0);
}
#endif

}  // namespace
