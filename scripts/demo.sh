#!/usr/bin/env bash
# The main job: validate the Lab Tour mission and run it.
# Usage: scripts/demo.sh [--language English|isiZulu|Kinyarwanda] [--trace] [--answer yes|no]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export PATH="$PWD/.venv/bin:$PATH"

btgen validate missions/LabTour.xml
if [ -x build/demo/lab_tour_robot ] || [ -f examples/lab_tour_robot/CMakeLists.txt ]; then
  cmake -S . -B build/demo -G Ninja -DCMAKE_BUILD_TYPE=Release -DBTGEN_BUILD_TESTS=OFF \
    -DPython3_EXECUTABLE="$PWD/.venv/bin/python" >/dev/null
  cmake --build build/demo --target lab_tour_robot
  exec build/demo/examples/lab_tour_robot/lab_tour_robot --kb-config data/environmentKnowledgeBaseConfiguration.ini "$@"
fi
# Until the simulated robot is built: the reference interpreter runs the tour with scripted leaves.
btgen run missions/LabTour.xml --scenario missions/scenarios/LabTour.yes.scenario
