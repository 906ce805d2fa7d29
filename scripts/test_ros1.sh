#!/usr/bin/env bash
# The Lab Tour on ROS 1: build ros/cssr_system and ros/btgen_behavior_controller
# with Debian's catkin in a workspace under build/ros1, then run the
# end-to-end test (ros/btgen_behavior_controller/test/run_e2e.py) under a
# real roscore on a free port of 127.0.0.1.
#
# Installs the Debian ROS 1 packages when missing (as root); where apt cannot
# install them, prints why and skips (exit 0) unless BTGEN_REQUIRE_ROS=1.
# Arguments go to run_e2e.py (-k NAME runs one scenario, --keep DIR keeps logs).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

ros_pkgs=(ros-core catkin libroscpp-dev ros-message-generation ros-std-msgs python3-rospy python3-rostest rosbash
          libeigen3-dev libgtest-dev)
missing=()
for pkg in "${ros_pkgs[@]}"; do
  dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "test_ros1: installing ${missing[*]}" >&2
  if ! { [ "$(id -u)" = 0 ] && DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
         DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }; then
    echo "test_ros1: SKIPPED: cannot install the ROS 1 packages ${missing[*]} with apt here" >&2
    [ "${BTGEN_REQUIRE_ROS:-0}" = 1 ] && exit 1
    exit 0
  fi
fi
[ -x .venv/bin/python ] || bash scripts/setup.sh

# ROS 1's Python tools (catkin, rospy, roscore) need Debian's Python, not the
# python3 of a pyenv or venv earlier on PATH; btgen runs with the .venv's.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin"
unset PYTHONPATH PYTHONHOME VIRTUAL_ENV

ws="$repo/build/ros1/ws"
mkdir -p "$ws/src"
ln -sfn "$repo/ros/cssr_system" "$ws/src/cssr_system"
ln -sfn "$repo/ros/btgen_behavior_controller" "$ws/src/btgen_behavior_controller"
echo "== ROS 1: catkin_make (log: build/ros1/catkin_make.log)"
if ! (cd "$ws" && nice catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 \
        -DPython3_EXECUTABLE="$repo/.venv/bin/python" -DCMAKE_BUILD_TYPE=Release \
        -DBTGEN_BEHAVIOR_CONTROLLER_UNIT_TESTS=ON \
        >"$repo/build/ros1/catkin_make.log" 2>&1); then
  tail -40 "$repo/build/ros1/catkin_make.log" >&2
  echo "test_ros1: catkin_make failed (build/ros1/catkin_make.log)" >&2
  exit 1
fi

echo "== ROS 1: unit tests of the node's worker and phrases"
"$ws/devel/lib/btgen_behavior_controller/behavior_controller_unit_test" --gtest_brief=1

echo "== ROS 1: end-to-end test under roscore"
set +u  # setup.bash reads unset variables
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
/usr/bin/python3 "$repo/ros/btgen_behavior_controller/test/run_e2e.py" \
  --node "$ws/devel/lib/btgen_behavior_controller/behaviorController" \
  --kb "$repo/data/environmentKnowledgeBaseInput.dat" "$@"
