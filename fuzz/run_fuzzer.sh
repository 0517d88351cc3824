#!/usr/bin/env bash
# run_fuzzer.sh FUZZER SEEDS CORPUS SECONDS: fuzzes FUZZER for SECONDS starting from SEEDS (kept
# read-only) and CORPUS (grown); crash, leak and timeout inputs are written to CORPUS/../artifacts.
set -euo pipefail
fuzzer=$1 seeds=$2 corpus=$3 seconds=$4
artifacts="$(dirname "$corpus")/artifacts/"
mkdir -p "$corpus" "$artifacts"
exec "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -artifact_prefix="$artifacts" -print_final_stats=1 "$corpus" "$seeds"
