// RECORDER, not part of btgen: runs a tests/groot2 mission under the REAL
// BehaviorTree.CPP's Groot2Publisher so that scripts/groot2_oracle/record.py can
// record its replies (the facts kept in tests/groot2/*.hooks410.json).
//
// Built by record.py against an oracle install of BehaviorTree.CPP (e.g. 4.10.0)
// plus that tag's src/loggers/groot2_publisher.cpp (the oracle is built without
// ZeroMQ; the publisher's one translation unit is compiled next to this file).
//
//   recorder MISSION.xml SCENARIO PORT     stdin: "tick" | "quit"; stdout: "ready", "tick STATUS"
//
// Leaves: every <Action> model is a stateful action whose onStart/onRunning, and
// every <Condition> model a condition whose tick, take the next word of the
// scenario's `leaf NAME ...` list for the node's name (the last word repeats;
// a name without a list gives SUCCESS), as tests/python/test_groot2.py's
// Reference does with behaviortreepy.
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/loggers/groot2_publisher.h>

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {
std::map<std::string, std::vector<std::string>> lists;
std::map<std::string, size_t> used;

BT::NodeStatus take(const std::string& name) {
  auto it = lists.find(name);
  if (it == lists.end() || it->second.empty()) return BT::NodeStatus::SUCCESS;
  size_t& n = used[name];
  const std::string& w = it->second[std::min(n, it->second.size() - 1)];
  ++n;
  return BT::convertFromString<BT::NodeStatus>(w);
}

class Scripted : public BT::StatefulActionNode {
 public:
  Scripted(const std::string& name, const BT::NodeConfig& config) : BT::StatefulActionNode(name, config) {}
  static BT::PortsList providedPorts() { return {}; }
  BT::NodeStatus onStart() override { return take(name()); }
  BT::NodeStatus onRunning() override { return take(name()); }
  void onHalted() override {}
};
}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: recorder MISSION.xml SCENARIO PORT\n";
    return 2;
  }
  std::ifstream sc(argv[2]);
  for (std::string line; std::getline(sc, line);) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::string kw, name, w;
    if (!(words >> kw) || kw != "leaf" || !(words >> name)) continue;
    while (words >> w) lists[name].push_back(w);
  }
  std::ifstream xf(argv[1]);
  std::stringstream xml;
  xml << xf.rdbuf();
  const std::string text = xml.str();

  BT::BehaviorTreeFactory factory;
  for (const char* id : {"Move", "Work"}) factory.registerNodeType<Scripted>(id);
  for (const char* id : {"IsReady", "Check"})
    factory.registerSimpleCondition(id, [](BT::TreeNode& n) { return take(n.name()); });
  auto tree = factory.createTreeFromText(text);
  BT::Groot2Publisher publisher(tree, static_cast<unsigned>(std::stoul(argv[3])));
  std::cout << "ready" << std::endl;
  for (std::string cmd; std::getline(std::cin, cmd);) {
    if (cmd == "quit") break;
    if (cmd == "tick") {
      const BT::NodeStatus s = tree.tickExactlyOnce();
      std::cout << "tick " << BT::toStr(s) << std::endl;
    }
  }
  return 0;
}
