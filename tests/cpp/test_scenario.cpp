// The scenario reader: every error FORMAT.md lists, with its position.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "btgen/harness/scenario.hpp"
#include "control_flow.hpp"
#include "test_leaves.hpp"

namespace {

using btgen::Diagnostic;
using btgen::Scenario;

std::vector<std::string> parse(const std::string& text, Scenario* out = nullptr) {
  std::vector<Diagnostic> diags;
  Scenario sc;
  btgen::ScenarioParser("s.scenario", diags).parse(text, sc);
  if (out != nullptr) *out = sc;
  std::vector<std::string> lines;
  for (const auto& d : diags) lines.push_back(d.str());
  return lines;
}

TEST(ScenarioParse, ReadsEveryKeyword) {
  Scenario sc;
  EXPECT_TRUE(parse("# comment\n\nticks 20   # budget\ndefault FAILURE\nleaf Move RUNNING SUCCESS\r\nclock_ms 5\n", &sc)
                  .empty());
  EXPECT_EQ(sc.ticks, 20);
  EXPECT_EQ(sc.default_status, btgen::Status::FAILURE);
  EXPECT_EQ(sc.clock_ms, 5);
  ASSERT_EQ(sc.leaves.size(), 1u);
  EXPECT_EQ(sc.leaves[0].name, "Move");
  EXPECT_EQ(sc.leaves[0].statuses, (std::vector<btgen::Status>{btgen::Status::RUNNING, btgen::Status::SUCCESS}));
}

TEST(ScenarioParse, QueueLines) {
  Scenario sc;
  EXPECT_TRUE(parse("queue Parse waypoints a b\nqueue Parse other\nqueue Fill waypoints 1\n", &sc).empty());
  ASSERT_EQ(sc.queues.size(), 3u);
  EXPECT_EQ(sc.queues[0].name, "Parse");
  EXPECT_EQ(sc.queues[0].port, "waypoints");
  EXPECT_EQ(sc.queues[0].items, (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(sc.queues[1].items.empty());  // an empty queue
  EXPECT_EQ(sc.queues[2].line, 3);
  const std::vector<std::string> expected{
      "s.scenario:1:1: error: `queue` needs a leaf name, its queue port and the queue's items (none: empty)",
      "s.scenario:3:13: error: queue port `q` of leaf `Parse` is listed twice (first at line 2)",
  };
  EXPECT_EQ(parse("queue Parse\nqueue Parse q x\nqueue Parse q y\n"), expected);
}

TEST(ScenarioParse, Defaults) {
  Scenario sc;
  EXPECT_TRUE(parse("", &sc).empty());
  EXPECT_EQ(sc.ticks, 100);
  EXPECT_EQ(sc.default_status, btgen::Status::SUCCESS);
  EXPECT_EQ(sc.clock_ms, 0);
}

TEST(ScenarioParse, ReportsEveryErrorWithItsPosition) {
  const auto errs = parse(
      "ticks 0\n"
      "ticks 3\n"
      "default RUNING\n"
      "default SUCCESS\n"
      "leaf Move\n"
      "leaf Grasp SUCCESS\n"
      "leaf Grasp FAILURE\n"
      "  tick 4\n"
      "leaf Calibrate SKIPPED\n"
      "clock_ms -1\n");
  const std::vector<std::string> expected{
      "s.scenario:1:7: error: ticks must be at least 1, got 0",
      "s.scenario:2:1: error: `ticks` is given twice (first at line 1)",
      "s.scenario:3:9: error: unknown status `RUNING`: use SUCCESS, FAILURE or RUNNING (did you mean `RUNNING`?)",
      "s.scenario:4:1: error: `default` is given twice (first at line 3)",
      "s.scenario:5:10: error: leaf `Move` has no status: list one or more of SUCCESS, FAILURE, RUNNING",
      "s.scenario:7:6: error: leaf `Grasp` is listed twice (first at line 6)",
      "s.scenario:8:3: error: unknown keyword `tick`: a line starts with ticks, default, leaf, clock_ms or queue "
      "(did you mean `ticks`?)",
      "s.scenario:9:16: error: `SKIPPED` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING",
      "s.scenario:10:10: error: clock_ms cannot be negative, got -1",
  };
  EXPECT_EQ(errs, expected);
}

TEST(ScenarioParse, NumbersAreWholeAndBounded) {
  EXPECT_EQ(parse("ticks many\n"), std::vector<std::string>{"s.scenario:1:7: error: `ticks` needs a whole number, "
                                                            "got `many`"});
  EXPECT_EQ(parse("ticks\n"), std::vector<std::string>{"s.scenario:1:6: error: `ticks` needs a whole number (the "
                                                       "most root ticks to send)"});
  EXPECT_EQ(parse("ticks 3 4\n"), std::vector<std::string>{"s.scenario:1:9: error: `ticks` takes one number, found "
                                                           "also `4`"});
  EXPECT_EQ(parse("ticks 99999999999\n"),
            std::vector<std::string>{"s.scenario:1:7: error: ticks 99999999999 is too large (at most 2147483647)"});
  EXPECT_EQ(parse("leaf\n"), std::vector<std::string>{"s.scenario:1:5: error: `leaf` needs a leaf name and at least "
                                                      "one status"});
}

TEST(ScenarioParse, ColumnsCountCharacters) {
  EXPECT_EQ(parse("leaf \xc3\xa9t\xc3\xa9 BAD\n"),
            std::vector<std::string>{"s.scenario:1:10: error: unknown status `BAD`: use SUCCESS, FAILURE or RUNNING"});
}

using Mission = control_flow::ControlFlow<btgen_test::InstantLeaves>;

std::vector<std::string> check(const std::string& text, bool* ok_out = nullptr) {
  std::vector<Diagnostic> diags;
  Scenario sc;
  EXPECT_TRUE(btgen::ScenarioParser("s.scenario", diags).parse(text, sc));
  const bool ok = btgen::check_scenario(sc, Mission::nodes().data(), Mission::node_count(), diags);
  if (ok_out != nullptr) *ok_out = ok;
  std::vector<std::string> lines;
  for (const auto& d : diags) lines.push_back(d.str());
  return lines;
}

TEST(ScenarioCheck, ConditionsCannotRun) {
  bool ok = true;
  const auto lines = check("leaf IsDone SUCCESS RUNNING\nleaf Approach RUNNING\n", &ok);
  EXPECT_FALSE(ok);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("s.scenario:1:21: error: `IsDone` is a Condition and cannot return RUNNING (a Condition "
                           "answers in one tick; its Condition node is at ",
                           0),
            0u)
      << lines[0];
}

TEST(ScenarioCheck, DefaultRunningMustNotReachAnUnscriptedCondition) {
  bool ok = true;
  const auto lines = check("default RUNNING\nleaf IsDone SUCCESS\n", &ok);
  EXPECT_FALSE(ok);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("s.scenario:1:9: error: `default RUNNING` reaches the Condition `IsBatteryOk`"),
            std::string::npos)
      << lines[0];
}

TEST(ScenarioCheck, UnknownLeafIsAWarning) {
  bool ok = false;
  const auto lines = check("leaf Aproach SUCCESS\nleaf Sleep FAILURE\n", &ok);
  EXPECT_TRUE(ok);
  const std::vector<std::string> expected{
      "s.scenario:1:6: warning: leaf `Aproach` matches no Action or Condition of the mission; its line is ignored "
      "(did you mean `Approach`?)",
      "s.scenario:2:6: warning: `Sleep` is a built-in node of BehaviorTree.CPP and keeps its built-in behaviour; its "
      "line is ignored",
  };
  EXPECT_EQ(lines, expected);
}

// Found by comparing the engines: a leaf name with control characters was
// printed raw by the C++ runner and escaped by the interpreter.
TEST(ScenarioCheck, DiagnosticsStayOnOneLine) {
  bool ok = false;
  const auto lines = check(
      "leaf a\x01"
      "b SUCCESS\nleaf c\xc2\x85\x7f\xe2\x80\xa8"
      "d FAILURE\n",
      &ok);
  EXPECT_TRUE(ok);
  const std::vector<std::string> expected{
      "s.scenario:1:6: warning: leaf `a\\x01b` matches no Action or Condition of the mission; its line is ignored",
      "s.scenario:2:6: warning: leaf `c\\x85\\x7f\\u2028d` matches no Action or Condition of the mission; its "
      "line is ignored",
  };
  EXPECT_EQ(lines, expected);
}

TEST(OneLine, EscapesAsTheInterpreterDoes) {
  std::string out;
  btgen::one_line("two\nlines\r\xc2\x85 caf\xc3\xa9 \xe2\x80\xa9\x1b!", [&out](std::string_view p) { out.append(p); });
  EXPECT_EQ(out, "two\\nlines\\r\\x85 caf\xc3\xa9 \\u2029\\x1b!");
  out.clear();
  btgen::one_line("plain text", [&out](std::string_view p) { out.append(p); });
  EXPECT_EQ(out, "plain text");
}

TEST(ScenarioLeaves, InstancesShareOneListAndTheLastStatusRepeats) {
  std::vector<Diagnostic> diags;
  Scenario sc;
  ASSERT_TRUE(btgen::ScenarioParser("s", diags).parse("default FAILURE\nleaf Approach SUCCESS RUNNING\n", sc));
  btgen::ScenarioLeaves leaves(sc, Mission::nodes().data(), Mission::node_count());
  std::vector<const btgen::NodeInfo*> approach;
  const btgen::NodeInfo* grasp = nullptr;
  for (const auto& n : Mission::nodes()) {
    if (n.name == "Approach") approach.push_back(&n);
    if (n.id == "Grasp" && grasp == nullptr) grasp = &n;
  }
  ASSERT_EQ(approach.size(), 2u);  // one per Fetch instance
  ASSERT_NE(grasp, nullptr);
  control_flow::detail::Blackboard bb;
  const btgen::ErrorSink err([](void*, const btgen::RuntimeError&) noexcept {}, nullptr);
  control_flow::leaf::Move mv(bb, err, *approach[0]);
  control_flow::leaf::Grasp gr(bb, err, *grasp);
  EXPECT_EQ(leaves.onStart(mv, *approach[1]), btgen::Status::SUCCESS);
  EXPECT_EQ(leaves.onStart(mv, *approach[0]), btgen::Status::RUNNING);
  EXPECT_EQ(leaves.onRunning(mv, *approach[1]), btgen::Status::RUNNING);
  EXPECT_EQ(leaves.onStart(gr, *grasp), btgen::Status::FAILURE);  // unlisted: the default
}

}  // namespace
