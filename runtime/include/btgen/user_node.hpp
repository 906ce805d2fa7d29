// btgen runtime: what the mission's own Controls and Decorators (declared
// in TreeNodesModel) can do with their children.
//
// The generated model class of such a node (mission header, namespace
// `control`) gives its tick() hook what BehaviorTree.CPP's ControlNode and
// DecoratorNode give their subclasses: typed ports as for leaves, and
// through a ChildOps the number of children, executeTick of child i (its
// status returned), haltChild(i), haltChildren(), a child's resetStatus(),
// the child's and the node's own status, setStatus(), name and UID. The
// engine does the bookkeeping of TreeNode::executeTick around tick()
// (pre/post conditions, the node's status from what tick() returns,
// SKIPPED keeping IDLE, a decorator's completed child reset) and of
// ControlNode::halt()/DecoratorNode::halt() around the optional halt() hook
// (children halted first, then the hook, then the node IDLE).
//
// Children run on the engine's fixed stack: no allocation, no recursion
// beyond the tree's depth.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "btgen/blackboard.hpp"
#include "btgen/hooks.hpp"
#include "btgen/node.hpp"
#include "btgen/status.hpp"

namespace btgen {

// Function table an Engine fills in once per mission type (static storage).
struct ChildOpsTable {
  Status (*tick_child)(void* engine, const NodeInfo& n, std::size_t i, std::size_t base) noexcept;
  void (*halt_child)(void* engine, const NodeInfo& n, std::size_t i) noexcept;
  void (*reset_child_status)(void* engine, const NodeInfo& n, std::size_t i) noexcept;
  Status (*child_status)(const void* engine, const NodeInfo& n, std::size_t i) noexcept;
  Status (*status)(const void* engine, std::uint16_t node) noexcept;
  void (*set_status)(void* engine, std::uint16_t node, Status s) noexcept;
  std::uint64_t (*now_ms)(void* engine) noexcept;
};

// The children of one user Control/Decorator being ticked or halted.
class ChildOps {
 public:
  constexpr ChildOps(const ChildOpsTable* table, void* engine, const NodeInfo* node, std::size_t base) noexcept
      : table_(table), engine_(engine), node_(node), base_(base) {}

  [[nodiscard]] std::size_t children_count() const noexcept { return node_->child_count; }
  // executeTick() of child i: its status (SKIPPED included).
  Status tick_child(std::size_t i) const noexcept { return table_->tick_child(engine_, *node_, i, base_); }
  // ControlNode::haltChild(i) / DecoratorNode::resetChild(): halted if
  // RUNNING, then IDLE.
  void halt_child(std::size_t i) const noexcept { table_->halt_child(engine_, *node_, i); }
  // ControlNode::haltChildren() (resetChildren()).
  void halt_children() const noexcept {
    for (std::size_t i = 0; i < node_->child_count; ++i) halt_child(i);
  }
  // child(i)->resetStatus(): IDLE without halting.
  void reset_child_status(std::size_t i) const noexcept { table_->reset_child_status(engine_, *node_, i); }
  [[nodiscard]] Status child_status(std::size_t i) const noexcept { return table_->child_status(engine_, *node_, i); }
  // The node's own status (IDLE on its first tick), and setStatus().
  [[nodiscard]] Status status() const noexcept { return table_->status(engine_, node_->index); }
  void set_status(Status s) const noexcept { table_->set_status(engine_, node_->index, s); }
  // The mission clock, in milliseconds (for rate and time based nodes).
  [[nodiscard]] std::uint64_t now_ms() const noexcept { return table_->now_ms(engine_); }
  [[nodiscard]] const NodeInfo& node() const noexcept { return *node_; }

 private:
  const ChildOpsTable* table_;
  void* engine_;
  const NodeInfo* node_;
  std::size_t base_;
};

// What every generated model class (namespace `leaf` of a mission header) has,
// whatever its ports: the node instance being run, the mission's blackboard and
// the reporting of errors. The model class adds its id, its number and its typed
// port accessors, which read bb_, err_ and node_.
template <class Blackboard, LeafKind K>
class ModelBase {
 public:
  static constexpr LeafKind kKind = K;

  ModelBase(Blackboard& bb, const ErrorSink& err, const NodeInfo& node) noexcept : bb_(&bb), err_(err), node_(&node) {}

  // The node instance being run, and the mission's blackboard.
  [[nodiscard]] const NodeInfo& node() const noexcept { return *node_; }
  [[nodiscard]] Blackboard& blackboard() const noexcept { return *bb_; }

  // Reports a run-time error of this node (btgen::RuntimeError, at the
  // node's position; `message` must outlive the call) and returns FAILURE:
  // the node fails whatever the hook then returns.
  Status fail(std::string_view message) const noexcept {
    (void)err_.fail(*node_, node_->source, message);
    return Status::FAILURE;
  }
  // (scenario runners) The setter of the queue port named `n`: a model with queue ports
  // has its own (btgen/queue_view.hpp); false: no such port.
  template <class T>
  bool set_queue_port(std::string_view n, const T& value) const noexcept {
    (void)n;
    (void)value;
    return false;
  }
  // (Actions) A SyncActionNode's tick() result as the engine takes it: RUNNING
  // is reported as an error and fails the node.
  template <LeafKind L = K, std::enable_if_t<L == LeafKind::Action, int> = 0>
  [[nodiscard]] Status sync_result(Status s) const noexcept {
    return btgen::sync_result(s, err_, *node_);
  }

 protected:
  Blackboard* bb_;
  ErrorSink err_;
  const NodeInfo* node_;
};

// The message of an Action the virtual Leaves class of a mission (<Mission>Leaves)
// runs without an override: "Action <ID> has no implementation: override tick() or
// onStart/onRunning/onHalted", put together when compiling.
template <class Model>
struct NoImplementation {
  static constexpr std::string_view kHead = "Action ";
  static constexpr std::string_view kTail = " has no implementation: override tick() or onStart/onRunning/onHalted";
  static constexpr std::size_t kSize = kHead.size() + Model::kId.size() + kTail.size();
  static constexpr std::array<char, kSize> kText = [] {
    std::array<char, kSize> text{};
    std::size_t i = 0;
    for (const std::string_view part : {kHead, Model::kId, kTail}) {
      for (const char c : part) text[i++] = c;
    }
    return text;
  }();
};

// What the virtual Leaves class's tick() does for an Action nothing overrides: the
// node fails with that message.
template <class Model>
Status no_implementation(const Model& model) noexcept {
  return model.fail(std::string_view(NoImplementation<Model>::kText.data(), NoImplementation<Model>::kSize));
}

// A model class of the mission's own Controls and Decorators: what
// BT::ControlNode and BT::DecoratorNode give their subclasses, through ChildOps.
template <class Blackboard, LeafKind K>
class ControlModelBase : public ModelBase<Blackboard, K> {
 public:
  ControlModelBase(Blackboard& bb, const ErrorSink& err, const NodeInfo& node, const ChildOps& ops) noexcept
      : ModelBase<Blackboard, K>(bb, err, node), ops_(ops) {}

  [[nodiscard]] std::size_t children_count() const noexcept { return ops_.children_count(); }
  Status tick_child(std::size_t i) const noexcept { return ops_.tick_child(i); }
  void halt_child(std::size_t i) const noexcept { ops_.halt_child(i); }
  void halt_children() const noexcept { ops_.halt_children(); }
  void reset_child_status(std::size_t i) const noexcept { ops_.reset_child_status(i); }
  [[nodiscard]] Status child_status(std::size_t i) const noexcept { return ops_.child_status(i); }
  [[nodiscard]] Status status() const noexcept { return ops_.status(); }
  void set_status(Status s) const noexcept { ops_.set_status(s); }
  [[nodiscard]] std::uint64_t now_ms() const noexcept { return ops_.now_ms(); }
  [[nodiscard]] std::string_view name() const noexcept { return this->node_->name; }
  [[nodiscard]] std::uint16_t uid() const noexcept { return this->node_->uid; }

 private:
  ChildOps ops_;
};

}  // namespace btgen
