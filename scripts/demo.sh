#!/usr/bin/env bash
# The main job: a shipped scene through the whole pipeline, results under out/.
# Usage: scripts/demo.sh BUILD_DIR SCENE
set -euo pipefail
build=${1:-build/release}
scene=${2:-scenes/cornell.json}
name=$(basename "$scene" .json)
mkdir -p out
echo "== $scene: scene and patch statistics"
"$build/preprocess/firstshot-preprocess" "$scene" --stats | tee "out/$name-stats.txt"
echo "== first-shot factors of the small lights"
"$build/preprocess/firstshot-preprocess" "$scene" -o "out/$name.fsd"
if [ -x "$build/render/firstshot-render" ]; then
  echo "== render with the table at the defaults (--integrator auto: a pilot picks the method, and whether reading the"
  echo "   table pays; EXR with albedo/normal layers, PNG)"
  "$build/render/firstshot-render" "$scene" --firstshot "out/$name.fsd" --aov -o "out/$name.exr" -o "out/$name.png"
  echo "== the table read by the path tracer, whatever the pilot chose"
  "$build/render/firstshot-render" "$scene" --firstshot "out/$name.fsd" --integrator path \
    -o "out/$name-firstshot.exr" -o "out/$name-firstshot.png"
  echo "== reference: the same view by path tracing with next-event estimation, no table"
  "$build/render/firstshot-render" "$scene" --integrator path -o "out/$name-nee.exr" -o "out/$name-nee.png"
  ls -l out/"$name".* out/"$name"-firstshot.* out/"$name"-nee.*
fi
