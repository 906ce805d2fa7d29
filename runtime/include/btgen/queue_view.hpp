// btgen runtime: the queue ports of a mission's own leaves.
//
// BehaviorTree.CPP passes a queue between nodes as BT::SharedQueue<T>
// (std::shared_ptr<std::deque<T>>): a node fills one and setOutput()s it, a
// LoopString (or another node) reads the same deque through getInput() and
// pops from it. A generated mission keeps the queue in place, in its
// blackboard entry (FixedQueue<E, N>, N from `btgen compile
// --queue-capacity`), and a leaf reaches it through a QueueView:
//
//   auto q = model.waypoint_queue();   // btgen::Input<btgen::QueueView<std::string_view>>
//   if (q) { q->size(); q->front(); q->pop_front(); q->push_back("x"); }
//   model.set_waypoint_queue(items);   // a new queue: every element of `items`
//   auto out = model.set_waypoint_queue();  // a new, empty queue, filled through its view
//   if (!out.push_back(part)) return model.fail("too many waypoints");
//
// A QueueView is the shared deque: its changes are the entry's, as with the
// library's shared pointer. Its element type does not depend on the mission's
// capacities (std::string_view, std::int32_t, double or bool), so one leaf
// implementation builds against every mission using its model. Nothing here
// allocates: a push that does not fit (the queue is full, or a string is
// longer than the entry's element capacity) returns false and changes nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "btgen/blackboard.hpp"
#include "btgen/fixed_string.hpp"
#include "btgen/node.hpp"
#include "btgen/port.hpp"
#include "btgen/value.hpp"

namespace btgen {

namespace queue_detail {

// The element a leaf sees for a stored element type.
template <class T>
struct Seen {
  using type = std::string_view;  // FixedString<C>
};
template <>
struct Seen<std::int64_t> {
  using type = std::int32_t;  // BT::SharedQueue<int>
};
template <>
struct Seen<double> {
  using type = double;
};
template <>
struct Seen<bool> {
  using type = bool;
};

// A stored element from what a leaf passes: false when it does not fit.
template <class T, class V>
bool store(T& out, const V& v) noexcept {
  if constexpr (port::is_fixed_string<T>::value) {
    return out.assign(std::string_view(v));
  } else {
    out = static_cast<T>(v);
    return true;
  }
}

template <class T>
typename Seen<T>::type seen(const T& v) noexcept {
  if constexpr (port::is_fixed_string<T>::value) {
    return v.view();
  } else {
    return static_cast<typename Seen<T>::type>(v);
  }
}

}  // namespace queue_detail

// A view of a queue entry (BT::SharedQueue<E>) whatever its capacities: the
// element type E a leaf sees is std::string_view, std::int32_t, double or bool.
// A default-constructed view is of no entry: empty, and every push fails.
template <class E>
class QueueView {
 public:
  using value_type = E;

  constexpr QueueView() noexcept = default;
  template <class T, std::size_t N>
  explicit QueueView(FixedQueue<T, N>& q) noexcept : q_(&q), ops_(&kOps<T, N>) {
    static_assert(std::is_same_v<typename queue_detail::Seen<T>::type, E>, "a view of another element type");
  }

  [[nodiscard]] bool valid() const noexcept { return q_ != nullptr; }
  [[nodiscard]] std::size_t size() const noexcept { return q_ ? ops_->size(q_) : 0; }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  [[nodiscard]] std::size_t capacity() const noexcept { return q_ ? ops_->capacity : 0; }
  [[nodiscard]] bool full() const noexcept { return size() == capacity(); }
  // The i-th element from the front (i < size()); a string views the entry's text,
  // valid until that element is popped or overwritten.
  [[nodiscard]] E operator[](std::size_t i) const noexcept { return ops_->at(q_, i); }
  [[nodiscard]] E front() const noexcept { return ops_->at(q_, 0); }
  [[nodiscard]] E back() const noexcept { return ops_->at(q_, size() - 1); }
  // deque::push_back; false (and no change) when the queue is full or a string
  // is longer than the entry's element capacity.
  [[nodiscard]] bool push_back(E value) const noexcept { return q_ != nullptr && ops_->push(q_, value); }
  // deque::pop_front; false when empty.
  bool pop_front() const noexcept { return q_ != nullptr && ops_->pop(q_); }
  void clear() const noexcept {
    if (q_ != nullptr) ops_->clear(q_);
  }

 private:
  struct Ops {
    std::size_t (*size)(const void* q) noexcept;
    std::size_t capacity;
    E (*at)(const void* q, std::size_t i) noexcept;
    bool (*push)(void* q, E value) noexcept;
    bool (*pop)(void* q) noexcept;
    void (*clear)(void* q) noexcept;
  };
  template <class T, std::size_t N>
  static constexpr Ops kOps = {
      [](const void* q) noexcept { return static_cast<const FixedQueue<T, N>*>(q)->size(); },
      N,
      [](const void* q, std::size_t i) noexcept {
        return queue_detail::seen((*static_cast<const FixedQueue<T, N>*>(q))[i]);
      },
      [](void* q, E value) noexcept {
        T item{};
        return queue_detail::store(item, value) && static_cast<FixedQueue<T, N>*>(q)->push_back(item);
      },
      [](void* q) noexcept { return static_cast<FixedQueue<T, N>*>(q)->pop_front(); },
      [](void* q) noexcept { static_cast<FixedQueue<T, N>*>(q)->clear(); },
  };

  void* q_ = nullptr;
  const Ops* ops_ = nullptr;
};

namespace port {

// getInput<SharedQueue<E>> of a port connected to a queue entry: the entry's own queue.
template <class E, class T, std::size_t N>
Input<QueueView<E>> read_queue(Slot<FixedQueue<T, N>>& slot) noexcept {
  if (!slot.exists) return PortError::kNoEntry;
  if (!slot.has_value) return PortError::kNoValue;
  return QueueView<E>(slot.value);
}

// setOutput of a new, empty SharedQueue<E> into the port's entry (it exists and holds
// that queue after it): the view to fill it through.
template <class E, class T, std::size_t N>
QueueView<E> new_queue(Slot<FixedQueue<T, N>>& slot) noexcept {
  slot.value.clear();
  slot.mark_written();
  return QueueView<E>(slot.value);
}

// A new queue of every element of `items` (a range of E, or, for numbers and
// bools, of texts converted as convertFromString<E> converts them, doubles by
// the release's rule). Errc::kTooLong: more elements than the capacity, or a
// string longer than the element capacity; a text that does not convert: its
// conversion error. On an error the queue is left as it was.
template <bool kFromChars, class T, std::size_t N, class Range>
Errc fill_queue(FixedQueue<T, N>& out, const Range& items) noexcept {
  FixedQueue<T, N> q;
  for (const auto& item : items) {
    T* slot = q.emplace_slot();
    if (slot == nullptr) return Errc::kTooLong;
    using V = std::decay_t<decltype(item)>;
    if constexpr (port::is_fixed_string<T>::value) {
      if (!slot->assign(std::string_view(item))) return Errc::kTooLong;
    } else if constexpr (std::is_convertible_v<V, std::string_view>) {
      if (!queue_element<kFromChars>(std::string_view(item), *slot)) return Errc::kInvalid;
    } else {
      *slot = static_cast<T>(item);
    }
  }
  out = q;
  return Errc::kOk;
}

// setOutput of a new SharedQueue<E> holding `items` into the port's entry: the
// entry holds that queue (and exists) after it. A queue that does not fit is
// reported as `message` at `where` with the reason, and nothing is stored.
template <bool kFromChars, class T, std::size_t N, class Range>
bool set_queue(Slot<FixedQueue<T, N>>& slot, const Range& items, const ErrorSink& err, const NodeInfo& node,
               std::string_view where, std::string_view message) noexcept {
  const Errc e = fill_queue<kFromChars>(slot.value, items);
  if (e == Errc::kOk) {
    slot.mark_written();
    return true;
  }
  (void)err.fail(node, where, message, describe(e));
  return false;
}

}  // namespace port

// ---------------------------------------------------------------- shared queues
//
// SetBlackboard value="{q}" output_key="r" copies the library's shared pointer: `r` and
// `q` are one deque until either is set anew. The entries such copies connect (one
// element type and capacity) keep a QueueRef, the number of a queue of their QueuePool,
// which holds as many queues as there are entries: an entry set anew releases its queue
// and takes a free one (the others hold at most all but one), a copy shares the source's.

// The queue an entry of a pool holds (meaningful while the entry has a value).
struct QueueRef {
  std::uint8_t index = 0;
};

template <class Q, std::size_t K>
class QueuePool {
  static_assert(K >= 1 && K <= 255, "a pool of 1 to 255 queues");

 public:
  [[nodiscard]] Q& at(QueueRef r) noexcept { return items_[r.index]; }
  [[nodiscard]] const Q& at(QueueRef r) const noexcept { return items_[r.index]; }

  // The entry's queue is released (when it holds one).
  void release(const Slot<QueueRef>& slot) noexcept {
    if (slot.has_value && refs_[slot.value.index] > 0) --refs_[slot.value.index];
  }
  // The entry holds a new, empty queue of its own.
  Q& fresh(Slot<QueueRef>& slot) noexcept {
    release(slot);
    std::size_t i = 0;
    while (i + 1 < K && refs_[i] != 0) ++i;  // (one is free: K entries, this one released)
    refs_[i] = 1;
    items_[i].clear();
    slot.value.index = static_cast<std::uint8_t>(i);
    return items_[i];
  }
  // The entry `dst` holds the queue of `src` (which has a value).
  void share(Slot<QueueRef>& dst, const Slot<QueueRef>& src) noexcept {
    const std::uint8_t i = src.value.index;
    ++refs_[i];  // first: `dst` may be `src`
    release(dst);
    dst.value.index = i;
  }

 private:
  Q items_[K] = {};
  std::uint8_t refs_[K] = {};
};

// An entry of a pool as the blackboard's visitors see it (Groot2): its queue, by value.
template <class Q, std::size_t K>
Slot<Q> pooled_slot(const Slot<QueueRef>& slot, const QueuePool<Q, K>& pool) noexcept {
  Slot<Q> out;
  if (slot.has_value) out.value = pool.at(slot.value);
  out.seq = slot.seq;
  out.exists = slot.exists;
  out.has_value = slot.has_value;
  out.entry_type = slot.entry_type;
  return out;
}

namespace port {

template <class E, class Q, std::size_t K>
Input<QueueView<E>> read_queue(Slot<QueueRef>& slot, QueuePool<Q, K>& pool) noexcept {
  if (!slot.exists) return PortError::kNoEntry;
  if (!slot.has_value) return PortError::kNoValue;
  return QueueView<E>(pool.at(slot.value));
}

template <class E, class Q, std::size_t K>
QueueView<E> new_queue(Slot<QueueRef>& slot, QueuePool<Q, K>& pool) noexcept {
  Q& q = pool.fresh(slot);
  slot.mark_written();
  return QueueView<E>(q);
}

template <bool kFromChars, class Q, std::size_t K, class Range>
bool set_queue(Slot<QueueRef>& slot, QueuePool<Q, K>& pool, const Range& items, const ErrorSink& err,
               const NodeInfo& node, std::string_view where, std::string_view message) noexcept {
  Q q;
  const Errc e = fill_queue<kFromChars>(q, items);
  if (e != Errc::kOk) {
    (void)err.fail(node, where, message, describe(e));
    return false;
  }
  pool.fresh(slot) = q;
  slot.mark_written();
  return true;
}

}  // namespace port
}  // namespace btgen
