// btgen runtime: Groot2 log files (.btlog), as BehaviorTree.CPP's FileLogger2 writes them.
//
//     btgen::btlog::FileLogger log(mission, "run.btlog");  // mission: observer btgen::MonitorObserver<...>
//
// The file (4.6.2, src/loggers/bt_file_logger_v2.cpp) is
//
//     "BTCPP4-FileLogger2"   18 bytes
//     protocol               1 byte, 1
//     XML length             int32, little-endian
//     tree XML               WriteTreeToXML(tree, true, true): the mission's Groot2::kTreeXml
//     first timestamp        int64 microseconds since the epoch, little-endian
//     transitions            9 bytes each: 6 bytes of microseconds since the first timestamp,
//                            uint16 UID, uint8 new status (IDLE included), all little-endian
//
// Groot2 opens it in its log replay. On the tick path a status change is one
// record pushed into a fixed ring (no allocation, no lock); a writer thread
// drains the ring to the file every 10 ms and at the end. When the ring is
// full (the writer fell behind by `capacity` records) records are dropped and
// counted (dropped()), never waited for.
#pragma once

#ifdef BTGEN_BARE_METAL
#error \
    "btgen/btlog.hpp needs an operating system (a writer thread and files): it is not built for bare-metal targets (mcu/README.md)"
#endif

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>

#include "btgen/monitor.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen {

// One status change: microseconds (from an origin the user chooses), UID, new status.
struct Transition {
  std::uint64_t usec;
  std::uint16_t uid;
  std::uint8_t status;
};

// A single-producer single-consumer ring of transitions: the tick thread
// pushes, one other thread pops. Fixed capacity (allocated once).
class TransitionRing {
 public:
  explicit TransitionRing(std::size_t capacity) : cap_(capacity < 2 ? 2 : capacity), buf_(new Transition[cap_]) {}

  // Tick thread. False (and counted) when full.
  bool push(const Transition& t) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == cap_ ? 0 : head + 1;
    if (next == tail_.load(std::memory_order_acquire)) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    buf_[head] = t;
    head_.store(next, std::memory_order_release);
    return true;
  }

  // Consumer thread: calls f(const Transition&) for every record pushed so far.
  template <class F>
  std::size_t drain(F&& f) {
    std::size_t tail = tail_.load(std::memory_order_relaxed);
    const std::size_t head = head_.load(std::memory_order_acquire);
    std::size_t n = 0;
    while (tail != head) {
      f(buf_[tail]);
      tail = tail + 1 == cap_ ? 0 : tail + 1;
      ++n;
      tail_.store(tail, std::memory_order_release);
    }
    return n;
  }

  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::size_t capacity() const noexcept { return cap_ - 1; }

 private:
  std::size_t cap_;
  std::unique_ptr<Transition[]> buf_;
  std::atomic<std::size_t> head_{0};
  std::atomic<std::size_t> tail_{0};
  std::atomic<std::uint64_t> dropped_{0};
};

// The 9 bytes of a record as FileLogger2 and Groot2Publisher's GET_TRANSITIONS write them.
inline void pack_transition(const Transition& t, char out[9]) noexcept {
  for (int i = 0; i < 6; ++i) out[i] = static_cast<char>((t.usec >> (8 * i)) & 0xFF);
  out[6] = static_cast<char>(t.uid & 0xFF);
  out[7] = static_cast<char>(t.uid >> 8);
  out[8] = static_cast<char>(t.status);
}

[[nodiscard]] inline std::int64_t wall_clock_usec() noexcept {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

namespace btlog {

// Writes the .btlog of a mission whose observer is a btgen::MonitorObserver;
// destroy it before the mission (it detaches itself; the file is complete then).
// Opening the file fails with std::runtime_error (wrong extension, as
// FileLogger2 requires `.btlog`, or the file cannot be created).
class FileLogger final : public StatusSink {
 public:
  static constexpr std::size_t kDefaultCapacity = 1 << 16;

  template <class Mission>
  FileLogger(Mission& mission, const std::string& path, std::size_t capacity = kDefaultCapacity)
      : FileLogger(path, Mission::Groot2::kTreeXml, capacity) {
    if (!mission.observer().attach(this)) {
      close_file();
      throw std::runtime_error("btlog: the mission's observer has no room for another monitor");
    }
    detach_ = [](void* m, StatusSink* s) { static_cast<Mission*>(m)->observer().detach(s); };
    mission_ = &mission;
  }

  // Without a mission: feed it with on_status() yourself (tests, other observers).
  FileLogger(const std::string& path, std::string_view tree_xml, std::size_t capacity = kDefaultCapacity)
      : ring_(capacity) {
    if (path.size() < 6 || path.compare(path.size() - 6, 6, ".btlog") != 0)
      throw std::runtime_error("btlog: the file extension must be .btlog: " + path);
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) throw std::runtime_error("btlog: cannot create " + path + ": " + std::strerror(errno));
    write("BTCPP4-FileLogger2", 18);
    write("\x01", 1);
    const auto n = static_cast<std::uint32_t>(tree_xml.size());
    char len[4];
    for (int i = 0; i < 4; ++i) len[i] = static_cast<char>((n >> (8 * i)) & 0xFF);
    write(len, 4);
    write(tree_xml.data(), tree_xml.size());
    first_usec_ = wall_clock_usec();
    const auto first = static_cast<std::uint64_t>(first_usec_);
    char ts[8];
    for (int i = 0; i < 8; ++i) ts[i] = static_cast<char>((first >> (8 * i)) & 0xFF);
    write(ts, 8);
    flush();
    if (const int e = error_.load()) {
      close_file();
      throw std::runtime_error("btlog: cannot write " + path + ": " + std::strerror(e));
    }
    writer_ = std::thread([this] { writer_loop(); });
  }

  FileLogger(const FileLogger&) = delete;
  FileLogger& operator=(const FileLogger&) = delete;

  ~FileLogger() { static_cast<void>(close()); }

  // Stops logging, writes what is pending and closes the file: 0 when every byte reached
  // it, else the errno of the first write that failed (ENOSPC on a full file system: the
  // file is cut short, and a robot should say so). Later calls return the same.
  [[nodiscard]] int close() noexcept {
    if (mission_ != nullptr) detach_(mission_, this);
    mission_ = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_one();
    if (writer_.joinable()) writer_.join();
    close_file();
    return error_.load();
  }
  // The errno of the first failed write so far (0: none).
  [[nodiscard]] int error() const noexcept { return error_.load(); }

  void on_status(const NodeInfo& node, Status, Status to) noexcept override {
    const std::int64_t now = wall_clock_usec();
    const std::uint64_t rel = now > first_usec_ ? static_cast<std::uint64_t>(now - first_usec_) : 0;
    ring_.push(Transition{rel, node.uid, static_cast<std::uint8_t>(to)});
  }

  // Records dropped because the ring was full.
  [[nodiscard]] std::uint64_t dropped() const noexcept { return ring_.dropped(); }
  // Microseconds since the epoch of the file's first timestamp.
  [[nodiscard]] std::int64_t first_timestamp() const noexcept { return first_usec_; }

 private:
  void writer_loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      const bool stopping = cv_.wait_for(lock, std::chrono::milliseconds(10), [this] { return stop_; });
      lock.unlock();
      write_pending();
      lock.lock();
      if (stopping) return;
    }
  }
  void write_pending() {
    char rec[9];
    const std::size_t n = ring_.drain([&](const Transition& t) {
      pack_transition(t, rec);
      write(rec, 9);
    });
    if (n != 0) flush();
  }
  // After a failed write nothing more is written: the file stays a prefix of the log.
  void write(const char* data, std::size_t size) noexcept {
    if (error_.load() != 0 || file_ == nullptr) return;
    errno = 0;
    if (std::fwrite(data, 1, size, file_) != size) fail();
  }
  void flush() noexcept {
    if (error_.load() != 0 || file_ == nullptr) return;
    errno = 0;
    if (std::fflush(file_) != 0) fail();
  }
  void fail() noexcept {
    int expected = 0;
    error_.compare_exchange_strong(expected, errno != 0 ? errno : EIO);
  }
  void close_file() noexcept {
    if (file_ == nullptr) return;
    errno = 0;
    if (std::fclose(file_) != 0) fail();
    file_ = nullptr;
  }

  TransitionRing ring_;
  std::FILE* file_ = nullptr;
  std::atomic<int> error_{0};
  std::int64_t first_usec_ = 0;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread writer_;
  void* mission_ = nullptr;
  void (*detach_)(void*, StatusSink*) = nullptr;
};

}  // namespace btlog
}  // namespace btgen
