// btgen runtime: part of class btgen::Engine, the straight-line ticks (tick_node<S>: one function
// per node shape, the compiled form of the table interpreter's state machines). Not a header of
// its own: btgen/engine.hpp includes it inside the class body (private members, as they were
// written in engine.hpp; clang-format is off because it would indent them as if at namespace
// scope).
// clang-format off
  // ------------------------------------------------------- compiled ticks
  // tick_node<S>(id) is executeTick of node `id`, whose shape is S, as
  // straight-line code: the same begin / enter / resume / finish as the
  // interpreter, with the node's kind, model, scripts, parameters and
  // children (their shapes, their offsets from `id`) known when compiling,
  // so that g++ folds every branch of other kinds away and calls its
  // children's tick_node directly. Nodes of one shape (Spec::kShape: equal
  // subtrees, e.g. the instances of one SubTree) share the function; their
  // state stays where the interpreter keeps it (status_, counters_, timers_:
  // halts and the user nodes' ChildOps read it there), found from `id` and
  // its table row. The generator gives nodes at kCompiledDepth and below a
  // shape of their own that runs on the interpreter, which also takes the
  // mission's own Controls and Decorators (their children run on the
  // explicit stack, ChildOps) and the shapes beyond the budget.
  static constexpr std::size_t kCompiledDepth = 48;  // generator/btgen/backend_cpp/shapes.py
  static constexpr bool kShaped = engine_detail::has_shapes<Spec>::value;
  static constexpr std::size_t straight_line_budget = engine_detail::straight_line_budget<Spec>::value;
  // A node's weight against the budget (1, or 6 when it runs scripts, plus its children's
  // call sites) is summed by the generator (shapes.py): Spec::kTotalWeight, kRepWeightBefore.
  // A mission whose every node fits in the budget gets a function per node
  // (a shape per node: its index and its state's places are constants, the
  // fastest form); a larger one shares the functions of equal subtrees.
  static constexpr bool per_node() noexcept {
    if constexpr (!kShaped) {
      return false;
    } else {
      return Spec::kTotalWeight <= straight_line_budget;
    }
  }
  static constexpr bool kPerNode = per_node();
  static constexpr std::uint16_t shape_of(std::size_t i) noexcept {
    if constexpr (kPerNode) {
      return static_cast<std::uint16_t>(i);
    } else {
      return Spec::kShape[i];
    }
  }
  // The first node of shape s (kNoNode: a node below the compiled depth).
  static constexpr std::uint16_t rep_of(std::uint16_t s) noexcept {
    if constexpr (kPerNode) {
      return Spec::kShapeRep[Spec::kShape[s]] == kNoNode ? kNoNode : s;
    } else {
      return Spec::kShapeRep[s];
    }
  }
  static constexpr std::size_t uses_of(std::uint16_t s) noexcept {
    if constexpr (kPerNode) {
      (void)s;
      return 1;
    } else {
      return Spec::kShapeUses[s];
    }
  }
  // The shapes first met below this index tick as straight-line code
  // (BTGEN_STRAIGHT_LINE_BUDGET counts the nodes of distinct shapes). A Spec
  // without shape tables runs on the interpreter.
  static constexpr std::size_t straight_line_nodes() noexcept {
    if constexpr (!kShaped) {
      return 0;
    } else if constexpr (kPerNode) {
      return kNodeCount;
    } else {
      // The first node of a compiled shape whose predecessors (Spec::kRepNode, in creation
      // order) weigh the budget or more: a binary search of the generator's running sums (a
      // loop over 65,535 nodes would pass clang's constant-evaluation step limit).
      std::size_t lo = 0;
      std::size_t hi = Spec::kRepNode.size();
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (Spec::kRepWeightBefore[mid] >= straight_line_budget) {
          hi = mid;
        } else {
          lo = mid + 1;
        }
      }
      return lo < Spec::kRepNode.size() ? Spec::kRepNode[lo] : kNodeCount;
    }
  }
  static constexpr std::size_t kStraightLine = straight_line_nodes();
  // Whether any node runs on the table interpreter (execute_at and its
  // stack): a shape beyond the budget or below the compiled depth, or the
  // mission's own Controls and Decorators (their children run there). When
  // none does, the interpreter's stack takes no room.
  static constexpr bool uses_interpreter() noexcept {
    if constexpr (!kShaped) {
      return true;
    } else {
      // (a catch child ticked inside a halt runs there too)
      return kStraightLine < kNodeCount || Spec::kHasDeepShape || Spec::kHasUserControlFlow || kCatchOnHalt;
    }
  }
  static constexpr bool kUsesInterpreter = uses_interpreter();
  // Children ticked through a table of member-function pointers above this
  // many (else a chain of comparisons of the position).
  static constexpr std::size_t kDirectChildren = 8;
  // Sequences and the like with more children take the generic form (clang
  // limits a fold expression to 256 operands).
  static constexpr std::size_t kInRow = 64;

  static constexpr std::uint16_t child_of(std::uint16_t n, std::size_t i) noexcept {
    return Spec::kChildren[std::size_t{Spec::kNodes[n].child_begin} + i];
  }
  // Child I of a node whose shape's first node is R: its shape, its offset
  // from the node. (The helpers below are few and shared, not one per shape
  // and child: g++'s time per straight-line shape grew with their number.)
  template <std::uint16_t R, std::size_t I>
  static constexpr std::uint16_t kChildShape = shape_of(child_of(R, I));
  template <std::uint16_t R, std::size_t I>
  static constexpr std::size_t kChildOffset = child_of(R, I) - R;
  // ControlNode::haltChild of node `c`.
  [[gnu::always_inline]] void halt_child_id(std::size_t c) noexcept {
    if (status_[c] == Status::RUNNING) halt_node(static_cast<std::uint16_t>(c));
    reset_status(c);
  }

  template <NodeKind K>
  [[gnu::always_inline]] Step begin_k(Frame& f) noexcept {
    return begin(f, K);
  }
  template <NodeKind K>
  [[gnu::always_inline]] Step resume_k(Frame& f, Status cs) noexcept {
    return resume(f, cs, K);
  }

  // Which straight-line form shape S takes.
  enum class Form { kInterpreted, kGeneric, kLeaf, kScripted, kSequence, kReactive, kDecorator };
  static constexpr bool kScriptTable = engine_detail::has_script_table<Spec>::value;
  // Leaves whose scripts (Script, ScriptCondition, pre- and post-conditions) the
  // straight-line code calls directly (Form::kScripted).
  static constexpr bool is_scripted_leaf(NodeKind k) noexcept {
    return k == NodeKind::Action || k == NodeKind::Condition || k == NodeKind::AlwaysSuccess ||
           k == NodeKind::AlwaysFailure || k == NodeKind::Script || k == NodeKind::ScriptCondition;
  }
  template <std::uint16_t S>
  static constexpr Form form() noexcept {
    constexpr std::uint16_t R = rep_of(S);
    if (R == kNoNode || R >= kStraightLine) return Form::kInterpreted;
    constexpr const NodeInfo& n = Spec::kNodes[R == kNoNode ? 0 : R];  // (row 0 unused then)
    if (n.kind == NodeKind::UserControl || n.kind == NodeKind::UserDecorator || is_nav2(n.kind)) {
      return Form::kInterpreted;
    }
    if (kScriptTable && n.child_count == 0 && is_scripted_leaf(n.kind) &&
        ((n.scripts & (kPreBits | kPostBits)) != 0 || n.kind == NodeKind::Script ||
         n.kind == NodeKind::ScriptCondition)) {
      return Form::kScripted;
    }
    if ((n.scripts & (kPreBits | kPostBits)) != 0) return Form::kGeneric;
    if (n.child_count == 0) {
      switch (n.kind) {
        case NodeKind::Action:
        case NodeKind::Condition:
        case NodeKind::AlwaysSuccess:
        case NodeKind::AlwaysFailure: return Form::kLeaf;
        default: return Form::kGeneric;
      }
    }
    if (n.child_count > kInRow) return Form::kGeneric;
    switch (n.kind) {
      case NodeKind::Sequence:
      case NodeKind::Fallback: return Form::kSequence;
      case NodeKind::ReactiveSequence:
      case NodeKind::ReactiveFallback: return Form::kReactive;
      case NodeKind::Inverter:
      case NodeKind::ForceSuccess:
      case NodeKind::ForceFailure:
      case NodeKind::SubTree: return Form::kDecorator;  // one child, ticked once
      default: return Form::kGeneric;
    }
  }

  template <std::uint16_t S>
  Status tick_node(std::size_t id) noexcept {
    constexpr Form kForm = form<S>();
    if constexpr (kForm == Form::kInterpreted) {
      return execute_at(static_cast<std::uint16_t>(id), 0);
    } else {
      constexpr std::uint16_t R = rep_of(S);
      // A shape of one node: its index, its row and its state's places are constants.
      if constexpr (uses_of(S) == 1) id = R;
      constexpr NodeKind K = Spec::kNodes[R].kind;
      using Children = std::make_index_sequence<Spec::kNodes[R].child_count>;
      if constexpr (kHooks && kForm != Form::kScripted && kForm != Form::kGeneric) {
        // (these forms have no pre- or post-conditions: the hook comes first)
        if (__builtin_expect(observer_.hooked(id), 0)) {
          const Status h = replaced(id);
          if (h != Status::IDLE) return h;
        }
      }
      if constexpr (kForm == Form::kSequence) {
        return tick_sequence<R, K == NodeKind::Sequence>(id, Children{});
      } else if constexpr (kForm == Form::kReactive) {
        return tick_reactive<R, K == NodeKind::ReactiveSequence>(id, Children{});
      } else if constexpr (kForm == Form::kDecorator) {
        // Inverter, ForceSuccess, ForceFailure, SubTree: enter, resume and finish above.
        const std::size_t c = id + kChildOffset<R, 0>;
        if constexpr (K == NodeKind::SubTree) {
          if (status_[id] == Status::IDLE) set_status(id, Status::RUNNING);
        } else {
          set_status(id, Status::RUNNING);
        }
        return decorated<K>(id, c, tick_node<kChildShape<R, 0>>(c));
      } else if constexpr (kForm == Form::kLeaf) {
        return tick_leaf<K, Spec::kNodes[R].model>(id);
      } else if constexpr (kForm == Form::kScripted) {
        return tick_scripted<R>(id);
      } else {
        Frame f{static_cast<std::uint16_t>(id), 0, 0, Status::IDLE, 0};
        Step step = begin_k<K>(f);
        while (step.child != kNoNode) {
          if constexpr (kWakeUp) f.child_prev = status_[step.child];
          const Status cs = tick_child<R>(id, f.pos, Children{});
          step = resume_k<K>(f, cs);
        }
        return finish(f, step.status);
      }
    }
  }

  // Action, Condition, AlwaysSuccess and AlwaysFailure without pre- or
  // post-conditions: enter and finish above for these kinds, the model's
  // hook called directly. (Written out, not enter and finish folded: g++
  // spent most of a straight-line node's compile time inlining the whole of
  // enter and folding it away.)
  template <NodeKind K, std::uint16_t kModel>
  [[gnu::always_inline]] Status tick_leaf(std::size_t id) noexcept {
    const Status s = post_hook(id, leaf_status<K, kModel>(id));
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }

  // What a leaf answers when its pre-conditions did not decide (enter, for these kinds).
  template <NodeKind K, std::uint16_t kModel>
  [[gnu::always_inline]] Status leaf_status(std::size_t id) noexcept {
    Status s = Status::FAILURE;
    if constexpr (K == NodeKind::AlwaysSuccess) {
      s = Status::SUCCESS;
    } else if constexpr (K == NodeKind::Action || K == NodeKind::Condition) {
      const NodeInfo& n = info(id);
      const Status st = status_[id];
      if (K == NodeKind::Action && st != Status::IDLE && st != Status::RUNNING && !Hooks::sync_action(n)) {
        s = st;
      } else {
        const std::uint64_t before = errors_;
        const ErrorSink es = sink();
        if constexpr (K == NodeKind::Condition) {
          s = guarded(Hooks::template check_m<kModel>(*leaves_, bb_, es, n), before);
        } else {
          s = guarded(st == Status::IDLE ? Hooks::template on_start_m<kModel>(*leaves_, bb_, es, n)
                                         : Hooks::template on_running_m<kModel>(*leaves_, bb_, es, n),
                      before);
        }
      }
    }
    return s;
  }

  // A leaf with scripts (Script, ScriptCondition, or pre- and post-conditions):
  // begin, enter and finish above for these kinds, every script a direct call
  // of its function (the same for every node of the shape; the node's own error
  // sites are found from `id`).
  template <std::uint16_t R>
  Status tick_scripted(std::size_t id) noexcept {
    constexpr NodeKind K = Spec::kNodes[R].kind;
    constexpr std::uint16_t kBits = Spec::kNodes[R].scripts;
    Status s = Status::IDLE;
    if constexpr ((kBits & kPreBits) != 0) s = pre_conditions_c<R>(id);
    if constexpr (kHooks) {
      if (s == Status::IDLE && __builtin_expect(observer_.hooked(id), 0)) s = forced_slow(id);
    }
    if (s == Status::IDLE) {
      if constexpr (K == NodeKind::Script) {
        s = script_c<R, ScriptSlot::kCode>(id) < 0 ? Status::FAILURE : Status::SUCCESS;
      } else if constexpr (K == NodeKind::ScriptCondition) {
        s = script_c<R, ScriptSlot::kCode>(id) == 1 ? Status::SUCCESS : Status::FAILURE;
      } else {
        s = leaf_status<K, Spec::kNodes[R].model>(id);
      }
    }
    if constexpr ((kBits & kPostBits) != 0) {
      if (is_completed(s)) {
        bool ok = true;
        if constexpr (has_c<R>(ScriptSlot::kOnSuccess)) {
          if (s == Status::SUCCESS) ok = script_c<R, ScriptSlot::kOnSuccess>(id) >= 0;
        }
        if constexpr (has_c<R>(ScriptSlot::kOnFailure)) {
          if (s == Status::FAILURE) ok = script_c<R, ScriptSlot::kOnFailure>(id) >= 0;
        }
        if constexpr (has_c<R>(ScriptSlot::kPost)) {
          if (ok) ok = script_c<R, ScriptSlot::kPost>(id) >= 0;
        }
        if (!ok) s = Status::FAILURE;
      }
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }

  template <std::uint16_t R>
  static constexpr bool has_c(ScriptSlot which) noexcept {
    return has(Spec::kNodes[R], which);
  }
  // Where node R's script for `which` sits among its sites (ScriptSlot order).
  template <std::uint16_t R, ScriptSlot W>
  static constexpr std::uint32_t site_of() noexcept {
    for (std::uint32_t i = Spec::kScriptFirst[R]; i < Spec::kScriptFirst[R + 1u]; ++i) {
      if (Spec::kScripts[i].which == W) return i - Spec::kScriptFirst[R];
    }
    return 0;
  }
  // run_script of a node of shape R (first node R): the function is a constant.
  template <std::uint16_t R, ScriptSlot W>
  [[gnu::always_inline]] int script_c(std::size_t id) noexcept {
    constexpr std::uint32_t k = site_of<R, W>();
    constexpr auto fn = Spec::kScripts[Spec::kScriptFirst[R] + k].fn;
    const ErrorSink es = sink();
    return fn(bb_, info(id), es, Spec::kScripts[Spec::kScriptFirst[id] + k]);
  }
  // pre_conditions with the node's scripts known when compiling.
  template <std::uint16_t R>
  [[gnu::always_inline]] Status pre_conditions_c(std::size_t id) noexcept {
    const Status st = status_[id];
    if (st == Status::IDLE) {
      if constexpr (has_c<R>(ScriptSlot::kFailureIf)) {
        const int r = script_c<R, ScriptSlot::kFailureIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::FAILURE;
      }
      if constexpr (has_c<R>(ScriptSlot::kSuccessIf)) {
        const int r = script_c<R, ScriptSlot::kSuccessIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::SUCCESS;
      }
      if constexpr (has_c<R>(ScriptSlot::kSkipIf)) {
        const int r = script_c<R, ScriptSlot::kSkipIf>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 1) return Status::SKIPPED;
      }
      if constexpr (has_c<R>(ScriptSlot::kWhile)) {
        const int r = script_c<R, ScriptSlot::kWhile>(id);
        if (r < 0) return Status::FAILURE;
        if (r == 0) return Status::SKIPPED;
      }
    } else if constexpr (has_c<R>(ScriptSlot::kWhile)) {
      if (st == Status::RUNNING) {
        const int r = script_c<R, ScriptSlot::kWhile>(id);
        if (r <= 0) {
          halt_node(static_cast<std::uint16_t>(id));
          return r < 0 ? Status::FAILURE : Status::SKIPPED;
        }
      }
    }
    return Status::IDLE;
  }

  // The rest of a decorator's tick once its child `c` returned `cs`.
  template <NodeKind K>
  [[gnu::always_inline]] Status decorated(std::size_t id, std::size_t c, Status cs) noexcept {
    Status s = cs;
    if (is_completed(cs)) {
      halt_child_id(c);
      if constexpr (K == NodeKind::Inverter) {
        s = cs == Status::SUCCESS ? Status::FAILURE : Status::SUCCESS;
      } else if constexpr (K == NodeKind::ForceSuccess) {
        s = Status::SUCCESS;
      } else if constexpr (K == NodeKind::ForceFailure) {
        s = Status::FAILURE;
      }
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    if (is_completed(status_[c])) reset_status(c);  // DecoratorNode::executeTick
    return s;
  }

  // Sequence (kSeq) and Fallback without pre- or post-conditions: enter,
  // resume and sequence_next above, with the children in a row: child I
  // ticks when the index points at it, and then the node either goes on or
  // returns (RUNNING, or the status that ends it: its children are reset
  // then, by one copy of the resets, not one per child).
  template <std::uint16_t R, bool kSeq, std::size_t... I>
  [[gnu::always_inline]] Status tick_sequence(std::size_t id, std::index_sequence<I...>) noexcept {
    // c[0]: the index; c[1]: a child did not skip (4.6.2), or the children skipped in this run
    // (Sem::skipped_by_count)
    std::int32_t* const c = &counters_[info(id).slot];
    if (!is_active(status_[id])) c[1] = 0;
    set_status(id, Status::RUNNING);
    Status s = Status::IDLE;
    if (!((c[0] == static_cast<std::int32_t>(I) &&
           sequence_step<kSeq>(tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), c, s)) ||
          ...)) {
      s = all_skipped(c[1], sizeof...(I)) ? Status::SKIPPED : (kSeq ? Status::SUCCESS : Status::FAILURE);
    }
    if (s != Status::RUNNING) {
      (halt_child_id(id + kChildOffset<R, I>), ...);
      c[0] = 0;
    }
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }
  // After the child at the index returned `cs`: true when the node returns `s`.
  template <bool kSeq>
  [[gnu::always_inline]] static bool sequence_step(Status cs, std::int32_t* c, Status& s) noexcept {
    note_skipped(c[1], cs);
    if (cs == Status::RUNNING) {
      s = Status::RUNNING;
      return true;
    }
    if (cs != Status::SKIPPED && cs != (kSeq ? Status::SUCCESS : Status::FAILURE)) {
      s = kSeq ? Status::FAILURE : Status::SUCCESS;
      return true;
    }
    ++c[0];
    return false;
  }

  // Every child of `n` but the one at `keep` halted (one loop, not one copy
  // per child of the reactive node: that grew as its children squared).
  [[gnu::noinline]] void halt_others(const NodeInfo& n, std::size_t keep) noexcept {
    for (std::size_t i = 0; i < n.child_count; ++i) {
      if (i != keep) halt_child(n, i);
    }
  }

  // ReactiveSequence (kSeq) and ReactiveFallback without pre- or post-conditions.
  template <std::uint16_t R, bool kSeq, std::size_t... I>
  [[gnu::always_inline]] Status tick_reactive(std::size_t id, std::index_sequence<I...>) noexcept {
    set_status(id, Status::RUNNING);
    bool all_skipped = true;
    Status s = Status::IDLE;
    if (!(reactive_step<kSeq>(tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), id, I, id + kChildOffset<R, I>,
                              all_skipped, s) ||
          ...)) {
      s = all_skipped ? Status::SKIPPED : (kSeq ? Status::SUCCESS : Status::FAILURE);
    }
    if (s != Status::RUNNING) (halt_child_id(id + kChildOffset<R, I>), ...);
    s = post_hook(id, s);
    if (s != Status::SKIPPED) set_status(id, s);
    return s;
  }
  // After child `i` (node `c`) returned `cs`: true when the node returns `s`.
  template <bool kSeq>
  [[gnu::always_inline]] bool reactive_step(Status cs, std::size_t id, std::size_t i, std::size_t c, bool& all_skipped,
                                            Status& s) noexcept {
    if (cs != Status::SKIPPED) all_skipped = false;
    if (cs == Status::RUNNING) {
      halt_others(info(id), i);
      s = Status::RUNNING;
      return true;
    }
    if (cs == (kSeq ? Status::FAILURE : Status::SUCCESS)) {
      s = cs;
      return true;
    }
    if (cs == Status::SKIPPED) halt_child_id(c);
    return false;
  }

  // The child at position `pos` of node `id` (the one begin / resume asked for).
  template <std::uint16_t R, std::size_t... I>
  [[gnu::always_inline]] Status tick_child(std::size_t id, std::size_t pos, std::index_sequence<I...>) noexcept {
    if constexpr (sizeof...(I) <= kDirectChildren) {
      Status s = Status::IDLE;
      (void)((pos == I ? (s = tick_node<kChildShape<R, I>>(id + kChildOffset<R, I>), true) : false) || ...);
      return s;
    } else {
      using Tick = Status (Engine::*)(std::size_t) noexcept;
      static constexpr Tick kTicks[] = {&Engine::template tick_node<kChildShape<R, I>>...};
      static constexpr std::uint16_t kOffsets[] = {kChildOffset<R, I>...};
      return (this->*kTicks[pos])(id + kOffsets[pos]);
    }
  }
// clang-format on
