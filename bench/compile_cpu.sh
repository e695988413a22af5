#!/bin/bash
# Compiler CPU seconds (user + system) of a build directory's objects whose paths match a regex,
# compiled one at a time without ccache, so that batched and file-by-file builds can be compared:
#   bench/compile_cpu.sh build/release 'client/cli/CMakeFiles/(vscan|vscan_cli_args|vscan_campaign_plan)\.dir/'
set -euo pipefail
build_dir=$1
pattern=$2
cd "$build_dir"
total=0
count=0
for object in $(ninja -t targets all | cut -d: -f1 | grep -E "^${pattern}.*\.o$" | sort -u); do
  command=$(ninja -t commands "$object" | tail -1 | sed 's/^.*ccache //; s/ -o [^ ]*/ -o \/dev\/null/')
  /usr/bin/time -f "%U %S" -o /tmp/compile_cpu.$$ bash -c "$command" >/dev/null 2>&1
  seconds=$(awk '{print $1 + $2}' /tmp/compile_cpu.$$)
  printf '%8.2f s  %s\n' "$seconds" "$object"
  total=$(awk -v a="$total" -v b="$seconds" 'BEGIN {print a + b}')
  count=$((count + 1))
done
rm -f /tmp/compile_cpu.$$
printf '%8.2f s  in %d objects\n' "$total" "$count"
