#!/usr/bin/env bash
# The main job: installs what is missing, builds, and opens the viewer (`penumbra view`)
# on the default scene, on its exact render (the soft shadows). With no display, `penumbra view`
# says so and writes the headless screenshot of its UI once the render is done (out/view.png,
# out/view_state.json) and the preview image (out/preview.png) instead.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build --target penumbra
scene=${1:-assets/cornell_box.obj}
exec ./build/app/penumbra view "${scene}"
