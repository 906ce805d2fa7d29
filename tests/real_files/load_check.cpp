// Does the real BehaviorTree.CPP load a tree whose nodes are registered in C++ (Nav2)?
// Registers every <Action>/<Condition>/<Control>/<Decorator> of a models file as a node of
// that kind with the model's port names and directions (untyped: the C++ types of Nav2's
// ports are not in the file), then builds the file's main tree. Prints "loaded" and exits 0,
// or prints the library's exception and exits 2. Not run by the tests: it records facts.
//   g++ -std=c++17 load_check.cpp -I$PREFIX/include -L$PREFIX/lib -Wl,-rpath,$PREFIX/lib \
//       -lbehaviortree_cpp -o load_check && ./load_check MODELS.xml TREE.xml
#include <behaviortree_cpp/bt_factory.h>

#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {
struct Leaf : BT::SyncActionNode {
  Leaf(const std::string& n, const BT::NodeConfig& c) : BT::SyncActionNode(n, c) {}
  BT::NodeStatus tick() override { return BT::NodeStatus::SUCCESS; }
};
struct Cond : BT::ConditionNode {
  Cond(const std::string& n, const BT::NodeConfig& c) : BT::ConditionNode(n, c) {}
  BT::NodeStatus tick() override { return BT::NodeStatus::SUCCESS; }
};
struct Ctrl : BT::ControlNode {
  Ctrl(const std::string& n, const BT::NodeConfig& c) : BT::ControlNode(n, c) {}
  BT::NodeStatus tick() override { return BT::NodeStatus::SUCCESS; }
};
struct Deco : BT::DecoratorNode {
  Deco(const std::string& n, const BT::NodeConfig& c) : BT::DecoratorNode(n, c) {}
  BT::NodeStatus tick() override { return BT::NodeStatus::SUCCESS; }
};

template <class T>
void add(BT::BehaviorTreeFactory& f, BT::NodeType type, const std::string& id, const BT::PortsList& ports) {
  BT::TreeNodeManifest m;
  m.type = type;
  m.registration_ID = id;
  m.ports = ports;
  f.registerBuilder(m, [](const std::string& n, const BT::NodeConfig& c) { return std::make_unique<T>(n, c); });
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: load_check MODELS.xml TREE.xml\n";
    return 64;
  }
  try {
    BT::BehaviorTreeFactory factory;
    std::ifstream in(argv[1]);
    if (!in) {
      std::cerr << "cannot read " << argv[1] << "\n";
      return 64;
    }
    std::stringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    // The models file is read with a regex: the library does not export its XML parser.
    // Each <Kind ID="..."> starts a model; the port elements after it are its ports.
    const std::regex tag(
        R"re(<(Action|Condition|Control|Decorator|input_port|output_port|inout_port|bidirectional_port)\b[^>]*?(?:ID|name)="([^"]+)")re");
    struct Model {
      std::string kind, id;
      BT::PortsList ports;
    };
    std::vector<Model> list;
    for (auto it = std::sregex_iterator(s.begin(), s.end(), tag); it != std::sregex_iterator(); ++it) {
      const std::string kind = (*it)[1], name = (*it)[2];
      if (kind.find("_port") == std::string::npos)
        list.push_back({kind, name, {}});
      else if (!list.empty()) {
        const auto dir = kind == "input_port"    ? BT::PortDirection::INPUT
                         : kind == "output_port" ? BT::PortDirection::OUTPUT
                                                 : BT::PortDirection::INOUT;
        list.back().ports.emplace(name, BT::PortInfo(dir));
      }
    }
    for (const auto& m : list) {
      if (factory.builtinNodes().count(m.id) != 0) continue;  // a built-in the models file documents
      if (m.kind == "Action")
        add<Leaf>(factory, BT::NodeType::ACTION, m.id, m.ports);
      else if (m.kind == "Condition")
        add<Cond>(factory, BT::NodeType::CONDITION, m.id, m.ports);
      else if (m.kind == "Control")
        add<Ctrl>(factory, BT::NodeType::CONTROL, m.id, m.ports);
      else
        add<Deco>(factory, BT::NodeType::DECORATOR, m.id, m.ports);
    }
    auto tree = factory.createTreeFromFile(argv[2]);
    std::cout << "loaded\n";
    return 0;
  } catch (const std::exception& e) {
    std::cout << "refused: " << e.what() << "\n";
    return 2;
  }
}
