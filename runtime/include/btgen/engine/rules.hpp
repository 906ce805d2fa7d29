// btgen runtime: part of class btgen::Engine, the per-kind rules of the built-in nodes on the
// table interpreter (enter, resume and their helpers). Not a header of its own: btgen/engine.hpp
// includes it inside the class body (private members, as they were written in engine.hpp;
// clang-format is off because it would indent them as if at namespace scope).
// clang-format off
  // Hooks must answer SUCCESS, FAILURE or RUNNING; anything else breaks
  // their contract (BehaviorTree.CPP throws) and counts as FAILURE.
  static constexpr Status sanitize(Status s) noexcept {
    return (s == Status::SUCCESS || s == Status::FAILURE || s == Status::RUNNING) ? s : Status::FAILURE;
  }

  // `else` / `if_empty` = IDLE: the node would set its own status to IDLE,
  // which makes BehaviorTree.CPP 4.6.2 throw (edges table, L1 and L2): a
  // run-time error, and the node fails.
  Status not_idle(const NodeInfo& n, Status s) noexcept {
    if (s != Status::IDLE) return s;
    sink().fail(n, n.source,
                n.kind == NodeKind::Precondition
                    ? std::string_view("the condition is false and `else` is IDLE: a node may not set its own status "
                                       "to IDLE (BehaviorTree.CPP throws)")
                    : std::string_view("the queue is empty and `if_empty` is IDLE: a node may not set its own status "
                                       "to IDLE (BehaviorTree.CPP throws)"));
    return Status::FAILURE;
  }

  // The condition of IfThenElse / WhileDoElse `n` answered SKIPPED, which the library throws
  // on: a run-time error at the condition, and the node fails. (lower.py knows which
  // conditions can skip; only a run can tell whether one does.)
  Status skipped_condition(const NodeInfo& n) noexcept {
    const NodeInfo& cond = info(child(n, 0));
    sink().fail(cond, cond.source,
                n.kind == NodeKind::IfThenElse
                    ? std::string_view("the condition of this `IfThenElse` returned SKIPPED, which makes "
                                       "BehaviorTree.CPP throw (a condition child must not be skippable)")
                    : std::string_view("the condition of this `WhileDoElse` returned SKIPPED, which makes "
                                       "BehaviorTree.CPP throw (a condition child must not be skippable)"));
    return Status::FAILURE;
  }

  static constexpr bool is_sequence(NodeKind k) noexcept {
    return k == NodeKind::Sequence || k == NodeKind::AsyncSequence || k == NodeKind::SequenceWithMemory ||
           k == NodeKind::ReactiveSequence;
  }

  [[gnu::always_inline]] Step enter(Frame& f, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    switch (kind) {
      case NodeKind::Sequence:
      case NodeKind::AsyncSequence:
      case NodeKind::SequenceWithMemory:
      case NodeKind::Fallback:
      case NodeKind::AsyncFallback:
        // 4.6.2's all_skipped_ flag (counter 1: a child did not skip), cleared
        // only when the node is ticked from IDLE; or 4.7.0's skipped count.
        if (!is_active(status_[f.node])) counter(n, 1) = 0;
        set_status(f.node, Status::RUNNING);
        return sequence_next(f, n, kind);

      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 1;  // all children skipped so far
        return descend(child(n, 0));

      case NodeKind::TryCatch:
        // TryCatchNode (4.9.0): counter 0 the try child, 1 the try children skipped, 2 in the
        // catch child (the last one).
        if (!is_active(status_[f.node])) {
          counter(n, 1) = 0;
          counter(n, 2) = 0;
        }
        set_status(f.node, Status::RUNNING);
        if (counter(n, 2) != 0) {
          f.pos = static_cast<std::uint16_t>(n.child_count - 1);
          return descend(child(n, f.pos));
        }
        return try_next(f, n);

      case NodeKind::Parallel:
        // p2 bit 2: success_count / failure_count as `{key}`, read at the start of every tick
        // (Spec::read_param; it throws where a read fails or a threshold cannot be reached)
        if ((n.p2 & kParallelReads) != 0) {
          std::int64_t v = 0;
          if (Spec::read_param(bb_, sink(), n, v) < 0) return done(Status::FAILURE);
          counter(n, 2) = static_cast<std::int32_t>(v & 0xFFFFF);
          counter(n, 3) = static_cast<std::int32_t>((v >> 20) & 0xFFFFF);
          counter(n, 4) = static_cast<std::int32_t>((v >> 40) & 1);
        }
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 0;  // skipped this tick
        return parallel_next(f, n);

      case NodeKind::ParallelAll:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        f.aux = 0;
        return parallel_all_next(f, n);

      case NodeKind::IfThenElse:
        set_status(f.node, Status::RUNNING);
        f.pos = static_cast<std::uint16_t>(counter(n, 0));
        return descend(child(n, f.pos));

      case NodeKind::WhileDoElse:
        set_status(f.node, Status::RUNNING);
        f.pos = 0;
        return descend(child(n, 0));

      case NodeKind::Inverter:
      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
      case NodeKind::KeepRunningUntilFailure:
        f.decorator = 1;
        set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Repeat:
      case NodeKind::RetryUntilSuccessful:
        f.decorator = 1;
        // 4.6.2's all_skipped_ flag (counter 1: a child did not skip), cleared
        // only from IDLE: a count of 0 or below -1 never ticks the child, so
        // the node answers SKIPPED and stays RUNNING (edges table, R1).
        if (!read_param(n, true)) return done(Status::FAILURE);  // 4.6.2 throws: the node fails
        if (status_[f.node] == Status::IDLE) counter(n, 1) = 0;
        set_status(f.node, Status::RUNNING);
        if (counter(n, 0) < max_cycles(n) || max_cycles(n) == -1) return descend(child(n, 0));
        counter(n, 0) = 0;
        // From 4.7.0 (Sem::loop_end_never_skipped) the loop ends SUCCESS / FAILURE.
        if (!Sem::loop_end_never_skipped && counter(n, 1) == 0) return done(Status::SKIPPED);
        return done(kind == NodeKind::Repeat ? Status::SUCCESS : Status::FAILURE);

      case NodeKind::RunOnce:
        f.decorator = 1;
        if (counter(n, 0) != 0) {
          // then_skip given as `{key}` (p1 is 1): getInput<bool> never throws here, so reading
          // it only once the child has completed is what 4.6.2's read on every tick gives.
          std::int64_t skip = (n.p1 != 0 || param::then_skip(n)) ? 1 : 0;
          if (n.p1 != 0) (void)Spec::read_param(bb_, sink(), n, skip);
          return done(skip != 0 ? Status::SKIPPED : static_cast<Status>(counter(n, 1)));
        }
        set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Timeout: {
        f.decorator = 1;
        std::int32_t& started = counter(n, 0);
        std::int32_t& armed = counter(n, 1);
        if (!read_param(n, started == 0)) return done(Status::FAILURE);
        if (started == 0) {
          started = 1;
          set_status(f.node, Status::RUNNING);
          armed = duration_ms(n) > 0 ? 1 : 0;
          timer(n) = clock_.now_ms();
        } else if (armed != 0 && reached(elapsed(n), duration_ms(n))) {
          // The timer fires: a RUNNING child is halted and the node fails.
          armed = 0;
          if (status_[child(n, 0)] == Status::RUNNING) {
            halt_child(n, 0);
            started = 0;
            return done(Status::FAILURE);
          }
        }
        return descend(child(n, 0));
      }

      case NodeKind::Delay: {
        f.decorator = 1;
        std::int32_t& started = counter(n, 0);
        if (!read_param(n, started == 0)) return done(Status::FAILURE);
        if (started == 0) {
          started = 1;
          set_status(f.node, Status::RUNNING);
          timer(n) = clock_.now_ms();
        }
        if (reached(elapsed(n), duration_ms(n))) return descend(child(n, 0));
        return done(Status::RUNNING);
      }

      case NodeKind::SubTree:
        f.decorator = 1;
        if (status_[f.node] == Status::IDLE) set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));

      case NodeKind::Switch: {
        // SwitchNode<N>: no RUNNING of its own before the case is ticked;
        // a change of case halts the one that was running.
        const int match = Spec::switch_case(bb_, n);
        std::int32_t& running = counter(n, 0);  // the case RUNNING + 1
        if (running != 0 && running - 1 != match) halt_child(n, static_cast<std::size_t>(running - 1));
        f.pos = static_cast<std::uint16_t>(match);
        return descend(child(n, f.pos));
      }

      case NodeKind::Precondition: {
        f.decorator = 1;
        // p1: `else` read on every tick (Spec::read_param): a `{key}`, or a literal that is no
        // NodeStatus, which the library throws on when it reads it (the read reports it)
        Status otherwise = param::otherwise(n);
        if (n.p1 != 0) {
          std::int64_t v = 0;
          if (Spec::read_param(bb_, sink(), n, v) < 0) return done(Status::FAILURE);
          otherwise = static_cast<Status>(v);
        }
        // 4.6.2 evaluates `if` on every tick; when false it answers `else`
        // without ticking (or halting) its child. From 4.7.0
        // (Sem::precondition_if_until_started) only until the child has
        // started (counter 0), which then runs to completion; halt() does not
        // clear that flag (a quirk of the library, followed).
        if constexpr (Sem::precondition_if_until_started) {
          if (counter(n, 0) != 0) return descend(child(n, 0));
        }
        const int r = run_script(n, ScriptSlot::kCode);
        if (r < 0) return done(Status::FAILURE);
        if (r == 1) {
          if constexpr (Sem::precondition_if_until_started) counter(n, 0) = 1;
          return descend(child(n, 0));
        }
        return done(not_idle(n, otherwise));
      }

      case NodeKind::Loop: {
        f.decorator = 1;
        // LoopNode<T>: one element per run of the child (written to
        // `value`), RUNNING after every child success, `if_empty` (p0)
        // once the queue is used up.
        std::int32_t& child_running = counter(n, 0);
        const bool idle = status_[f.node] == Status::IDLE;
        if (idle) child_running = 0;
        if (child_running == 0) {
          const ErrorSink es = sink();
          const int r = Spec::loop_pop(bb_, n, es, idle);
          if (r < 0) return done(Status::FAILURE);
          if (r == 0) {
            if (!read_param(n, false)) return done(Status::FAILURE);  // p1: an `if_empty` that is no NodeStatus
            return done(not_idle(n, param::otherwise(n)));
          }
        }
        if (idle) set_status(f.node, Status::RUNNING);
        return descend(child(n, 0));
      }

      case NodeKind::SkipUnlessUpdated:
      case NodeKind::WaitValueUpdate: {
        f.decorator = 1;
        // EntryUpdatedDecorator: the child runs only when the entry's
        // update counter moved since this node last looked.
        const Status not_updated = kind == NodeKind::SkipUnlessUpdated ? Status::SKIPPED : Status::RUNNING;
        if (counter(n, 0) != 0) return descend(child(n, 0));  // the child is still executing
        const std::int64_t seq = Spec::entry_seq(bb_, n);
        if (seq < 0) return done(not_updated);
        const std::uint64_t previous = timer(n);
        timer(n) = static_cast<std::uint64_t>(seq);
        if (previous == static_cast<std::uint64_t>(seq)) return done(not_updated);
        return descend(child(n, 0));
      }

      case NodeKind::AlwaysSuccess: return done(Status::SUCCESS);

      case NodeKind::AlwaysFailure: return done(Status::FAILURE);

      case NodeKind::Sleep: {
        const Status st = status_[f.node];
        if (st == Status::IDLE) {
          if (!read_param(n, true)) return done(Status::FAILURE);
          if (duration_ms(n) <= 0) return done(Status::SUCCESS);
          set_status(f.node, Status::RUNNING);
          timer(n) = clock_.now_ms();
          return done(Status::RUNNING);
        }
        if (st == Status::RUNNING) return done(reached(elapsed(n), duration_ms(n)) ? Status::SUCCESS : Status::RUNNING);
        return done(st);
      }

      case NodeKind::Script: return done(run_script(n, ScriptSlot::kCode) < 0 ? Status::FAILURE : Status::SUCCESS);

      case NodeKind::ScriptCondition:
        return done(run_script(n, ScriptSlot::kCode) == 1 ? Status::SUCCESS : Status::FAILURE);

      case NodeKind::SetBlackboard:
      case NodeKind::UnsetBlackboard: {
        const ErrorSink es = sink();
        return done(Spec::data_leaf(bb_, n, es));
      }

      case NodeKind::WasEntryUpdated: {
        const std::int64_t seq = Spec::entry_seq(bb_, n);
        if (seq < 0) return done(Status::FAILURE);
        const std::uint64_t previous = timer(n);
        timer(n) = static_cast<std::uint64_t>(seq);
        return done(previous != static_cast<std::uint64_t>(seq) ? Status::SUCCESS : Status::FAILURE);
      }

      case NodeKind::Action: {
        // StatefulActionNode: onStart from IDLE, onRunning while RUNNING; a
        // node not yet reset by its parent answers its status again (a
        // SyncActionNode, tick() alone, ticks again: LeafHooks::on_start calls it).
        const Status st = status_[f.node];
        if (st != Status::IDLE && st != Status::RUNNING && !Hooks::sync_action(n)) return done(st);
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        const Status s =
            st == Status::IDLE ? Hooks::on_start(*leaves_, bb_, es, n) : Hooks::on_running(*leaves_, bb_, es, n);
        return done(guarded(s, before));
      }

      case NodeKind::Condition: {
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        return done(guarded(Hooks::check(*leaves_, bb_, es, n), before));
      }

      case NodeKind::PipelineSequence:
      case NodeKind::RecoveryNode:
      case NodeKind::RoundRobin:
      case NodeKind::NonblockingSequence:
      case NodeKind::PersistentSequence:
      case NodeKind::RateController:
      case NodeKind::SingleTrigger:
      case NodeKind::DistanceController:
      case NodeKind::SpeedController:
      case NodeKind::GoalUpdatedController:
      case NodeKind::PathLongerOnApproach:
      case NodeKind::GoalUpdater: {
        // Nav2's nodes tick their children as a user Control does, above this frame of the
        // stack; an error of a child fails only the child.
        f.decorator = is_decorator(kind) ? 1 : 0;
        const std::uint64_t before = errors_;
        const std::size_t base = static_cast<std::size_t>(&f - stack_.data()) + 1;
        f.aux = 0;
        const Status s = nav2_tick(n, ChildOps(&kChildOps, this, &n, base));
        if (errors_ - before > f.aux) return done(Status::FAILURE);
        return done(s);
      }

      case NodeKind::UserControl:
      case NodeKind::UserDecorator: {
        // The user's tick(); its children run above this frame of the stack. An error the
        // node reports itself (fail(), a port write) fails it; its children's errors
        // (counted in f.aux by ops_tick_child) only fail them.
        f.decorator = kind == NodeKind::UserDecorator ? 1 : 0;
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        const std::size_t base = static_cast<std::size_t>(&f - stack_.data()) + 1;
        f.aux = 0;
        const Status s = Hooks::user_tick(*leaves_, bb_, es, n, ChildOps(&kChildOps, this, &n, base));
        if (errors_ - before > f.aux) return done(Status::FAILURE);
        if (s == Status::IDLE) {
          // TreeNode::setStatus(IDLE) throws in 4.6.2.
          (void)es.fail(n, n.source, "tick() returned IDLE: a node is not allowed to set its status to IDLE");
          return done(Status::FAILURE);
        }
        return done(s);
      }
    }
    return done(Status::FAILURE);
  }

  [[gnu::always_inline]] Step resume(Frame& f, Status cs, NodeKind kind) noexcept {
    const NodeInfo& n = info(f.node);
    switch (kind) {
      case NodeKind::Sequence:
      case NodeKind::AsyncSequence:
      case NodeKind::SequenceWithMemory: {
        std::int32_t& idx = counter(n, 0);
        note_skipped(counter(n, 1), cs);
        switch (cs) {
          case Status::RUNNING: return done(Status::RUNNING);
          case Status::SUCCESS:
            ++idx;
            // SequenceWithMemory always has the wake-up rule in 4.6.2,
            // AsyncSequence is the plain Sequence with it.
            if (kind != NodeKind::Sequence && f.child_prev == Status::IDLE && idx < n.child_count) {
              return done(Status::RUNNING);
            }
            return sequence_next(f, n, kind);
          case Status::SKIPPED: ++idx; return sequence_next(f, n, kind);
          default:  // FAILURE
            if (kind == NodeKind::SequenceWithMemory) {
              for (std::size_t i = static_cast<std::size_t>(idx); i < n.child_count; ++i) halt_child(n, i);
            } else {
              reset_children(n);
              idx = 0;
            }
            return done(Status::FAILURE);
        }
      }

      case NodeKind::Fallback:
      case NodeKind::AsyncFallback: {
        std::int32_t& idx = counter(n, 0);
        note_skipped(counter(n, 1), cs);
        switch (cs) {
          case Status::RUNNING: return done(Status::RUNNING);
          case Status::FAILURE:
            ++idx;
            if (kind == NodeKind::AsyncFallback && f.child_prev == Status::IDLE && idx < n.child_count) {
              return done(Status::RUNNING);
            }
            return sequence_next(f, n, kind);
          case Status::SKIPPED: ++idx; return sequence_next(f, n, kind);
          default:  // SUCCESS
            reset_children(n);
            idx = 0;
            return done(Status::SUCCESS);
        }
      }

      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback: {
        const bool seq = kind == NodeKind::ReactiveSequence;
        if (cs != Status::SKIPPED) f.aux = 0;
        if (cs == Status::RUNNING) {
          for (std::size_t i = 0; i < n.child_count; ++i) {
            if (i != f.pos) halt_child(n, i);
          }
          return done(Status::RUNNING);
        }
        if (cs == (seq ? Status::FAILURE : Status::SUCCESS)) {
          reset_children(n);
          return done(cs);
        }
        if (cs == Status::SKIPPED) halt_child(n, f.pos);
        if (++f.pos < n.child_count) return descend(child(n, f.pos));
        reset_children(n);
        return done(f.aux != 0 ? Status::SKIPPED : (seq ? Status::SUCCESS : Status::FAILURE));
      }

      case NodeKind::TryCatch: {
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        if (counter(n, 2) != 0) {  // the catch child finished: the node fails
          reset_children(n);
          counter(n, 0) = 0;
          counter(n, 2) = 0;
          return done(Status::FAILURE);
        }
        if (cs == Status::FAILURE) {  // into the catch child, in this tick
          reset_children(n);
          counter(n, 0) = 0;
          counter(n, 2) = 1;
          f.pos = static_cast<std::uint16_t>(n.child_count - 1);
          return descend(child(n, f.pos));
        }
        if (cs == Status::SKIPPED) ++counter(n, 1);
        ++counter(n, 0);
        return try_next(f, n);
      }

      case NodeKind::Parallel: {
        const std::uint16_t c = child(n, f.pos);
        switch (cs) {
          case Status::SKIPPED: ++f.aux; break;
          case Status::SUCCESS:
            set_done(c, true);
            ++counter(n, 0);
            break;
          case Status::FAILURE:
            set_done(c, true);
            ++counter(n, 1);
            break;
          default: break;
        }
        const Status decided = parallel_check(f, n);
        if (decided != Status::IDLE) return done(decided);
        ++f.pos;
        return parallel_next(f, n);
      }

      case NodeKind::ParallelAll: {
        const std::uint16_t c = child(n, f.pos);
        switch (cs) {
          case Status::SKIPPED: ++f.aux; break;
          case Status::SUCCESS: set_done(c, true); break;
          case Status::FAILURE:
            set_done(c, true);
            ++counter(n, 0);
            break;
          default: break;
        }
        ++f.pos;
        return parallel_all_next(f, n);
      }

      case NodeKind::IfThenElse: {
        std::int32_t& branch = counter(n, 0);
        if (f.pos == 0) {
          if (cs == Status::RUNNING) return done(Status::RUNNING);
          if (cs == Status::SUCCESS) {
            branch = 1;
          } else if (cs == Status::FAILURE && n.child_count == 3) {
            branch = 2;
          } else if (cs == Status::SKIPPED) {
            // The library throws at once (both releases): a run-time error at the condition.
            return done(skipped_condition(n));
          } else {
            return done(Status::FAILURE);  // FAILURE without an else branch
          }
          f.pos = static_cast<std::uint16_t>(branch);
          return descend(child(n, f.pos));
        }
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        reset_children(n);
        branch = 0;
        return done(cs);
      }

      case NodeKind::WhileDoElse: {
        if (f.pos == 0) {
          if (cs == Status::RUNNING) return done(Status::RUNNING);
          if (cs == Status::SUCCESS) {
            if (n.child_count == 3) halt_child(n, 2);
            f.pos = 1;
            return descend(child(n, 1));
          }
          if (cs == Status::FAILURE && n.child_count == 3) {
            halt_child(n, 1);
            f.pos = 2;
            return descend(child(n, 2));
          }
          // FAILURE with two children; a SKIPPED condition: the library resets the children,
          // then throws (its status would become IDLE), in both releases.
          reset_children(n);
          return done(cs == Status::SKIPPED ? skipped_condition(n) : Status::FAILURE);
        }
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        reset_children(n);
        return done(cs);
      }

      case NodeKind::Inverter:
        if (cs == Status::SUCCESS || cs == Status::FAILURE) {
          halt_child(n, 0);
          return done(cs == Status::SUCCESS ? Status::FAILURE : Status::SUCCESS);
        }
        return done(cs);

      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
        if (is_completed(cs)) {
          halt_child(n, 0);
          return done(kind == NodeKind::ForceSuccess ? Status::SUCCESS : Status::FAILURE);
        }
        return done(cs);

      case NodeKind::KeepRunningUntilFailure:
        if (cs == Status::FAILURE) {
          halt_child(n, 0);
          return done(Status::FAILURE);
        }
        if (cs == Status::SUCCESS) halt_child(n, 0);
        return done(Status::RUNNING);

      case NodeKind::Repeat:
      case NodeKind::RetryUntilSuccessful: {
        const bool repeat = kind == NodeKind::Repeat;
        std::int32_t& count = counter(n, 0);
        if (cs != Status::SKIPPED) counter(n, 1) = 1;
        if (cs == Status::RUNNING) return done(Status::RUNNING);
        if (cs == Status::SKIPPED) {
          halt_child(n, 0);
          return done(Status::SKIPPED);
        }
        if (cs == (repeat ? Status::FAILURE : Status::SUCCESS)) {
          count = 0;
          halt_child(n, 0);
          return done(cs);
        }
        // Another cycle (Repeat after SUCCESS, Retry after FAILURE).
        if (count < INT32_MAX) ++count;
        // From 4.7.0 (Sem::retry_rereads_attempts) num_attempts is read again after a failure;
        // a read that fails keeps the count in use.
        if constexpr (Sem::retry_rereads_attempts) {
          if (!repeat) reread_param(n);
        }
        const bool again = count < max_cycles(n) || max_cycles(n) == -1;
        halt_child(n, 0);
        if (again && f.child_prev == Status::IDLE) return done(Status::RUNNING);  // wake-up rule
        if (again) return descend(child(n, 0));
        count = 0;
        return done(repeat ? Status::SUCCESS : Status::FAILURE);
      }

      case NodeKind::RunOnce:
        if (is_completed(cs)) {
          counter(n, 0) = 1;
          counter(n, 1) = static_cast<std::int32_t>(cs);
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::Timeout:
        if (is_completed(cs)) {
          counter(n, 0) = 0;
          counter(n, 1) = 0;
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::Delay:
        if (is_completed(cs)) {
          counter(n, 0) = 0;
          halt_child(n, 0);
        }
        return done(cs);

      case NodeKind::SubTree:
        if (is_completed(cs)) halt_child(n, 0);
        return done(cs);

      case NodeKind::Switch: {
        std::int32_t& running = counter(n, 0);
        if (cs == Status::SKIPPED) {
          running = 0;
          return done(Status::SKIPPED);
        }
        if (cs == Status::RUNNING) {
          running = static_cast<std::int32_t>(f.pos) + 1;
        } else {
          reset_children(n);
          running = 0;
        }
        return done(cs);
      }

      case NodeKind::Precondition:
        if (is_completed(cs)) {
          halt_child(n, 0);
          if constexpr (Sem::precondition_if_until_started) counter(n, 0) = 0;
        }
        return done(cs);

      case NodeKind::Loop:
        counter(n, 0) = cs == Status::RUNNING ? 1 : 0;
        if (is_completed(cs)) halt_child(n, 0);
        return done(cs == Status::FAILURE ? Status::FAILURE : Status::RUNNING);

      case NodeKind::SkipUnlessUpdated:
      case NodeKind::WaitValueUpdate: counter(n, 0) = cs == Status::RUNNING ? 1 : 0; return done(cs);

      default:  // leaves have no children
        return done(cs);
    }
  }

  // What the Sequence / Fallback family remembers of a child's result for SKIPPED: 4.6.2 a
  // flag "a child did not skip" (cleared from IDLE only), 4.7.0 the children skipped in this
  // run (Sem::skipped_by_count).
  [[gnu::always_inline]] static void note_skipped(std::int32_t& c, Status cs) noexcept {
    if constexpr (Sem::skipped_by_count) {
      if (cs == Status::SKIPPED) ++c;
    } else {
      if (cs != Status::SKIPPED) c = 1;
    }
  }
  // At the end of the loop: whether the node returns SKIPPED (4.7.0 clears its count then).
  [[gnu::always_inline]] static bool all_skipped(std::int32_t& c, std::size_t children) noexcept {
    if constexpr (Sem::skipped_by_count) {
      const bool all = static_cast<std::size_t>(c) == children;
      c = 0;
      return all;
    } else {
      return c == 0;
    }
  }

  // Sequence / Fallback family: tick the child at the stored index, or end.
  // 4.6.2 returns SKIPPED when no child ticked since the node was last IDLE
  // answered anything but SKIPPED; the flag is not reset when the loop ends.
  [[gnu::always_inline]] Step sequence_next(Frame& f, const NodeInfo& n, NodeKind kind) noexcept {
    std::int32_t& idx = counter(n, 0);
    if (idx < n.child_count) {
      f.pos = static_cast<std::uint16_t>(idx);
      return descend(child(n, f.pos));
    }
    const bool skipped = all_skipped(counter(n, 1), n.child_count);
    reset_children(n);
    idx = 0;
    if (skipped) return done(Status::SKIPPED);
    return done(is_sequence(kind) ? Status::SUCCESS : Status::FAILURE);
  }

  // TryCatch: the next try child, or the end of the try block (SKIPPED when all skipped).
  Step try_next(Frame& f, const NodeInfo& n) noexcept {
    std::int32_t& idx = counter(n, 0);
    const std::size_t tries = n.child_count - 1;
    if (static_cast<std::size_t>(idx) < tries) {
      f.pos = static_cast<std::uint16_t>(idx);
      return descend(child(n, f.pos));
    }
    const bool skipped = static_cast<std::size_t>(counter(n, 1)) == tries;
    reset_children(n);
    idx = 0;
    counter(n, 1) = 0;
    return done(skipped ? Status::SKIPPED : Status::SUCCESS);
  }

  Step parallel_next(Frame& f, const NodeInfo& n) noexcept {
    while (f.pos < n.child_count) {
      const std::uint16_t c = child(n, f.pos);
      if (!is_done(c)) return descend(c);
      const Status decided = parallel_check(f, n);
      if (decided != Status::IDLE) return done(decided);
      ++f.pos;
    }
    return done(f.aux == n.child_count ? Status::SKIPPED : Status::RUNNING);
  }

  // The thresholds, checked after every child as 4.6.2 does; IDLE: undecided.
  Status parallel_check(Frame& f, const NodeInfo& n) noexcept {
    const std::int64_t successes = counter(n, 0);
    const std::int64_t failures = counter(n, 1);
    const bool read = (n.p2 & kParallelReads) != 0;  // the thresholds read this tick
    const std::int64_t required = read ? counter(n, 2) : param::success_threshold(n);
    const std::int64_t failing = read ? counter(n, 3) : param::failure_threshold(n);
    const bool relative = read ? counter(n, 4) != 0 : param::success_count_relative(n);
    Status decided = Status::IDLE;
    if (successes >= required || (relative && successes + f.aux >= required)) {
      decided = Status::SUCCESS;
    } else if (n.child_count - failures < required || failures == failing) {
      decided = Status::FAILURE;
    }
    if (decided != Status::IDLE) {
      counter(n, 0) = 0;
      counter(n, 1) = 0;
      clear_done(n);
      reset_children(n);
    }
    return decided;
  }

  Step parallel_all_next(Frame& f, const NodeInfo& n) noexcept {
    while (f.pos < n.child_count) {
      const std::uint16_t c = child(n, f.pos);
      if (!is_done(c)) return descend(c);
      ++f.pos;
    }
    if (f.aux == n.child_count) return done(Status::SKIPPED);
    std::size_t completed = 0;
    for (std::size_t i = 0; i < n.child_count; ++i) completed += is_done(child(n, i)) ? 1u : 0u;
    if (f.aux + completed < n.child_count) return done(Status::RUNNING);
    reset_children(n);
    clear_done(n);
    const Status s = counter(n, 0) >= param::max_failures(n) ? Status::FAILURE : Status::SUCCESS;
    counter(n, 0) = 0;
    return done(s);
  }
// clang-format on
