#!/usr/bin/env bash
# docs/cli.md's generated parts: each tool's --help, verbatim, between the markers
#   <!-- cli-doc: TOOL -->
#   <!-- cli-doc end -->
# (the hand-written text around them is kept as it is). The ctest cli_doc_current runs this with --check, so the
# command reference cannot drift from the tools.
#
#   bash scripts/cli-doc.sh                        # rewrite docs/cli.md from build/release's tools
#   bash scripts/cli-doc.sh --check [EXE...]       # exit 1 with a diff when docs/cli.md is stale
#   bash scripts/cli-doc.sh --out F [EXE...]       # write the result to F instead
#
# EXE: the tools' executables (default: build/release's firstshot-preprocess, firstshot-fsd-compare and
# firstshot-render); each marker's TOOL is matched by the executable's file name, which is also the name --help
# prints (argv[0] is set to it, so the build folder's path never reaches the file).
set -euo pipefail
export LC_ALL=C

root="$(cd "$(dirname "$0")/.." && pwd)"
doc="$root/docs/cli.md"
check=0
out=""
exes=()
while (($#)); do
  case "$1" in
    --check) check=1 ;;
    --out) out="$2"; shift ;;
    --doc) doc="$2"; shift ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "cli-doc.sh: unknown option $1" >&2; exit 2 ;;
    *) exes+=("$1") ;;
  esac
  shift
done
if ((${#exes[@]} == 0)); then
  exes=("$root/build/release/preprocess/firstshot-preprocess" "$root/build/release/preprocess/firstshot-fsd-compare"
        "$root/build/release/render/firstshot-render")
fi

declare -A exe_of
for e in "${exes[@]}"; do
  [[ -x "$e" ]] || { echo "cli-doc.sh: $e: not an executable (build the tools first)" >&2; exit 2; }
  exe_of["$(basename "$e")"]="$e"
done

# One tool's help as it goes into the file: a fenced block, trailing blanks removed.
help_block() {
  local name="$1" exe="$2" text
  if ! text="$(exec -a "$name" "$exe" --help 2>&1)"; then
    echo "cli-doc.sh: $name --help failed:" >&2
    printf '%s\n' "$text" >&2
    return 1
  fi
  printf '```text\n$ %s --help\n' "$name"
  printf '%s\n' "$text" | sed 's/[[:space:]]*$//'
  printf '```\n'
}

generate() {
  local line name inside=0 seen=0
  while IFS= read -r line || [[ -n "$line" ]]; do
    if ((inside)); then
      if [[ "$line" == "<!-- cli-doc end -->" ]]; then
        inside=0
        printf '%s\n' "$line"
      fi
      continue
    fi
    printf '%s\n' "$line"
    if [[ "$line" =~ ^\<!--\ cli-doc:\ ([A-Za-z0-9_.-]+)\ --\>$ ]]; then
      name="${BASH_REMATCH[1]}"
      [[ -n "${exe_of[$name]:-}" ]] || { echo "cli-doc.sh: no executable given for $name (marker in $doc)" >&2; return 1; }
      help_block "$name" "${exe_of[$name]}" || return 1
      inside=1
      seen=$((seen + 1))
    fi
  done < "$doc"
  ((inside == 0)) || { echo "cli-doc.sh: $doc: a cli-doc marker without <!-- cli-doc end -->" >&2; return 1; }
  ((seen > 0)) || { echo "cli-doc.sh: $doc: no <!-- cli-doc: TOOL --> marker" >&2; return 1; }
}

tmp="$(mktemp "${TMPDIR:-/tmp}/cli-doc.XXXXXX")"
trap 'rm -f "$tmp"' EXIT
generate > "$tmp"

if ((check)); then
  if ! diff -u --label "$doc (committed)" --label "$doc (from the tools' --help)" "$doc" "$tmp"; then
    echo "cli-doc.sh: docs/cli.md is stale: run 'bash scripts/cli-doc.sh' (after building) and commit the result" >&2
    exit 1
  fi
  echo "docs/cli.md matches the tools' --help (${#exe_of[@]} tools)"
elif [[ -n "$out" ]]; then
  cp "$tmp" "$out"
else
  cp "$tmp" "$doc"
  echo "wrote $doc"
fi
