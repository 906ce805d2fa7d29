#!/usr/bin/env bash
# The main job: the Lab Tour mission, compiled to C++ by btgen, run end to end
# on a simulated Pepper robot that takes its poses, gesture targets and
# messages from the environment knowledge base.
#
# Usage: scripts/demo.sh [--language English|isiZulu|Kinyarwanda] [--answer yes|no]
#                        [--trace] [--tick-ms N] [--max-ticks N] [--kb-config FILE.ini]
#                        [--scenario FILE.scenario] [--groot2 PORT] [--btlog FILE.btlog]
# Every argument goes to lab_tour_robot (`scripts/demo.sh --help` lists them).
# On a fresh Debian machine run it as root: scripts/setup.sh installs what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

# --help answers at once: the robot's own help when it is built, else this script's.
for arg in "$@"; do
  if [ "$arg" = "--help" ] || [ "$arg" = "-h" ]; then
    if [ -x build/demo/examples/lab_tour_robot/lab_tour_robot ]; then
      exec build/demo/examples/lab_tour_robot/lab_tour_robot --help
    fi
    sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
    echo
    echo "The robot is not built yet: the first run of scripts/demo.sh builds it (build/demo),"
    echo "then \`scripts/demo.sh --help\` prints every option of lab_tour_robot."
    exit 0
  fi
done

bash scripts/setup.sh >&2
export PATH="$PWD/.venv/bin:$PATH"

# Everything before the run goes to stderr: stdout is the robot's alone.
step() { printf '\n== demo: %s\n' "$*" >&2; }

step "validate missions/LabTour.xml"
btgen validate missions/LabTour.xml >&2

step "lint the shipped knowledge base (the isiZulu placeholders are known warnings: data/README.md)"
btgen lint-kb data/environmentKnowledgeBaseInput.dat \
  --config data/environmentKnowledgeBaseConfiguration.ini --mission missions/LabTour.xml >&2

if [ -f examples/lab_tour_robot/CMakeLists.txt ] &&
   PYTHONPATH="$PWD/generator" python -m btgen.compiler --check missions/LabTour.xml 2>/dev/null; then
  step "compile the mission to C++ and build the simulated robot (build/demo, Release)"
  cmake -S . -B build/demo -G Ninja -DCMAKE_BUILD_TYPE=Release -DBTGEN_BUILD_TESTS=OFF \
    -DPython3_EXECUTABLE="$PWD/.venv/bin/python" >/dev/null
  cmake --build build/demo --target lab_tour_robot >&2
  step "run the Lab Tour on the simulated Pepper: build/demo/examples/lab_tour_robot/lab_tour_robot $*"
  exec build/demo/examples/lab_tour_robot/lab_tour_robot "$@"
fi

# If the C++ back end cannot compile the mission (an edit that uses something
# it does not support yet), say why and run the mission on the reference
# interpreter with scripted leaves instead.
step "the C++ back end cannot compile missions/LabTour.xml:"
PYTHONPATH="$PWD/generator" python -m btgen.compiler --check missions/LabTour.xml >&2 || true
step "running it on the reference interpreter with missions/scenarios/LabTour.yes.scenario instead"
btgen run missions/LabTour.xml --scenario missions/scenarios/LabTour.yes.scenario
