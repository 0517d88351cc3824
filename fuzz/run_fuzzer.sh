#!/usr/bin/env bash
# run_fuzzer.sh FUZZER SEEDS CORPUS SECONDS [FINDINGS]: fuzzes FUZZER for SECONDS starting from
# SEEDS and FINDINGS (earlier crash inputs, e.g. tests/data/fuzz; both kept read-only) and CORPUS
# (grown); crash, leak and timeout inputs are written to CORPUS/../artifacts. VESSEL_FUZZ_SEED
# fixes libFuzzer's random seed (0 or unset: a new one each run).
set -euo pipefail
fuzzer=$1 seeds=$2 corpus=$3 seconds=$4 findings=${5:-}
artifacts="$(dirname "$corpus")/artifacts/"
mkdir -p "$corpus" "$artifacts"
exec "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -seed="${VESSEL_FUZZ_SEED:-0}" -artifact_prefix="$artifacts" -print_final_stats=1 \
  "$corpus" "$seeds" ${findings:+"$findings"}
