#!/bin/bash
# Usage: scripts/gpu_bundle.sh [BUILD_DIR]          (make gpu-bundle; docs/gpu.md)
# The preprocessor for a machine with a GPU and none of our Debian packages: builds firstshot-preprocess
# and firstshot-fsd-compare (Release, MPI off; BUILD_DIR default build/gpu, configured if new) and packs them with
# every shared library they load (ldd), and the scaling scene of bench/gpu_preprocess.sh, into .gpu/bundle.tar.xz
# (git ignores .gpu/). Left out: the C library and its loader (the machine's own) and the GL/EGL vendor libraries
# that come with the machine's driver (libEGL_nvidia and the like, found by GLVND's libEGL through the vendor's
# JSON file). Kept: GLVND's libEGL.so.1 and libGLdispatch.so.0 (and libOpenGL.so.0), Mesa's libOSMesa with its LLVM
# (llvmpipe, for the comparison). Then unpacks the archive into a scratch folder and runs the bundled preprocessor on
# scenes/cornell.json with nothing but the bundle's libraries (env -i, LD_LIBRARY_PATH=the bundle). Run from the
# repository root. Prints the archive's size, which must stay under 64 MiB with the working tree (it travels with it).
set -euo pipefail
BUILD=${1:-build/gpu}
DEST=.gpu
[ -f CMakeLists.txt ] && [ -d preprocess ] || { echo "gpu_bundle.sh: run from the repository root" >&2; exit 2; }
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFIRSTSHOT_BENCH=OFF -DFIRSTSHOT_FUZZ=OFF \
    -DFIRSTSHOT_MPI=OFF "${launcher[@]}"
fi
cmake --build "$BUILD" --target firstshot-preprocess firstshot-fsd-compare -j "${JOBS:-$(nproc)}"

STAGE=$BUILD/gpu-bundle
rm -rf "$STAGE"; mkdir -p "$STAGE/bin" "$STAGE/lib" "$STAGE/scenes"
BINS=("$BUILD/preprocess/firstshot-preprocess" "$BUILD/preprocess/firstshot-fsd-compare")
cp "${BINS[@]}" "$STAGE/bin/"
# Every library ldd resolves, but the C library's (the machine's glibc must be at least this one's: $(ldd --version)).
skip='^(libc|libm|libdl|librt|libpthread|libresolv|libutil|ld-linux-x86-64)\.so'
for lib in $(ldd "${BINS[@]}" | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u); do
  name=$(basename "$lib")
  [[ $name =~ $skip ]] && continue
  case $name in libEGL_*|libGLX_*|libnvidia-*|libcuda*) continue;; esac  # vendor libraries: the driver's
  cp -L "$lib" "$STAGE/lib/$name"
done
# GLVND's libOpenGL (not linked: glad loads GL through eglGetProcAddress; kept for tools that want it).
for extra in libOpenGL.so.0; do
  path=$(ldconfig -p | awk -v n="$extra" '$1 == n && /x86-64/ {print $NF; exit}')
  [ -n "$path" ] && cp -L "$path" "$STAGE/lib/$extra"
done
python3 bench/preprocess_scaling.py --scene-only 1000000 1000 >"$STAGE/scenes/scaling-1M-1000.json"
python3 bench/preprocess_scaling.py --scene-only 100000 100 >"$STAGE/scenes/scaling-100k-100.json"
{
  echo "firstshot GPU bundle (scripts/gpu_bundle.sh), $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo "built on $(. /etc/os-release && echo "$PRETTY_NAME"), $(ldd --version | head -1)"
  echo "libraries:"; (cd "$STAGE/lib" && ls -l | awk 'NR > 1 {printf "  %-28s %10d\n", $9, $5}')
} >"$STAGE/MANIFEST"

mkdir -p "$DEST"
tar -C "$STAGE" -cf - bin lib scenes MANIFEST | xz -T"${JOBS:-0}" -9 >"$DEST/bundle.tar.xz.tmp"
mv "$DEST/bundle.tar.xz.tmp" "$DEST/bundle.tar.xz"
raw=$(du -sb "$STAGE" | cut -f1); packed=$(stat -c %s "$DEST/bundle.tar.xz")
tree=$(git ls-files -z | xargs -0 du -cb 2>/dev/null | tail -1 | cut -f1)
printf 'gpu bundle: %s, %.1f MiB (%.1f MiB unpacked, %d libraries); with the tracked tree (%.1f MiB): %.1f of 64 MiB\n' \
  "$DEST/bundle.tar.xz" "$(echo "$packed / 1048576" | bc -l)" "$(echo "$raw / 1048576" | bc -l)" \
  "$(ls "$STAGE/lib" | wc -l)" "$(echo "$tree / 1048576" | bc -l)" "$(echo "($packed + $tree) / 1048576" | bc -l)"

# The check: unpacked elsewhere, the bundle's preprocessor runs on cornell with no other library than the bundle's
# (the C library apart), with OSMesa; ldd shows where each library comes from.
CHECK=$(mktemp -d)
trap 'rm -rf "$CHECK"' EXIT
tar -C "$CHECK" -xJf "$DEST/bundle.tar.xz"
outside=$(env -i LD_LIBRARY_PATH="$CHECK/lib" ldd "$CHECK/bin/firstshot-preprocess" | awk '$3 ~ /^\// {print $1, $3}' \
  | grep -v " $CHECK/lib/" | grep -Ev "$skip" || true)
[ -z "$outside" ] || { echo "gpu_bundle.sh: libraries from outside the bundle: $outside" >&2; exit 1; }
env -i LD_LIBRARY_PATH="$CHECK/lib" "$CHECK/bin/firstshot-preprocess" scenes/cornell.json -o "$CHECK/cornell.fsd" -q \
  --backend gl --gl osmesa --resolution 64
env -i LD_LIBRARY_PATH="$CHECK/lib" "$CHECK/bin/firstshot-fsd-compare" "$CHECK/cornell.fsd" "$CHECK/cornell.fsd" >/dev/null
echo "gpu bundle: checked (bundled binaries ran on scenes/cornell.json with only the bundle's libraries)"
# EGL as well, where this machine has a vendor library (here Mesa's: the one library taken from outside, as the
# device takes NVIDIA's from its driver).
if env -i LD_LIBRARY_PATH="$CHECK/lib" "$CHECK/bin/firstshot-preprocess" --gl-device list >"$CHECK/devices" 2>&1; then
  sed 's/^/  /' "$CHECK/devices"
  env -i LD_LIBRARY_PATH="$CHECK/lib" "$CHECK/bin/firstshot-preprocess" scenes/cornell.json -o "$CHECK/cornell-egl.fsd" \
    -q --backend gl --gl egl --resolution 64 && echo "gpu bundle: EGL ran too"
else
  echo "gpu bundle: EGL lists no device here ($(tail -1 "$CHECK/devices")); OSMesa checked only"
fi
