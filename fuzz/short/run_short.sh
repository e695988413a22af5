#!/usr/bin/env bash
# Runs one libFuzzer target for a short while over a copy of its seed corpus (CTest's
# fuzz.<target>.short). Fails when the target is missing or libFuzzer reports a finding, whose
# input is kept under FINDINGS_DIR.
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: $0 FUZZER CORPUS_DIR FINDINGS_DIR SECONDS" >&2
  exit 2
fi
fuzzer="$1" corpus="$2" findings="$3" seconds="$4"
if [ ! -x "$fuzzer" ]; then
  echo "$fuzzer is missing: build the fuzz targets with scripts/build-fuzzers.sh" >&2
  exit 1
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp -R "$corpus/." "$work/"
mkdir -p "$findings"
"$fuzzer" "$work" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$findings/$(basename "$fuzzer")-"
