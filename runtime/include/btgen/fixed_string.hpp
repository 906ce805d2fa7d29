// btgen runtime: strings and queues of fixed capacity, for the blackboard.
//
// BehaviorTree.CPP keeps blackboard strings in std::string and queues in
// std::deque, both on the heap. A generated mission keeps them in place:
// FixedString<N> holds at most N bytes, FixedQueue<T, N> at most N elements,
// with N computed by the generator (or set with `btgen compile
// --string-capacity` / `--queue-capacity`). Nothing here allocates. A write
// that does not fit returns false and changes nothing; generated code
// reports it through the mission's error hook and the node doing it fails
// (the one deliberate difference from BehaviorTree.CPP, see README.md).
#pragma once

#include <cstddef>
#include <cstring>
#include <string_view>

namespace btgen {

template <std::size_t N>
class FixedString {
 public:
  static constexpr std::size_t kCapacity = N;

  constexpr FixedString() noexcept = default;
  // The text, cut at N bytes (generated code only passes texts that fit).
  constexpr explicit FixedString(std::string_view text) noexcept {
    const std::size_t n = text.size() < N ? text.size() : N;
    for (std::size_t i = 0; i < n; ++i) data_[i] = text[i];
    size_ = n;
    data_[n] = '\0';
  }

  [[nodiscard]] static constexpr std::size_t capacity() noexcept { return N; }
  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
  [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] constexpr const char* data() const noexcept { return data_; }
  [[nodiscard]] constexpr const char* c_str() const noexcept { return data_; }
  [[nodiscard]] constexpr std::string_view view() const noexcept { return std::string_view(data_, size_); }
  constexpr operator std::string_view() const noexcept { return view(); }  // NOLINT: a string is a view

  // Replaces the text; false (and no change) when it is longer than N bytes.
  [[nodiscard]] bool assign(std::string_view text) noexcept {
    if (text.size() > N) return false;
    if (!text.empty()) std::memmove(data_, text.data(), text.size());  // `text` may be this string
    size_ = text.size();
    data_[size_] = '\0';
    return true;
  }

  // Appends; false (and no change) when the result would be longer than N bytes.
  [[nodiscard]] bool append(std::string_view text) noexcept {
    if (text.size() > N - size_) return false;
    if (!text.empty()) std::memmove(data_ + size_, text.data(), text.size());
    size_ += text.size();
    data_[size_] = '\0';
    return true;
  }

  constexpr void clear() noexcept {
    size_ = 0;
    data_[0] = '\0';
  }

  friend bool operator==(const FixedString& a, std::string_view b) noexcept { return a.view() == b; }
  friend bool operator!=(const FixedString& a, std::string_view b) noexcept { return a.view() != b; }
  friend bool operator==(std::string_view a, const FixedString& b) noexcept { return a == b.view(); }
  friend bool operator!=(std::string_view a, const FixedString& b) noexcept { return a != b.view(); }

 private:
  std::size_t size_ = 0;
  char data_[N + 1] = {};
};

// A first-in first-out queue of at most N elements (BehaviorTree.CPP's
// SharedQueue<T>, the queue of LoopInt/LoopBool/LoopDouble/LoopString).
template <class T, std::size_t N>
class FixedQueue {
 public:
  using value_type = T;
  static constexpr std::size_t kCapacity = N;

  [[nodiscard]] static constexpr std::size_t capacity() noexcept { return N; }
  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
  [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] constexpr bool full() const noexcept { return size_ == N; }

  // The i-th element from the front.
  [[nodiscard]] constexpr const T& operator[](std::size_t i) const noexcept { return items_[(head_ + i) % slots()]; }
  [[nodiscard]] constexpr T& operator[](std::size_t i) noexcept { return items_[(head_ + i) % slots()]; }
  [[nodiscard]] constexpr const T& front() const noexcept { return items_[head_]; }

  // Adds at the back; false (and no change) when full.
  [[nodiscard]] constexpr bool push_back(const T& value) noexcept {
    if (size_ == N) return false;
    items_[(head_ + size_) % slots()] = value;
    ++size_;
    return true;
  }

  // Slot for a new element at the back (for elements built in place); nullptr when full.
  [[nodiscard]] constexpr T* emplace_slot() noexcept {
    if (size_ == N) return nullptr;
    T* slot = &items_[(head_ + size_) % slots()];
    ++size_;
    return slot;
  }

  // Removes the front element; false when empty.
  constexpr bool pop_front() noexcept {
    if (size_ == 0) return false;
    head_ = (head_ + 1) % slots();
    --size_;
    return true;
  }

  constexpr void clear() noexcept {
    head_ = 0;
    size_ = 0;
  }

 private:
  static constexpr std::size_t slots() noexcept { return N == 0 ? 1 : N; }

  std::size_t head_ = 0;
  std::size_t size_ = 0;
  T items_[N == 0 ? 1 : N] = {};
};

}  // namespace btgen
