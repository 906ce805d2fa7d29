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

#include <cstddef>
#include <cstdint>

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

}  // namespace btgen
