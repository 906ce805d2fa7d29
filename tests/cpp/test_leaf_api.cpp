// The leaf API is stable across missions: every port a leaf model declares
// has its accessors whether or not the mission sets it
// (missions/leaf_api_wired.xml sets every port of Detect,
// missions/leaf_api_unwired.xml none), so one leaf implementation builds
// against both. An unset port gives BehaviorTree.CPP 4.6.2's result:
// getInput fails (btgen::PortError::kNotSet), setOutput fails (false).
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "btgen/clock.hpp"
#include "leaf_api_unwired.hpp"
#include "leaf_api_wired.hpp"

namespace {

using btgen::Status;

struct Seen {
  btgen::Input<std::string_view> target = btgen::PortError::kNone;
  std::string target_text;
  btgen::Input<std::int32_t> retries = btgen::PortError::kNone;
  bool set_retries = false, set_error_code = false, set_pose = false;
  btgen::Input<double> threshold = btgen::PortError::kNone;
  int calls = 0;
};

// One implementation of Detect for any mission whose TreeNodesModel declares
// it: a template over the mission's leaf model class.
struct SharedLeaves {
  Seen seen;

  template <class Detect>
  Status onStart(Detect& m, const btgen::NodeInfo&) {
    ++seen.calls;
    seen.target = m.target();
    seen.target_text = std::string(seen.target.value());
    seen.retries = m.retries();
    seen.set_retries = m.set_retries(2);
    seen.set_error_code = m.set_error_code(7);
    seen.set_pose = m.set_pose(std::string_view("here"));
    return Status::SUCCESS;
  }
  template <class M>
  Status onRunning(M&, const btgen::NodeInfo&) {
    return Status::SUCCESS;
  }
  template <class M>
  void onHalted(M&, const btgen::NodeInfo&) {}
  template <class Unused>
  Status check(Unused& m, const btgen::NodeInfo&) {
    seen.threshold = m.threshold();
    return Status::SUCCESS;
  }
};

TEST(LeafApi, WiredPortsReadAndWrite) {
  SharedLeaves leaves;
  leaf_api_wired::LeafApiWired<SharedLeaves, btgen::ManualClock> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::SUCCESS);  // the ScriptCondition sees code == 7, pose == 'here'
  EXPECT_EQ(leaves.seen.calls, 1);
  EXPECT_EQ(leaves.seen.target_text, "cup");
  EXPECT_EQ(leaves.seen.retries.error(), btgen::PortError::kNoValue);  // the typed port created `tries`, empty
  EXPECT_TRUE(leaves.seen.set_retries);
  EXPECT_TRUE(leaves.seen.set_error_code);
  EXPECT_TRUE(leaves.seen.set_pose);
  EXPECT_EQ(mission.blackboard().code.value, 7);
  EXPECT_EQ(mission.blackboard().tries.value, 2);
}

TEST(LeafApi, UnwiredPortsFailAsInBehaviorTreeCpp) {
  SharedLeaves leaves;
  leaf_api_unwired::LeafApiUnwired<SharedLeaves, btgen::ManualClock> mission(leaves);
  EXPECT_EQ(mission.tick(), Status::SUCCESS);  // the hook decides: the failures are its to handle
  EXPECT_EQ(leaves.seen.calls, 1);
  EXPECT_EQ(leaves.seen.target.error(), btgen::PortError::kNotSet);
  EXPECT_EQ(leaves.seen.retries.error(), btgen::PortError::kNotSet);
  EXPECT_FALSE(leaves.seen.set_retries);
  EXPECT_FALSE(leaves.seen.set_error_code);
  EXPECT_FALSE(leaves.seen.set_pose);
  EXPECT_EQ(mission.errors(), 0u);
}

}  // namespace
