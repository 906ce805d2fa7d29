// Oracle harness: runs a BehaviorTree.CPP v4 mission on the real library and prints
// the canonical status trace of shared/conformance/FORMAT.md, or benchmarks ticking.
//
// btgen's copy of the shared oracle harness (../shared/oracle/harness.cpp) with queue ports:
// a model port declared BT::SharedQueue<T> / std::shared_ptr<std::deque<T>> (T: int, double,
// bool, std::string) is registered with that type, and a scenario line
//   queue NAME PORT ITEM ...
// makes every run of leaf NAME's code (onStart, onRunning, a Condition's tick) first
// setOutput(PORT, a new SharedQueue<T> of the items, each convertFromString<T>). The port of a
// leaf declared nowhere that a `queue` line names is registered as an inout
// SharedQueue<std::string>, as the C++ nodes of tests/real_files/queue_project declare it.
//
//   harness trace MISSION.xml SCENARIO.scenario   trace on stdout
//   harness bench MISSION.xml N                   N x tickExactlyOnce() with trivial leaves
//
// Errors (bad XML, bad scenario, a Condition scripted RUNNING): message on stderr, exit 2.
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/loggers/abstract_logger.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <deque>
#include <memory>
#include <stdexcept>
#include <thread>
#include <typeindex>

// ---------------------------------------------------------------- heap counting
static std::atomic<unsigned long long> g_allocs{ 0 };

void* operator new(std::size_t n)
{
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  if(void* p = std::malloc(n ? n : 1))
    return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a)
{
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  std::size_t al = static_cast<std::size_t>(a);
  if(void* p = std::aligned_alloc(al, (n + al - 1) / al * al))
    return p;
  throw std::bad_alloc();
}
#pragma GCC diagnostic push  // GCC 12 misreads free() in a replaced operator delete
#pragma GCC diagnostic ignored "-Wpragmas"
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace
{
using BT::NodeStatus;

struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

// ---------------------------------------------------------------- minimal XML reader
// Only what the harness needs from the mission: element names, attributes, nesting.
// BehaviorTree.CPP (tinyxml2) parses the file again and stays the authority on syntax.
struct Elem
{
  std::string tag;
  std::map<std::string, std::string> attr;
  std::vector<Elem> kids;
  const std::string* get(const std::string& k) const
  {
    auto it = attr.find(k);
    return it == attr.end() ? nullptr : &it->second;
  }
};

std::string decodeEntities(const std::string& s)
{
  static const std::map<std::string, std::string> named = {
    { "lt", "<" }, { "gt", ">" }, { "amp", "&" }, { "quot", "\"" }, { "apos", "'" }
  };
  std::string out;
  for(size_t i = 0; i < s.size(); ++i)
  {
    size_t semi = s[i] == '&' ? s.find(';', i) : std::string::npos;
    if(semi == std::string::npos)
    {
      out += s[i];
      continue;
    }
    std::string ent = s.substr(i + 1, semi - i - 1);
    if(!ent.empty() && ent[0] == '#')
    {
      unsigned long cp = ent.size() > 1 && (ent[1] == 'x' || ent[1] == 'X') ?
                             std::strtoul(ent.c_str() + 2, nullptr, 16) :
                             std::strtoul(ent.c_str() + 1, nullptr, 10);
      if(cp < 0x80)  // UTF-8 encode
        out += char(cp);
      else if(cp < 0x800)
        out += { char(0xC0 | cp >> 6), char(0x80 | (cp & 0x3F)) };
      else if(cp < 0x10000)
        out += { char(0xE0 | cp >> 12), char(0x80 | (cp >> 6 & 0x3F)),
                 char(0x80 | (cp & 0x3F)) };
      else
        out += { char(0xF0 | cp >> 18), char(0x80 | (cp >> 12 & 0x3F)),
                 char(0x80 | (cp >> 6 & 0x3F)), char(0x80 | (cp & 0x3F)) };
    }
    else if(named.count(ent))
      out += named.at(ent);
    else
      throw Error("XML: unknown entity &" + ent + ";");
    i = semi;
  }
  return out;
}

Elem parseXml(const std::string& s)
{
  Elem doc;
  std::vector<Elem*> open{ &doc };
  auto skipPast = [&](size_t from, const char* end) {
    size_t e = s.find(end, from);
    if(e == std::string::npos)
      throw Error(std::string("XML: missing '") + end + "'");
    return e + std::strlen(end);
  };
  auto isName = [](char c) { return !std::isspace((unsigned char)c) && !std::strchr("/>=", c); };
  for(size_t i = s.find('<'); i != std::string::npos; i = s.find('<', i))
  {
    if(s.compare(i, 4, "<!--") == 0)
      i = skipPast(i, "-->");
    else if(s.compare(i, 9, "<![CDATA[") == 0)
      i = skipPast(i, "]]>");
    else if(s.compare(i, 2, "<?") == 0)
      i = skipPast(i, "?>");
    else if(s.compare(i, 2, "<!") == 0)
      i = skipPast(i, ">");
    else if(s.compare(i, 2, "</") == 0)
    {
      size_t e = s.find('>', i);
      if(e == std::string::npos || open.size() < 2)
        throw Error("XML: unexpected closing tag");
      std::string name = s.substr(i + 2, e - i - 2);
      while(!name.empty() && std::isspace((unsigned char)name.back()))
        name.pop_back();
      if(name != open.back()->tag)
        throw Error("XML: </" + name + "> closes <" + open.back()->tag + ">");
      open.pop_back();
      i = e + 1;
    }
    else
    {
      Elem e;
      size_t j = i + 1;
      while(j < s.size() && isName(s[j]))
        e.tag += s[j++];
      if(e.tag.empty())
        throw Error("XML: bad tag");
      bool selfClosing = false;
      for(;;)
      {
        while(j < s.size() && std::isspace((unsigned char)s[j]))
          ++j;
        if(j >= s.size())
          throw Error("XML: unterminated <" + e.tag + ">");
        if(s[j] == '>')
          break;
        if(s.compare(j, 2, "/>") == 0)
        {
          selfClosing = true;
          ++j;
          break;
        }
        std::string key;
        while(j < s.size() && isName(s[j]))
          key += s[j++];
        while(j < s.size() && std::isspace((unsigned char)s[j]))
          ++j;
        if(key.empty() || j >= s.size() || s[j] != '=')
          throw Error("XML: bad attribute in <" + e.tag + ">");
        ++j;
        while(j < s.size() && std::isspace((unsigned char)s[j]))
          ++j;
        char q = j < s.size() ? s[j] : 0;
        size_t end = (q == '"' || q == '\'') ? s.find(q, j + 1) : std::string::npos;
        if(end == std::string::npos)
          throw Error("XML: bad attribute value in <" + e.tag + ">");
        e.attr[key] = decodeEntities(s.substr(j + 1, end - j - 1));
        j = end + 1;
      }
      i = j + 1;
      open.back()->kids.push_back(std::move(e));
      if(!selfClosing)
        open.push_back(&open.back()->kids.back());
    }
  }
  if(open.size() != 1 || doc.kids.size() != 1)
    throw Error("XML: unbalanced document");
  return doc.kids.front();
}

std::string readFile(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  if(!f)
    throw Error("cannot read " + path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// ---------------------------------------------------------------- leaves of the mission
struct LeafModel
{
  bool condition = false;
  BT::PortsList ports;
};

// Leaves to register: every <Action>/<Condition> of <TreeNodesModel>, plus leaves used in
// a <BehaviorTree> that neither the model nor BehaviorTree.CPP knows (made Actions).
std::map<std::string, LeafModel> collectLeaves(const Elem& root,
                                               const BT::BehaviorTreeFactory& factory)
{
  std::map<std::string, LeafModel> leaves;
  for(const Elem& model : root.kids)
  {
    if(model.tag != "TreeNodesModel")
      continue;
    for(const Elem& n : model.kids)
    {
      const std::string* id = n.get("ID");
      if((n.tag != "Action" && n.tag != "Condition") || !id)
        continue;
      if(factory.builders().count(*id))
      {
        std::cerr << "note: model entry " << *id << " is built in; keeping the built-in\n";
        continue;
      }
      LeafModel& leaf = leaves[*id];
      leaf.condition = n.tag == "Condition";
      for(const Elem& p : n.kids)
      {
        static const std::map<std::string, BT::PortDirection> dirs = {
          { "input_port", BT::PortDirection::INPUT },
          { "output_port", BT::PortDirection::OUTPUT },
          { "inout_port", BT::PortDirection::INOUT }
        };
        if(dirs.count(p.tag) && p.get("name"))
        {
          const std::string type = p.get("type") ? *p.get("type") : "";
          std::string compact;
          for(char c : type)
            if(!std::isspace((unsigned char)c))
              compact += c;
          const bool queue = compact.find("SharedQueue<") != std::string::npos ||
                             compact.find("deque<") != std::string::npos;
          const auto dir = dirs.at(p.tag);
          const std::string& pname = *p.get("name");
          if(queue && compact.find("<std::string>") != std::string::npos)
            leaf.ports.insert(BT::CreatePort<BT::SharedQueue<std::string>>(dir, pname));
          else if(queue && compact.find("<int>") != std::string::npos)
            leaf.ports.insert(BT::CreatePort<BT::SharedQueue<int>>(dir, pname));
          else if(queue && compact.find("<double>") != std::string::npos)
            leaf.ports.insert(BT::CreatePort<BT::SharedQueue<double>>(dir, pname));
          else if(queue && compact.find("<bool>") != std::string::npos)
            leaf.ports.insert(BT::CreatePort<BT::SharedQueue<bool>>(dir, pname));
          else
            leaf.ports.insert(BT::CreatePort(dir, pname));
        }
      }
    }
  }
  std::map<std::string, LeafModel> undeclared;
  std::function<void(const Elem&)> visit = [&](const Elem& e) {
    // <Action ID="X"/>, <Condition ID="X"/> or <X/>; never <SubTree>, <Control>, <Decorator>
    const bool generic = e.tag == "Action" || e.tag == "Condition";
    const bool special = e.tag == "SubTree" || e.tag == "Control" || e.tag == "Decorator";
    const std::string id = generic ? (e.get("ID") ? *e.get("ID") : "") : e.tag;
    if(e.kids.empty() && !special && !id.empty() && !leaves.count(id) &&
       !factory.builders().count(id))
    {
      LeafModel& leaf = undeclared[id];
      for(const auto& [key, value] : e.attr)
        if(BT::IsAllowedPortName(key) && key != "_autoremap")
          leaf.ports.insert(BT::InputPort(key));
    }
    for(const Elem& k : e.kids)
      visit(k);
  };
  for(const Elem& tree : root.kids)
    if(tree.tag == "BehaviorTree")
      for(const Elem& k : tree.kids)
        visit(k);
  for(auto& [id, leaf] : undeclared)
  {
    std::cerr << "note: leaf " << id << " is not in <TreeNodesModel>; treated as Action\n";
    leaves[id] = std::move(leaf);
  }
  return leaves;
}

template <class Action, class Condition, class... Args>
void registerLeaves(BT::BehaviorTreeFactory& factory,
                    const std::map<std::string, LeafModel>& leaves, Args... args)
{
  for(const auto& [id, leaf] : leaves)
  {
    if(leaf.condition)
      factory.registerNodeType<Condition>(id, leaf.ports, args...);
    else
      factory.registerNodeType<Action>(id, leaf.ports, args...);
  }
}

BT::Tree createTree(BT::BehaviorTreeFactory& factory, const std::string& path)
{
  // BehaviorTree.CPP prints warnings on std::cout; keep stdout for the trace.
  std::streambuf* saved = std::cout.rdbuf(std::cerr.rdbuf());
  try
  {
    // (an absolute path: 4.6.2 throws on a bare file name, whose parent_path() is empty)
    BT::Tree tree = factory.createTreeFromFile(std::filesystem::absolute(path));
    std::cout.rdbuf(saved);
    return tree;
  }
  catch(...)
  {
    std::cout.rdbuf(saved);
    throw;
  }
}

const char* statusName(NodeStatus s)
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

// ---------------------------------------------------------------- scenario
struct Scenario
{
  int ticks = 100;
  int clock_ms = 0;  // real sleep before each tick after the first (pick values far from timer boundaries)
  NodeStatus fallback = NodeStatus::SUCCESS;  // the `default` line
  std::map<std::string, std::vector<NodeStatus>> lists;
  std::map<std::string, size_t> used;
  // `queue NAME PORT ITEM ...`: (port, items) by leaf name
  std::map<std::string, std::vector<std::pair<std::string, std::vector<std::string>>>> queues;

  const std::vector<NodeStatus>* listOf(const std::string& name) const
  {
    auto it = lists.find(name);
    return it == lists.end() ? nullptr : &it->second;
  }
  NodeStatus next(const std::string& name)
  {
    const auto* list = listOf(name);
    if(!list)
      return fallback;
    size_t& k = used[name];
    NodeStatus s = (*list)[std::min(k, list->size() - 1)];
    k += k < list->size();
    return s;
  }
};

NodeStatus parseStatus(const std::string& word, const std::string& where)
{
  if(word == "SUCCESS")
    return NodeStatus::SUCCESS;
  if(word == "FAILURE")
    return NodeStatus::FAILURE;
  if(word == "RUNNING")
    return NodeStatus::RUNNING;
  throw Error(where + ": bad status '" + word + "' (SUCCESS, FAILURE or RUNNING)");
}

Scenario parseScenario(const std::string& path)
{
  Scenario sc;
  std::istringstream in(readFile(path));
  std::set<std::string> seen;
  std::string line;
  for(int lineNo = 1; std::getline(in, line); ++lineNo)
  {
    const std::string where = path + ":" + std::to_string(lineNo);
    std::istringstream words(line.substr(0, line.find('#')));
    std::vector<std::string> w;
    for(std::string t; words >> t;)
      w.push_back(t);
    if(w.empty())
      continue;
    const std::string key = w[0] == "leaf" && w.size() > 1                       ? "leaf " + w[1] :
                            w[0] == "queue" && w.size() > 2 ? "queue " + w[1] + " " + w[2] :
                                                                                   w[0];
    if(!seen.insert(key).second)
      throw Error(where + ": duplicate '" + key + "'");
    if(w[0] == "ticks" && w.size() == 2 &&
       w[1].find_first_not_of("0123456789") == std::string::npos && w[1].size() < 9 &&
       std::stoi(w[1]) > 0)
      sc.ticks = std::stoi(w[1]);
    else if(w[0] == "clock_ms" && w.size() == 2 &&
            w[1].find_first_not_of("0123456789") == std::string::npos && w[1].size() < 7)
      sc.clock_ms = std::stoi(w[1]);
    else if(w[0] == "default" && w.size() == 2)
      sc.fallback = parseStatus(w[1], where);
    else if(w[0] == "queue" && w.size() > 2)
      sc.queues[w[1]].emplace_back(w[2], std::vector<std::string>(w.begin() + 3, w.end()));
    else if(w[0] == "leaf" && w.size() > 2)
      for(size_t i = 2; i < w.size(); ++i)
        sc.lists[w[1]].push_back(parseStatus(w[i], where));
    else
      throw Error(where + ": cannot parse '" + line + "'");
  }
  return sc;
}

// ---------------------------------------------------------------- trace mode
template <class T>
void setQueue(BT::TreeNode& node, const std::string& port, const std::vector<std::string>& items)
{
  auto q = std::make_shared<std::deque<T>>();
  for(const std::string& item : items)
    q->push_back(BT::convertFromString<T>(item));
  auto res = node.setOutput(port, q);
  if(!res)
    throw Error("setOutput(" + port + ") of " + node.name() + ": " + res.error());
}

// The scenario's `queue` lines of a leaf, before its code answers.
void fillQueues(BT::TreeNode& node, const BT::NodeConfig& config, Scenario* sc)
{
  auto it = sc->queues.find(node.name());
  if(it == sc->queues.end())
    return;
  for(const auto& [port, items] : it->second)
  {
    const auto& ports = config.manifest->ports;
    auto p = ports.find(port);
    if(p == ports.end())
      throw Error("queue line: " + node.name() + " has no port " + port);
    const std::type_index t = p->second.type();
    if(t == typeid(BT::SharedQueue<std::string>))
      setQueue<std::string>(node, port, items);
    else if(t == typeid(BT::SharedQueue<int>))
      setQueue<int>(node, port, items);
    else if(t == typeid(BT::SharedQueue<double>))
      setQueue<double>(node, port, items);
    else if(t == typeid(BT::SharedQueue<bool>))
      setQueue<bool>(node, port, items);
    else
      throw Error("queue line: port " + port + " of " + node.name() + " is no queue");
  }
}

class ScriptedAction : public BT::StatefulActionNode
{
public:
  ScriptedAction(const std::string& name, const BT::NodeConfig& cfg, Scenario* sc)
    : StatefulActionNode(name, cfg), sc_(sc)
  {}
  NodeStatus onStart() override
  {
    fillQueues(*this, config(), sc_);
    return sc_->next(name());
  }
  NodeStatus onRunning() override
  {
    fillQueues(*this, config(), sc_);
    return sc_->next(name());
  }
  void onHalted() override {}

private:
  Scenario* sc_;
};

class ScriptedCondition : public BT::ConditionNode
{
public:
  ScriptedCondition(const std::string& name, const BT::NodeConfig& cfg, Scenario* sc)
    : ConditionNode(name, cfg), sc_(sc)
  {}
  NodeStatus tick() override
  {
    fillQueues(*this, config(), sc_);
    NodeStatus s = sc_->next(name());
    if(s == NodeStatus::RUNNING)
      throw Error("Condition " + name() + " scripted RUNNING");
    return s;
  }

private:
  Scenario* sc_;
};

// Names are printed between double quotes, C style: \" \\ \n \r \t and \xHH for
// other control bytes; everything else (UTF-8 included) verbatim.
std::string quoted(const std::string& s)
{
  std::string out = "\"";
  for(unsigned char c : s)
  {
    if(c == '"' || c == '\\')
      out += { '\\', char(c) };
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

class TraceLogger : public BT::StatusChangeLogger
{
public:
  explicit TraceLogger(BT::TreeNode* root) : StatusChangeLogger(root)
  {
    enableTransitionToIdle(true);
  }
  void callback(BT::Duration, const BT::TreeNode& node, NodeStatus from,
                NodeStatus to) override
  {
    std::cout << node.UID() << ' ' << node.registrationName() << ' ' << quoted(node.name())
              << ' ' << statusName(from) << " -> " << statusName(to) << '\n';
  }
  void flush() override { std::cout.flush(); }
};

int runTrace(const std::string& mission, const std::string& scenarioPath)
{
  Scenario sc = parseScenario(scenarioPath);
  BT::BehaviorTreeFactory factory;
  auto leaves = collectLeaves(parseXml(readFile(mission)), factory);
  // An untyped port a `queue` line names (a leaf declared nowhere, named by its ID): an inout
  // SharedQueue<std::string>, as `btgen models` declares it and the project's C++ registers it.
  for(const auto& [name, fills] : sc.queues)
  {
    auto leaf = leaves.find(name);
    if(leaf == leaves.end())
      continue;
    for(const auto& fill : fills)
    {
      auto port = leaf->second.ports.find(fill.first);
      if(port != leaf->second.ports.end() && port->second.type() == typeid(BT::AnyTypeAllowed))
      {
        leaf->second.ports.erase(port);
        leaf->second.ports.insert(BT::BidirectionalPort<BT::SharedQueue<std::string>>(fill.first));
      }
    }
  }
  registerLeaves<ScriptedAction, ScriptedCondition>(factory, leaves, &sc);
  BT::Tree tree = createTree(factory, mission);

  // Reject RUNNING for conditions up front; warn about scenario names that match no leaf.
  std::set<std::string> leafNames;
  for(const auto& sub : tree.subtrees)
    for(const auto& node : sub->nodes)
    {
      auto it = leaves.find(node->registrationName());
      if(it == leaves.end())
        continue;
      leafNames.insert(node->name());
      const auto* list = sc.listOf(node->name());
      bool running = list ? std::count(list->begin(), list->end(), NodeStatus::RUNNING) > 0 :
                            sc.fallback == NodeStatus::RUNNING;
      if(it->second.condition && running)
        throw Error("Condition " + node->name() + " is scripted RUNNING");
    }
  for(const auto& [name, list] : sc.lists)
    if(!leafNames.count(name))
      std::cerr << "warning: scenario leaf " << name << " matches no leaf of the tree\n";

  TraceLogger logger(tree.rootNode());
  for(int n = 1; n <= sc.ticks; ++n)
  {
    if(n > 1 && sc.clock_ms > 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(sc.clock_ms));
    std::cout << "tick " << n << '\n';
    NodeStatus result = tree.tickExactlyOnce();
    std::cout << "result " << statusName(result) << '\n';
    if(result == NodeStatus::SUCCESS || result == NodeStatus::FAILURE)
      break;
  }
  logger.setEnabled(false);  // the tree's destructor halts it: not part of the trace
  std::cout.flush();
  return 0;
}

// ---------------------------------------------------------------- bench mode
class TrivialAction : public BT::SyncActionNode
{
public:
  TrivialAction(const std::string& name, const BT::NodeConfig& cfg)
    : SyncActionNode(name, cfg)
  {}
  NodeStatus tick() override { return NodeStatus::SUCCESS; }
};

class TrivialCondition : public BT::ConditionNode
{
public:
  TrivialCondition(const std::string& name, const BT::NodeConfig& cfg)
    : ConditionNode(name, cfg)
  {}
  NodeStatus tick() override { return NodeStatus::SUCCESS; }
};

int runBench(const std::string& mission, long n)
{
  BT::BehaviorTreeFactory factory;
  registerLeaves<TrivialAction, TrivialCondition>(
      factory, collectLeaves(parseXml(readFile(mission)), factory));

  unsigned long long a0 = g_allocs.load();
  BT::Tree tree = createTree(factory, mission);
  unsigned long long createAllocs = g_allocs.load() - a0;
  size_t nodes = 0;
  for(const auto& sub : tree.subtrees)
    nodes += sub->nodes.size();

  NodeStatus result = NodeStatus::IDLE;
  a0 = g_allocs.load();
  auto t0 = std::chrono::steady_clock::now();
  for(long i = 0; i < n; ++i)
    result = tree.tickExactlyOnce();
  auto t1 = std::chrono::steady_clock::now();
  unsigned long long tickAllocs = g_allocs.load() - a0;

  long long ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
  std::printf("nodes %zu\nticks %ld\ntotal_ns %lld\nns_per_tick %.1f\n"
              "allocs_ticks %llu\nallocs_per_tick %.3f\nallocs_create %llu\n"
              "last_result %s\n",
              nodes, n, ns, n ? double(ns) / n : 0.0, tickAllocs,
              n ? double(tickAllocs) / n : 0.0, createAllocs, statusName(result));
  if(result == NodeStatus::RUNNING)
    std::cerr << "warning: the root is still RUNNING; ticks are not full traversals\n";
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  const std::string usage = "usage: harness trace MISSION.xml SCENARIO.scenario\n"
                            "       harness bench MISSION.xml N\n";
  try
  {
    const std::string mode = argc == 4 ? argv[1] : "";
    if(mode == "trace")
      return runTrace(argv[2], argv[3]);
    if(mode == "bench")
    {
      char* end = nullptr;
      long n = std::strtol(argv[3], &end, 10);
      if(*end || n < 1)
        throw Error("bench: N must be a positive integer");
      return runBench(argv[2], n);
    }
    std::cerr << usage;
  }
  catch(const std::exception& e)
  {
    std::cout.flush();
    std::cerr << "error: " << e.what() << '\n';
  }
  return 2;
}
