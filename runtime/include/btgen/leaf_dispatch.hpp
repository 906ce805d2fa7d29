// btgen runtime: the calls of the robot's leaf hooks, the same for every mission.
//
// A generated mission header gives its Spec, about its leaf models (namespace
// `leaf`):
//
//   template <std::uint16_t M> using Model = ...;   the model class numbered M
//   template <class Hook, class... Args>
//   static constexpr decltype(auto) visit_action(std::uint16_t model, Args&... args);
//     a switch over the numbers of the Action models: returns
//     Hook::template call<that model class>(args...), or Hook::template
//     call<void>(args...) for any other number; visit_condition the same over
//     the Conditions, and visit_user_node over the Controls and Decorators a
//     node uses (the others' hooks are never called, so Leaves need not have
//     them).
//
// LeafHooks has the hooks as such Hook types, and the engine's calls: by a
// model number known when compiling (the straight-line code: a direct call,
// nothing to dispatch) or by the node's model (the table interpreter and the
// halts: through the switch). The header lists its models; the calls are here.
#pragma once

#include <cstdint>
#include <type_traits>

#include "btgen/blackboard.hpp"
#include "btgen/hooks.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"
#include "btgen/user_node.hpp"

namespace btgen {

// Whether `Model` (a model class, or void for none) is of kind K.
template <class Model, LeafKind K>
[[nodiscard]] constexpr bool model_is() noexcept {
  if constexpr (std::is_void_v<Model>) {
    return false;
  } else {
    return Model::kKind == K;
  }
}

template <class Spec, class Leaves>
struct LeafHooks {
  using Blackboard = typename Spec::Blackboard;
  template <std::uint16_t M>
  using Model = typename Spec::template Model<M>;

  // ---- each hook for one model class (void, or a model of another kind: FAILURE, or
  // nothing done). Model is a template parameter, so what a Leaves lacks for a model
  // of another kind is never looked up. A hook Leaves lacks is never called here either:
  // the mission class has already said which one (BTGEN_ACTION_HOOKS, btgen/hooks.hpp);
  // the static_asserts below are a second line for a Spec without those checks, and no
  // call of a missing hook adds template errors after that sentence.

  // A StatefulActionNode's onStart, or a SyncActionNode's tick().
  struct OnStart {
    template <class M>
    static Status call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
      if constexpr (model_is<M, LeafKind::Action>()) {
        static_assert(has_action_hooks<Leaves, M>,
                      "Leaves implements neither tick() nor onStart/onRunning/onHalted for an Action model "
                      "(the model class is named in the instantiation above this line)");
        if constexpr (!has_action_hooks<Leaves, M>) {
          (void)leaves, (void)bb, (void)err, (void)node;
          return Status::FAILURE;
        } else {
          M model(bb, err, node);
          if constexpr (is_sync_action<Leaves, M>) {
            return model.sync_result(leaves.tick(model, node));
          } else {
            return leaves.onStart(model, node);
          }
        }
      } else {
        (void)leaves, (void)bb, (void)err, (void)node;
        return Status::FAILURE;
      }
    }
  };

  // onRunning, or tick() again (a SyncActionNode ticked before its parent reset it).
  struct OnRunning {
    template <class M>
    static Status call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
      if constexpr (model_is<M, LeafKind::Action>() && has_action_hooks<Leaves, M>) {
        static_assert(is_sync_action<Leaves, M> || has_on_running_hook<Leaves, M>,
                      "Leaves has onStart but no onRunning for an Action model (named in the instantiation above)");
        M model(bb, err, node);
        if constexpr (is_sync_action<Leaves, M>) {
          return model.sync_result(leaves.tick(model, node));
        } else if constexpr (has_on_running_hook<Leaves, M>) {
          return leaves.onRunning(model, node);
        } else {
          return Status::FAILURE;
        }
      } else {
        (void)leaves, (void)bb, (void)err, (void)node;
        return Status::FAILURE;
      }
    }
  };

  // Whether M is an Action that Leaves implements as a SyncActionNode (tick()
  // alone): it ticks again whatever its status, as 4.6.2's does, and has no onHalted.
  struct IsSync {
    template <class M>
    static constexpr bool call() noexcept {
      if constexpr (model_is<M, LeafKind::Action>()) {
        return is_sync_action<Leaves, M>;
      } else {
        return false;
      }
    }
  };

  struct OnHalted {
    template <class M>
    static void call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
      if constexpr (model_is<M, LeafKind::Action>() && !IsSync::template call<M>() && has_action_hooks<Leaves, M>) {
        static_assert(has_on_halted_hook<Leaves, M>,
                      "Leaves has onStart but no onHalted for an Action model (named in the instantiation above)");
        if constexpr (has_on_halted_hook<Leaves, M>) {
          M model(bb, err, node);
          leaves.onHalted(model, node);
        } else {
          (void)leaves, (void)bb, (void)err, (void)node;
        }
      } else {
        (void)leaves, (void)bb, (void)err, (void)node;
      }
    }
  };

  struct Check {
    template <class M>
    static Status call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
      if constexpr (model_is<M, LeafKind::Condition>()) {
        static_assert(has_check_hook<Leaves, M>,
                      "Leaves has no check() for a Condition model (named in the instantiation above)");
        if constexpr (has_check_hook<Leaves, M>) {
          M model(bb, err, node);
          return leaves.check(model, node);
        } else {
          (void)leaves, (void)bb, (void)err, (void)node;
          return Status::FAILURE;
        }
      } else {
        (void)leaves, (void)bb, (void)err, (void)node;
        return Status::FAILURE;
      }
    }
  };

  // The mission's own Controls and Decorators: tick() and the optional halt().
  template <class M>
  static constexpr bool user_node() noexcept {
    return model_is<M, LeafKind::Control>() || model_is<M, LeafKind::Decorator>();
  }

  struct UserTick {
    template <class M>
    static Status call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node,
                       const ChildOps& ops) {
      if constexpr (user_node<M>()) {
        static_assert(has_tick_hook<Leaves, M>,
                      "Leaves has no tick() for a Control or Decorator model (named in the instantiation above)");
        if constexpr (has_tick_hook<Leaves, M>) {
          M model(bb, err, node, ops);
          return leaves.tick(model, node);
        } else {
          (void)leaves, (void)bb, (void)err, (void)node, (void)ops;
          return Status::FAILURE;
        }
      } else {
        (void)leaves, (void)bb, (void)err, (void)node, (void)ops;
        return Status::FAILURE;
      }
    }
  };

  struct UserHalt {
    template <class M>
    static void call(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node, const ChildOps& ops) {
      if constexpr (user_node<M>() && has_halt_hook<Leaves, M>) {
        M model(bb, err, node, ops);
        leaves.halt(model, node);
      } else {
        (void)leaves, (void)bb, (void)err, (void)node, (void)ops;
      }
    }
  };

  // ---- the straight-line code's calls: the model by its number M, a constant

  template <std::uint16_t M>
  static Status on_start_m(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return OnStart::template call<Model<M>>(leaves, bb, err, node);
  }
  template <std::uint16_t M>
  static Status on_running_m(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return OnRunning::template call<Model<M>>(leaves, bb, err, node);
  }
  template <std::uint16_t M>
  static Status check_m(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return Check::template call<Model<M>>(leaves, bb, err, node);
  }

  // ---- the table interpreter's and the halts' calls: the node's model, through the
  // mission's switch of the hook's kind

  static Status on_start(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return Spec::template visit_action<OnStart>(node.model, leaves, bb, err, node);
  }
  static Status on_running(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return Spec::template visit_action<OnRunning>(node.model, leaves, bb, err, node);
  }
  static void on_halted(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    Spec::template visit_action<OnHalted>(node.model, leaves, bb, err, node);
  }
  static constexpr bool sync_action(const NodeInfo& node) noexcept {
    return Spec::template visit_action<IsSync>(node.model);
  }
  static Status check(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node) {
    return Spec::template visit_condition<Check>(node.model, leaves, bb, err, node);
  }
  static Status user_tick(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node,
                          const ChildOps& ops) {
    return Spec::template visit_user_node<UserTick>(node.model, leaves, bb, err, node, ops);
  }
  static void user_halt(Leaves& leaves, Blackboard& bb, const ErrorSink& err, const NodeInfo& node,
                        const ChildOps& ops) {
    Spec::template visit_user_node<UserHalt>(node.model, leaves, bb, err, node, ops);
  }
};

}  // namespace btgen
