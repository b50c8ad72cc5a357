#!/bin/bash
# Usage: bench/identical.sh BASE_BIN_DIR NEW_BIN_DIR [WORK_DIR]
# A redesign's check: every shipped scene is preprocessed (GL and Embree item buffers) and rendered
# with every integrator and its main variants by two builds; the .fsd files and images must agree
# byte for byte. BIN_DIRs hold firstshot-preprocess and firstshot-render (a build folder works:
# its preprocess/ and render/ subfolders are searched). Prints each difference and a summary;
# exit 1 when anything differs or fails. Run from the repository root. Takes a few minutes.
set -u
bins() { # dir -> "preprocess render"
  local d=$1
  if [ -x "$d/firstshot-render" ]; then echo "$d/firstshot-preprocess $d/firstshot-render"
  else echo "$d/preprocess/firstshot-preprocess $d/render/firstshot-render"; fi
}
read -r BP BR <<<"$(bins "$1")"; read -r NP NR <<<"$(bins "$2")"
W=${3:-$(mktemp -d)}; mkdir -p "$W/base" "$W/new"
SCENES=${IDENT_SCENES:-$(ls scenes/*.json | xargs -n1 basename | sed 's/\.json$//')}
COMMON="--width 32 --height 24 --spp 4 --seed 3 -q"
VARIANTS=(
 "path|--integrator path"
 "pathsobol|--integrator path --sampler sobol"
 "pathd2|--integrator path --max-depth 2"
 "pathpatch|--integrator path --primary patch --patch-nee every"
 "pathall|--integrator path --light-sampler all --patch-nee first --table-visibility off --light-visibility off"
 "ic|--integrator irradiance-cache"
 "icnee|--integrator irradiance-cache --ic-patch-nee 1 --primary patch"
 "icone|--integrator irradiance-cache --one-pass --threads 1 --max-depth 3"
 "light|--integrator light"
 "lightoff|--integrator light --shoot-firstshot off --light-paths 2"
 "bdpt|--integrator bdpt"
 "bdptpatch|--integrator bdpt --max-depth 3"  # bdpt does not read --primary (passing it is an error)
 "bundle|--integrator bundle --bundle-resolution 32"
 "bundlepatch|--integrator bundle --bundle-resolution 32 --primary patch"
 "sensors|--grid -1,-1,1,1,0.5,0.5 --samples 8"
 "sensorsic|--integrator irradiance-cache --grid -1,-1,1,1,0.5,0.5 --samples 8"
)
n=0; same=0; bad=0
check() { # file
  n=$((n+1))
  if [ -f "$W/base/$1" ] && [ -f "$W/new/$1" ] && cmp -s "$W/base/$1" "$W/new/$1"; then same=$((same+1))
  else bad=$((bad+1)); echo "DIFFERS: $1"; fi
}
for s in $SCENES; do
  for b in gl embree; do
    f=$s-$b.fsd
    [ -f "$W/base/$f" ] || "$BP" scenes/$s.json -o "$W/base/$f" --quiet --backend $b --threads 2 2>/dev/null || echo "BASE FAIL $f"
    "$NP" scenes/$s.json -o "$W/new/$f" --quiet --backend $b --threads 2 2>/dev/null || echo "NEW FAIL $f"
    check $f
  done
  for v in "${VARIANTS[@]}"; do
    name=${v%%|*}; opts=${v#*|}
    for t in table notable; do
      tab=""; [ $t = table ] && tab="--firstshot $W/base/$s-embree.fsd"
      case "$t:$name" in notable:*patch*|notable:icnee|notable:pathall) continue;; esac
      ext=exr; common=$COMMON; case $name in sensors*) ext=csv; common="--seed 3 -q";; esac
      f=$s-$name-$t.$ext
      [ -f "$W/base/$f" ] || "$BR" scenes/$s.json $tab $opts $common -o "$W/base/$f" 2>"$W/base/$f.err" >/dev/null || echo "BASE FAIL $f: $(tail -1 "$W/base/$f.err")"
      "$NR" scenes/$s.json $tab $opts $common -o "$W/new/$f" 2>"$W/new/$f.err" >/dev/null || echo "NEW FAIL $f: $(tail -1 "$W/new/$f.err")"
      check $f
    done
  done
done
echo "outputs: $n identical: $same differing or missing: $bad (work folder $W)"
[ $bad -eq 0 ]
