#!/usr/bin/env bash
# run_doc_block.sh DOC.md LANG N -- COMMAND...: extracts the N-th (1-based)
# ```LANG block of DOC.md into a temporary file and runs COMMAND FILE, so that
# documented examples are tested as written.
set -euo pipefail
doc="$1"; lang="$2"; n="$3"; shift 3
[ "$1" = "--" ] && shift
tmp=$(mktemp --suffix=".$lang")
trap 'rm -f "$tmp"' EXIT
awk -v want="$n" -v lang="$lang" '
  $0 == "```" lang { k++; if (k == want) { f = 1; next } }
  /^```/ { if (f) exit }
  f' "$doc" > "$tmp"
if [ ! -s "$tmp" ]; then echo "no \`\`\`$lang block $n in $doc"; exit 1; fi
"$@" "$tmp"
