// btgen runtime: what btgen::Engine asks of a generated mission's Spec (the requirements,
// and the traits that read its optional parts), and how much of it ticks as straight-line
// code (BTGEN_STRAIGHT_LINE_BUDGET). btgen/engine.hpp includes it.
#pragma once

#include <cstddef>
#include <type_traits>
#include <utility>

#include "btgen/blackboard.hpp"
#include "btgen/node.hpp"

// How much of a mission ticks as straight-line code (Engine::tick_node):
// the shapes first met in creation order (the root and the part of the tree
// drawn first) while the weights of the shapes before them add up to less
// than this, a shape weighing 1 (6 when it runs scripts) plus its children;
// a node of a shape met before is free (its code is shared). 0: none. The
// others run on the table interpreter.
// Straight line costs 6 to 18 instructions per visited node instead of 78,
// and g++ -O2 some milliseconds per distinct node instead of almost
// nothing: the budget keeps the build of a large mission fast. A Spec may set its own
// (`static constexpr std::size_t kStraightLineBudget`; 0: all interpreted).
#ifndef BTGEN_STRAIGHT_LINE_BUDGET
#define BTGEN_STRAIGHT_LINE_BUDGET 1000
#endif

namespace btgen {

namespace engine_detail {
template <class O, class = void>
struct has_on_error : std::false_type {};
template <class O>
struct has_on_error<O, std::void_t<decltype(std::declval<O&>().on_error(std::declval<const RuntimeError&>()))>>
    : std::true_type {};
// An observer that may force a node's status (btgen::MonitorObserver: Groot2's REPLACE hooks).
template <class O, class = void>
struct has_forced_status : std::false_type {};
template <class O>
struct has_forced_status<O, std::void_t<decltype(std::declval<O&>().forced_status(std::declval<const NodeInfo&>()))>>
    : std::true_type {};
// An observer that may also force a node's result after its tick (4.10.0's POST hooks).
template <class O, class = void>
struct has_post_forced_status : std::false_type {};
template <class O>
struct has_post_forced_status<
    O, std::void_t<decltype(std::declval<O&>().post_forced_status(std::declval<const NodeInfo&>()))>> : std::true_type {
};
template <class S, class = void>
struct straight_line_budget : std::integral_constant<std::size_t, BTGEN_STRAIGHT_LINE_BUDGET> {};
template <class S>
struct straight_line_budget<S, std::void_t<decltype(S::kStraightLineBudget)>>
    : std::integral_constant<std::size_t, S::kStraightLineBudget> {};
// A Spec with shape tables (Spec::kShape, kShapeRep: straight-line code shared by equal subtrees).
template <class S, class = void>
struct has_shapes : std::false_type {};
template <class S>
struct has_shapes<S, std::void_t<decltype(S::kShape), decltype(S::kShapeRep), decltype(S::kShapeUses),
                                 decltype(S::kTotalWeight), decltype(S::kRepNode), decltype(S::kRepWeightBefore),
                                 decltype(S::kHasDeepShape), decltype(S::kHasUserControlFlow)>> : std::true_type {};
// A Spec with a table of compiled scripts (Spec::kScripts, each a function and its node's
// error sites; kScriptFirst[i] is node i's first): straight-line code calls them directly.
template <class S, class = void>
struct has_script_table : std::false_type {};
template <class S>
struct has_script_table<S, std::void_t<decltype(S::kScripts), decltype(S::kScriptFirst)>> : std::true_type {};
// A Spec whose mission has a Nav2 PersistentSequence writing its place into an entry.
template <class S, class = void>
struct has_write_index : std::false_type {};
template <class S>
struct has_write_index<
    S, std::void_t<decltype(S::write_index(std::declval<typename S::Blackboard&>(), std::declval<const ErrorSink&>(),
                                           std::declval<const NodeInfo&>(), std::int64_t{}))>> : std::true_type {};
// A Spec with literals of user port types to convert at construction (btgen/user_type.hpp).
template <class S, class = void>
struct has_init : std::false_type {};
template <class S>
struct has_init<
    S, std::void_t<decltype(S::init(std::declval<typename S::Blackboard&>(), std::declval<const ErrorSink&>()))>>
    : std::true_type {};
}  // namespace engine_detail

// Spec requirements (the generator writes them):
//   static constexpr std::size_t kNodeCount, kChildCount, kCounterCount,
//                                kTimerCount, kMaxDepth;
//   static constexpr bool kHasParallel;
//   static constexpr std::array<NodeInfo, kNodeCount> kNodes;
//   static constexpr std::array<std::uint16_t, kChildCount> kChildren;
//   static constexpr std::array<std::uint16_t, kNodeCount> kShape;     // node -> its shape
//   static constexpr std::array<std::uint16_t, kShapeCount> kShapeRep; // shape -> first node (kNoNode: interpreted)
//   static constexpr std::array<std::uint32_t, kShapeCount> kShapeUses;  // shape -> its nodes
//   static constexpr std::size_t kTotalWeight;                          // all nodes' weights
//   static constexpr std::array<std::uint16_t, R> kRepNode;             // first node of each shape
//   static constexpr std::array<std::uint32_t, R> kRepWeightBefore;     // weight of the ones before
//   static constexpr bool kHasDeepShape, kHasUserControlFlow;
//     (without the shape tables every node runs on the interpreter)
//   struct Blackboard;  (default-constructible: the entries as the tree is built)
//   using BB = Blackboard; using ES = const ErrorSink;
//   template <std::uint16_t M> using Model;   // the leaf model class numbered M
//   template <class H, class... A> static constexpr decltype(auto) visit_action(std::uint16_t, A&...);
//     (and visit_condition, visit_user_node: H::call<the model class of that number>(A...);
//     btgen/leaf_dispatch.hpp's LeafHooks calls the hooks through these)
//   static int script(BB&, const NodeInfo&, ES&, ScriptSlot);   // 1/0 (truth), -1 error
//   static Status data_leaf(BB&, const NodeInfo&, ES&);        // SetBlackboard, UnsetBlackboard
//   static std::int64_t entry_seq(const BB&, const NodeInfo&); // update counter; -1: no entry
//   static int read_param(const BB&, const ErrorSink&, const NodeInfo&, std::int64_t&);  // {key} counts
//   static int switch_case(const BB&, const NodeInfo&);        // child to tick (the last: default)
//   static int loop_pop(BB&, const NodeInfo&, ES&, bool restart);  // 1 popped, 0 empty, -1 error
// and, optionally (missions with literals of user port types),
//   static void init(BB&, ES&);  // converts them, once, in the constructor; reports failures

}  // namespace btgen
