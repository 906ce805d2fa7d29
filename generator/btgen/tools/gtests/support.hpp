// Written by `btgen tests`: scripted leaves and a status-change recorder for BehaviorTree.CPP.
// Tick-exact: no timers, threads or sleeps; each leaf answers from its test's script.
#pragma once

#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/loggers/abstract_logger.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace btgen_tests
{
using BT::NodeStatus;

// What each leaf name returns, call by call; once a list is used up its last status repeats,
// and a leaf with no list returns SUCCESS (btgen's scenario files, FORMAT.md).
struct Script
{
  std::map<std::string, std::vector<NodeStatus>> lists;
  std::map<std::string, std::size_t> used;

  NodeStatus next(const std::string& name)
  {
    auto it = lists.find(name);
    if(it == lists.end() || it->second.empty())
      return NodeStatus::SUCCESS;
    std::size_t& k = used[name];
    NodeStatus s = it->second[std::min(k, it->second.size() - 1)];
    if(k < it->second.size())
      ++k;
    return s;
  }
};

// An Action takes its next status in onStart (ticked while IDLE) and onRunning (ticked while RUNNING).
class ScriptedAction : public BT::StatefulActionNode
{
public:
  ScriptedAction(const std::string& name, const BT::NodeConfig& cfg, Script* script)
    : StatefulActionNode(name, cfg), script_(script)
  {}
  NodeStatus onStart() override { return script_->next(name()); }
  NodeStatus onRunning() override { return script_->next(name()); }
  void onHalted() override {}

private:
  Script* script_;
};

// A Condition takes its next status at every tick.
class ScriptedCondition : public BT::ConditionNode
{
public:
  ScriptedCondition(const std::string& name, const BT::NodeConfig& cfg, Script* script)
    : ConditionNode(name, cfg), script_(script)
  {}
  NodeStatus tick() override
  {
    NodeStatus s = script_->next(name());
    if(s == NodeStatus::RUNNING)
    {
      ADD_FAILURE() << "Condition " << name() << " scripted RUNNING";
      return NodeStatus::FAILURE;
    }
    return s;
  }

private:
  Script* script_;
};

inline const char* statusName(NodeStatus s)
{
  switch(s)
  {
    case NodeStatus::IDLE: return "IDLE";
    case NodeStatus::RUNNING: return "RUNNING";
    case NodeStatus::SUCCESS: return "SUCCESS";
    case NodeStatus::FAILURE: return "FAILURE";
    case NodeStatus::SKIPPED: return "SKIPPED";
  }
  return "?";
}

// A node name between double quotes: \" \\ \n \r \t, \xHH for other control bytes.
inline std::string quoted(const std::string& s)
{
  std::string out = "\"";
  for(unsigned char c : s)
  {
    if(c == '"' || c == '\\')
    {
      out += '\\';
      out += char(c);
    }
    else if(c == '\n')
      out += "\\n";
    else if(c == '\r')
      out += "\\r";
    else if(c == '\t')
      out += "\\t";
    else if(c < 0x20 || c == 0x7F)
    {
      char buf[5];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
    else
      out += char(c);
  }
  return out + "\"";
}

// Every status change of every node, in order, transitions to IDLE included.
class Recorder : public BT::StatusChangeLogger
{
public:
  Recorder(BT::TreeNode* root, std::vector<std::string>* lines)
    : StatusChangeLogger(root), lines_(lines)
  {
    enableTransitionToIdle(true);
  }
  void callback(BT::Duration, const BT::TreeNode& node, NodeStatus from, NodeStatus to) override
  {
    lines_->push_back(std::to_string(node.UID()) + ' ' + node.registrationName() + ' ' +
                      quoted(node.name()) + ' ' + statusName(from) + " -> " + statusName(to));
  }
  void flush() override {}

private:
  std::vector<std::string>* lines_;
};

// The script of the test that runs (for the project's nodes that read a fact of the world).
inline Script*& currentScript()
{
  static Script* script = nullptr;
  return script;
}

// A scenario input of a node the project registers (`leaf NAME SUCCESS|FAILURE` in the
// scenario, yes/no call by call, as btgen's engines read it): the next answer for node NAME.
inline bool scriptedInput(const std::string& name)
{
  return currentScript() != nullptr && currentScript()->next(name) == NodeStatus::SUCCESS;
}

// The project's own nodes (`btgen tests --register FILE.cpp`, or the CMake list
// BTGEN_REGISTER): a registration file compiled into the suite adds a Hook,
//   static btgen_tests::AddHook mine({&registerMyNodes, nullptr, nullptr});
// nodes(factory) runs before the scripted leaves are registered, blackboard(bb) on the root
// blackboard before the tree is created (entries the nodes' constructors read), and tree(t)
// after it is created. Shared libraries of BT_REGISTER_NODES plugins (the CMake list
// BTGEN_PLUGINS) are loaded with registerFromPlugin before the hooks run.
struct Hook
{
  void (*nodes)(BT::BehaviorTreeFactory&);
  void (*blackboard)(BT::Blackboard&);
  void (*tree)(BT::Tree&);
};
inline std::vector<Hook>& hooks()
{
  static std::vector<Hook> all;
  return all;
}
struct AddHook
{
  explicit AddHook(Hook hook) { hooks().push_back(hook); }
};

struct Leaf
{
  const char* id;
  bool condition;
  std::vector<std::pair<BT::PortDirection, const char*>> ports;
};

// Registers the scripted leaves, creates the tree from the mission file, ticks it with
// tickExactlyOnce() up to `ticks` times (stopping when the root completes), and checks the
// status changes and the root's results against `expected` (`tick N`, the changes, `result S`).
// (static: a registration file includes this header too, without the test file's macros)
static inline void runAndCheck(const std::vector<Leaf>& leaves, Script script, int ticks,
                        const std::vector<std::string>& expected)
{
  currentScript() = &script;
  struct Reset
  {
    ~Reset() { currentScript() = nullptr; }
  } reset;
  BT::BehaviorTreeFactory factory;
#ifdef BTGEN_PLUGINS_FILE
  // the plugins of BTGEN_PLUGINS (CMake), as the application loads them
  for(const char* plugin : std::initializer_list<const char*>{
#include BTGEN_PLUGINS_FILE
      })
    factory.registerFromPlugin(plugin);
#endif
  for(const Hook& hook : hooks())
    if(hook.nodes != nullptr)
      hook.nodes(factory);
  for(const Leaf& leaf : leaves)
  {
    BT::PortsList ports;
    for(const auto& [direction, name] : leaf.ports)
      ports.insert(BT::CreatePort(direction, name));
    if(leaf.condition)
      factory.registerNodeType<ScriptedCondition>(leaf.id, ports, &script);
    else
      factory.registerNodeType<ScriptedAction>(leaf.id, ports, &script);
  }
#ifdef BTGEN_ENUMS
  // the scripting enums of --enum / --enums, as the application registers them
  for(const auto& [name, value] : std::initializer_list<std::pair<const char*, int>> BTGEN_ENUMS)
    factory.registerScriptingEnum(name, value);
#endif
#ifdef BTGEN_TREES
  // the tree libraries of --trees (relative to the suite's folder, or absolute), registered
  // before the mission as the application registers them
  for(const char* file : std::initializer_list<const char*> BTGEN_TREES)
    factory.registerBehaviorTreeFromFile(std::filesystem::path(BTGEN_SOURCE_DIR) / file);
#endif
  BT::Blackboard::Ptr blackboard = BT::Blackboard::create();
#ifdef BTGEN_ENTRIES
  // the entries of --entry, created before the tree as the application creates them
  BTGEN_ENTRIES(*blackboard);
#endif
  for(const Hook& hook : hooks())
    if(hook.blackboard != nullptr)
      hook.blackboard(*blackboard);
#ifdef BTGEN_MAIN_TREE
  factory.registerBehaviorTreeFromFile(BTGEN_MISSION);
  BT::Tree tree = factory.createTree(BTGEN_MAIN_TREE, blackboard);
#else
  BT::Tree tree = factory.createTreeFromFile(BTGEN_MISSION, blackboard);
#endif
  for(const Hook& hook : hooks())
    if(hook.tree != nullptr)
      hook.tree(tree);
  std::vector<std::string> lines;
  std::vector<std::string> results;
  Recorder recorder(tree.rootNode(), &lines);
  for(int n = 1; n <= ticks; ++n)
  {
    lines.push_back("tick " + std::to_string(n));
    NodeStatus result;
    try
    {
      result = tree.tickExactlyOnce();
    }
    catch(const std::exception& e)
    {
      // a run-time error ends the run (btgen's engines stop there too): `error`, then the checks
      lines.push_back("error");
      std::printf("the tree threw: %s\n", e.what());
      break;
    }
    lines.push_back(std::string("result ") + statusName(result));
    results.push_back(statusName(result));
    if(result == NodeStatus::SUCCESS || result == NodeStatus::FAILURE)
      break;
  }
  recorder.setEnabled(false);  // the tree's destructor halts it: not part of the run

  std::vector<std::string> expectedResults;
  for(const std::string& line : expected)
    if(line.rfind("result ", 0) == 0)
      expectedResults.push_back(line.substr(7));
  EXPECT_EQ(results, expectedResults) << "the root's results, tick by tick";
  const std::size_t n = std::min(lines.size(), expected.size());
  for(std::size_t i = 0; i < n; ++i)
    if(lines[i] != expected[i])
    {
      ADD_FAILURE() << "status change " << i + 1 << " of " << expected.size()
                    << " differs:\n  expected: " << expected[i] << "\n  actual:   " << lines[i];
      return;
    }
  EXPECT_EQ(lines.size(), expected.size())
      << "the run recorded " << lines.size() << " lines, the expectation has " << expected.size()
      << (lines.size() > n ? "; first extra: " + lines[n] : std::string())
      << (expected.size() > n ? "; first missing: " + expected[n] : std::string());
}
// The expected lines as a static array of C strings (quick to compile, however many there are).
template <std::size_t N>
static void runAndCheck(const std::vector<Leaf>& leaves, Script script, int ticks,
                 const char* const (&expected)[N])
{
  runAndCheck(leaves, std::move(script), ticks, std::vector<std::string>(expected, expected + N));
}
}  // namespace btgen_tests
