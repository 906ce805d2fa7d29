// Unit tests of the parts of behaviorController that need no ROS: the
// service worker (order, halts, stop) and the phrase table (languages,
// phrases, answers). scripts/test_ros1.sh builds and runs them.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "phrases.hpp"
#include "service_worker.hpp"

namespace bbc = btgen_behavior_controller;
using Poll = bbc::ServiceWorker::Poll;

namespace {

// A call that blocks until released.
class Gate {
 public:
  void wait() {
    std::unique_lock<std::mutex> lock(m_);
    entered_ = true;
    cv_.notify_all();
    cv_.wait(lock, [this] { return open_; });
  }
  void wait_entered() {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [this] { return entered_; });
  }
  void open() {
    std::lock_guard<std::mutex> lock(m_);
    open_ = true;
    cv_.notify_all();
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  bool entered_ = false, open_ = false;
};

Poll wait_result(bbc::ServiceWorker& w, std::size_t index) {
  for (int i = 0; i < 2000; ++i) {
    const Poll p = w.poll(index);
    if (p != Poll::kRunning) return p;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return Poll::kRunning;
}

}  // namespace

TEST(ServiceWorker, ResultsArriveOnceAndCallsRunInOrder) {
  bbc::ServiceWorker w(3);
  std::mutex m;
  std::vector<int> order;
  Gate gate;
  w.start(0, [&] {
    gate.wait();
    std::lock_guard<std::mutex> l(m);
    order.push_back(0);
    return true;
  });
  w.start(1, [&] {
    std::lock_guard<std::mutex> l(m);
    order.push_back(1);
    return false;
  });
  gate.wait_entered();
  EXPECT_EQ(w.poll(0), Poll::kRunning);  // still in the call
  EXPECT_EQ(w.poll(1), Poll::kRunning);  // queued behind it
  gate.open();
  EXPECT_EQ(wait_result(w, 0), Poll::kSucceeded);
  EXPECT_EQ(wait_result(w, 1), Poll::kFailed);
  EXPECT_EQ(w.poll(0), Poll::kRunning);  // consumed: no second result
  EXPECT_EQ(order, (std::vector<int>{0, 1}));
}

TEST(ServiceWorker, AbandonedWhileQueuedIsNeverCalled) {
  bbc::ServiceWorker w(2);
  Gate gate;
  std::atomic<bool> called{false};
  w.start(0, [&] {
    gate.wait();
    return true;
  });
  gate.wait_entered();
  w.start(1, [&] {
    called = true;
    return true;
  });
  w.abandon(1);  // the node was halted before its call began
  gate.open();
  EXPECT_EQ(wait_result(w, 0), Poll::kSucceeded);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(called);
  EXPECT_EQ(w.poll(1), Poll::kRunning);  // nothing to report
}

TEST(ServiceWorker, ResultOfAnAbandonedCallIsDroppedAndARestartGetsItsOwn) {
  bbc::ServiceWorker w(1);
  Gate gate;
  w.start(0, [&] {
    gate.wait();
    return false;  // the old call fails...
  });
  gate.wait_entered();
  w.abandon(0);                     // ...but the node was halted meanwhile
  w.start(0, [] { return true; });  // and started again
  gate.open();
  EXPECT_EQ(wait_result(w, 0), Poll::kSucceeded);  // the new call's result, not the old one's
}

TEST(ServiceWorker, StopWaitsForTheCallInProgressAndMakesNoOther) {
  Gate gate;
  std::atomic<int> calls{0};
  {
    bbc::ServiceWorker w(2);
    w.start(0, [&] {
      gate.wait();
      ++calls;
      return true;
    });
    gate.wait_entered();
    w.start(1, [&] {
      ++calls;
      return true;
    });
    std::thread opener([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      gate.open();
    });
    w.stop();  // returns once the call in progress did
    opener.join();
    EXPECT_EQ(calls.load(), 1);
  }  // the destructor stops again: harmless
  EXPECT_EQ(calls.load(), 1);
}

TEST(Phrases, LanguagesByTheProductionNodesNamesInAnyCase) {
  EXPECT_EQ(bbc::parse_language("English"), bbc::Language::kEnglish);
  EXPECT_EQ(bbc::parse_language("isiZulu"), bbc::Language::kIsiZulu);
  EXPECT_EQ(bbc::parse_language("IsiZulu"), bbc::Language::kIsiZulu);
  EXPECT_EQ(bbc::parse_language("KINYARWANDA"), bbc::Language::kKinyarwanda);
  EXPECT_FALSE(bbc::parse_language("Klingon"));
  EXPECT_FALSE(bbc::parse_language(""));
  EXPECT_STREQ(bbc::language_name(bbc::Language::kIsiZulu), "IsiZulu");
}

TEST(Phrases, EveryIdOfTheProductionMissionInEveryLanguage) {
  EXPECT_EQ(bbc::utility_phrase_ids(), "1, 2, 3, 4, 5, 7");
  for (const char* id : {"1", "2", "3", "4", "5", "7"}) {
    for (bbc::Language l : {bbc::Language::kEnglish, bbc::Language::kIsiZulu, bbc::Language::kKinyarwanda}) {
      const char* text = bbc::utility_phrase(id, l);
      ASSERT_NE(text, nullptr) << id;
      EXPECT_GT(std::strlen(text), 0u) << id;
    }
  }
  EXPECT_EQ(bbc::utility_phrase("6", bbc::Language::kEnglish), nullptr);
  EXPECT_EQ(bbc::utility_phrase("SayText", bbc::Language::kEnglish), nullptr);
  EXPECT_STREQ(bbc::utility_phrase("2", bbc::Language::kEnglish), "Please follow me.");
}

TEST(Phrases, AnswersAreWholeWordsAffirmativeFirst) {
  using bbc::Answer;
  const auto en = bbc::Language::kEnglish;
  EXPECT_EQ(bbc::classify_answer("Yes, I would love to", en), Answer::kYes);
  EXPECT_EQ(bbc::classify_answer("no thanks", en), Answer::kNo);
  EXPECT_EQ(bbc::classify_answer("NO.", en), Answer::kNo);
  EXPECT_EQ(bbc::classify_answer("I don't know", en), Answer::kNone);  // "know" is not "no"
  EXPECT_EQ(bbc::classify_answer("nobody", en), Answer::kNone);
  EXPECT_EQ(bbc::classify_answer("goodness", en), Answer::kNone);  // nor is it "good" or "go"
  EXPECT_EQ(bbc::classify_answer("", en), Answer::kNone);
  EXPECT_EQ(bbc::classify_answer("no, yes", en), Answer::kYes);  // as the production node: yes first
  EXPECT_EQ(bbc::classify_answer("Yego", bbc::Language::kKinyarwanda), Answer::kYes);
  EXPECT_EQ(bbc::classify_answer("oya", bbc::Language::kKinyarwanda), Answer::kNo);
  EXPECT_EQ(bbc::classify_answer("yes", bbc::Language::kKinyarwanda), Answer::kNone);  // another language's word
  EXPECT_EQ(bbc::classify_answer("Yebo", bbc::Language::kIsiZulu), Answer::kYes);
  EXPECT_EQ(bbc::classify_answer("cha", bbc::Language::kIsiZulu), Answer::kNo);
}
