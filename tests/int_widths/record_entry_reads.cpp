// Records what BehaviorTree.CPP's getInput<T> gives for integer ports narrower than 32 bits
// reading entries a script wrote (entry_reads.xml). Built against the oracle library:
//
//   g++ -std=c++17 record_entry_reads.cpp -I PREFIX/include -L PREFIX/lib -lbehaviortree_cpp \
//       -Wl,-rpath,PREFIX/lib -o record && ./record entry_reads.xml > entry_reads-VERSION.txt
//
// One line per node: `NAME value N` or `NAME error`.
#include <behaviortree_cpp/bt_factory.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

template <class T>
class Take : public BT::SyncActionNode {
 public:
  Take(const std::string& name, const BT::NodeConfig& config) : BT::SyncActionNode(name, config) {}
  static BT::PortsList providedPorts() { return {BT::InputPort<T>("v")}; }
  BT::NodeStatus tick() override {
    const auto v = getInput<T>("v");
    if (v) {
      std::printf("%s value %lld\n", name().c_str(), static_cast<long long>(*v));
    } else {
      std::printf("%s error\n", name().c_str());
    }
    return BT::NodeStatus::SUCCESS;
  }
};

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  BT::BehaviorTreeFactory factory;
  factory.registerNodeType<Take<uint16_t>>("U16");
  factory.registerNodeType<Take<int8_t>>("I8");
  factory.registerNodeType<Take<uint32_t>>("U32");
  std::ifstream file(argv[1]);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  auto tree = factory.createTreeFromText(text);
  return tree.tickOnce() == BT::NodeStatus::SUCCESS ? 0 : 1;
}
