// btgen runtime: part of class btgen::Engine, the rules of Nav2's Controls and Decorators
// (nav2_tick, the halt they call from their tick, PersistentSequence's write_index). Not a header
// of its own: btgen/engine.hpp includes it inside the class body (private members, as they were
// written in engine.hpp; clang-format is off because it would indent them as if at namespace
// scope).
// clang-format off
  // Nav2's Controls and Decorators (the generator's lang/nav2.py), as the traces recorded from
  // Nav2's own plugins show them (tests/conformance/nav2). `halt_self` is the node's halt()
  // called from its own tick: the children reset, the node IDLE, its place forgotten.
  void nav2_halt_self(const NodeInfo& n, const ChildOps& ops) noexcept {
    ops.halt_children();
    ops.set_status(Status::IDLE);
    forget(n);
  }
  // setOutput of PersistentSequence's place (Spec::write_index, generated for missions that
  // have one writing an entry; a literal port is not written, as setOutput fails on it).
  void write_index(const NodeInfo& n, std::int64_t value) noexcept {
    if constexpr (engine_detail::has_write_index<Spec>::value) {
      if (n.p1 != 0) (void)Spec::write_index(bb_, sink(), n, value);
    } else {
      (void)n;
      (void)value;
    }
  }
  Status nav2_tick(const NodeInfo& n, const ChildOps& ops) noexcept {
    const auto count = static_cast<std::int32_t>(n.child_count);
    switch (n.kind) {
      case NodeKind::PipelineSequence: {
        // counter 0: the furthest child that answered RUNNING
        std::int32_t& last = counter(n, 0);
        std::int32_t skipped = 0;
        for (std::int32_t i = 0; i < count; ++i) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(i));
          if (cs == Status::FAILURE) {
            ops.halt_children();
            last = 0;
            return cs;
          }
          if (cs == Status::SKIPPED) {
            ++skipped;
          } else if (cs == Status::RUNNING && i >= last) {
            last = i;
            return cs;
          }
        }
        ops.halt_children();
        last = 0;
        return skipped == count ? Status::SKIPPED : Status::SUCCESS;
      }
      case NodeKind::RecoveryNode: {
        // counters: 0 the child being run, 1 recoveries done, 2 and 3 the `{key}` value read
        // last and whether one was (a failed read keeps it; none yet: Nav2's 1)
        std::int32_t& current = counter(n, 0);
        std::int32_t& tries = counter(n, 1);
        std::int64_t retries = param::number_of_retries(n);
        if (n.p1 != 0) {
          std::int64_t v = 0;
          if (Spec::read_param(bb_, ErrorSink([](void*, const RuntimeError&) noexcept {}, nullptr), n, v) > 0) {
            counter(n, 2) = static_cast<std::int32_t>(v);
            counter(n, 3) = 1;
          }
          retries = counter(n, 3) != 0 ? counter(n, 2) : 1;
        }
        ops.set_status(Status::RUNNING);
        while (current < 2 && tries <= retries) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(current));
          if (cs == Status::RUNNING) return cs;
          if (current == 0) {
            if (cs == Status::SKIPPED) {
              nav2_halt_self(n, ops);
              return cs;
            }
            if (cs == Status::SUCCESS) {
              ops.halt_child(1);
              nav2_halt_self(n, ops);
              return cs;
            }
            if (tries >= retries) {
              nav2_halt_self(n, ops);
              return Status::FAILURE;
            }
            ops.halt_child(0);
            current = 1;
          } else {
            if (cs == Status::SKIPPED) {
              current = 0;
              ops.halt_child(1);
              return Status::FAILURE;
            }
            if (cs == Status::FAILURE) {
              nav2_halt_self(n, ops);
              return cs;
            }
            ops.halt_child(1);
            ++tries;
            current = 0;
          }
        }
        nav2_halt_self(n, ops);
        return Status::FAILURE;
      }
      case NodeKind::RoundRobin: {
        // counters: 0 the next child, 1 failures in a row
        std::int32_t& idx = counter(n, 0);
        std::int32_t& failed = counter(n, 1);
        ops.set_status(Status::RUNNING);
        std::int32_t skipped = 0;
        while (failed + skipped < count) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(idx));
          if (cs != Status::RUNNING && ++idx == count) {
            if (param::wrap_around(n)) {
              idx = 0;
            } else {
              if (cs == Status::SKIPPED) ++skipped;
              if (cs == Status::FAILURE) ++failed;
              break;
            }
          }
          if (cs == Status::SUCCESS) {
            failed = 0;
            ops.halt_children();
            return cs;
          }
          if (cs == Status::RUNNING) return cs;
          if (cs == Status::FAILURE) ++failed;
          if (cs == Status::SKIPPED) ++skipped;
        }
        const bool all_skipped = skipped == count;
        nav2_halt_self(n, ops);
        return all_skipped ? Status::SKIPPED : Status::FAILURE;
      }
      case NodeKind::NonblockingSequence: {
        bool all_success = true;
        for (std::int32_t i = 0; i < count; ++i) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(i));
          if (cs == Status::FAILURE) {
            ops.halt_children();
            return cs;
          }
          if (cs == Status::RUNNING) {
            all_success = false;
          } else if (cs != Status::SUCCESS) {
            (void)sink().fail(n, n.source,
                              "a child returned SKIPPED, which Nav2's NonblockingSequence forbids (it throws)");
            return Status::FAILURE;
          }
        }
        if (!all_success) return Status::RUNNING;
        ops.halt_children();
        return Status::SUCCESS;
      }
      case NodeKind::PersistentSequence: {
        // Its place is the entry `current_child_idx` names: read on every tick (Nav2 throws when
        // it cannot: an error, the node fails), written after each child that completes.
        std::int64_t idx = n.p0;
        if (n.p1 != 0 && Spec::read_param(bb_, sink(), n, idx) < 0) return Status::FAILURE;
        if (idx < 0) {
          (void)sink().fail(n, n.source, "`current_child_idx` is negative: no child has that place");
          return Status::FAILURE;
        }
        ops.set_status(Status::RUNNING);
        while (idx < count) {
          const Status cs = ops.tick_child(static_cast<std::size_t>(idx));
          if (cs == Status::RUNNING) return cs;
          if (cs == Status::FAILURE) {
            ops.halt_children();
            write_index(n, 0);
            return cs;
          }
          ++idx;
          write_index(n, idx);
        }
        ops.halt_children();
        write_index(n, 0);
        return Status::SUCCESS;
      }
      case NodeKind::RateController: {
        // counter 0: the child is ticked on this run's first tick; timer: when the period began.
        // The time since, in float seconds (Nav2's duration<float>), against the period 1/hz.
        // Timer 1 keeps the bits of hz read when the run started (a literal: NodeInfo p0; a
        // `{key}`: getInput<double>, 1.0 when it fails, as Nav2's local default).
        std::int32_t& first = counter(n, 0);
        if (!is_active(status_[n.index])) {
          timer(n) = clock_.now_ms();
          first = 1;
          std::int64_t bits = n.p0;
          if (n.p1 != 0) (void)Spec::read_param(bb_, sink(), n, bits);
          timers_[n.timer + 1] = static_cast<std::uint64_t>(bits);
        }
        ops.set_status(Status::RUNNING);
        double hz = 0.0;
        const std::uint64_t hz_bits = timers_[n.timer + 1];
        std::memcpy(&hz, &hz_bits, sizeof hz);
        const double period = 1.0 / hz;
        const auto ns = static_cast<std::int64_t>(elapsed(n)) * 1000000;
        const float seconds = static_cast<float>(ns) / 1.0e9f;
        if (first != 0 || ops.child_status(0) == Status::RUNNING || static_cast<double>(seconds) >= period) {
          first = 0;
          const Status cs = ops.tick_child(0);
          if (cs == Status::SUCCESS) timer(n) = clock_.now_ms();
          return cs;
        }
        return status_[n.index];
      }
      case NodeKind::SingleTrigger: {
        // counter 0: the child completed during this run of the node
        std::int32_t& spent = counter(n, 0);
        if (!is_active(status_[n.index])) spent = 0;
        ops.set_status(Status::RUNNING);
        if (spent != 0) return Status::FAILURE;
        const Status cs = ops.tick_child(0);
        if (cs == Status::SUCCESS || cs == Status::FAILURE) spent = 1;
        return cs;
      }
      default:
        if (is_nav2_env_node(n.kind)) {
          std::int32_t none = 0;
          std::int32_t& first = n.slot != kNoSlot ? counter(n, 0) : none;
          return nav2_env_tick(n.kind, ops, first, [&]() { return nav2_env_input(n); });
        }
        return Status::FAILURE;
    }
  }
  // The input of a Nav2 Decorator (btgen/nav2.hpp): Leaves' answer, yes or no.
  bool nav2_env_input(const NodeInfo& n) noexcept {
    const Status s = nav2_input(*leaves_, n);
    if (s != Status::SUCCESS && s != Status::FAILURE) {
      (void)sink().fail(n, n.source, "the input of this Nav2 Decorator is SUCCESS (yes) or FAILURE (no)");
    }
    return s == Status::SUCCESS;
  }

  // The start of executeTick: the pre-conditions may decide instead of tick().
  [[gnu::always_inline]] Step begin(Frame& f, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    if ((kMissionScripts & kPreBits) != 0 && (n.scripts & kPreBits) != 0) {
      const Status decided = pre_conditions(f.node, n);
      if (decided != Status::IDLE) {
        f.decorator = is_decorator(kind) ? 1 : 0;
        return done(decided);
      }
    }
    if constexpr (kHooks) {
      const Status h = __builtin_expect(observer_.hooked(f.node), 0) ? forced_slow(f.node) : Status::IDLE;
      if (h != Status::IDLE) {
        f.decorator = is_decorator(kind) ? 1 : 0;
        return done(h);
      }
    }
    return enter(f, kind);
  }

  // The end of executeTick: the post-conditions of a completed node; a
  // SKIPPED node keeps its status; a decorator resets a child left
  // completed (DecoratorNode::executeTick). Returns the node's result.
  [[gnu::always_inline]] Status finish(const Frame& f, Status s) noexcept {
    const std::uint16_t node = f.node;
    const NodeInfo& n = info(node);
    if ((kMissionScripts & kPostBits) != 0 && (n.scripts & kPostBits) != 0 && is_completed(s)) {
      s = post_conditions(n, s);
    }
    s = post_hook(node, s);
    if (s != Status::SKIPPED) set_status(node, s);
    if (f.decorator != 0) {
      const std::uint16_t c = child(n, 0);
      if (is_completed(status_[c])) reset_status(c);
    }
    return s;
  }
// clang-format on
