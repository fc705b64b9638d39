#!/usr/bin/env bash
# fuzz/campaign.sh — a long fuzzing campaign of each target (default one hour),
# after the fuzz targets are built (-DMBGC_FUZZ=ON, see fuzz/CMakeLists.txt).
#
#   fuzz/campaign.sh BUILD_DIR [SECONDS] [TARGET...]
#
# Each target runs in libFuzzer's fork mode, which goes on after a crash, a
# timeout (30 s) or an out-of-memory (2 GB) and counts them; the inputs are
# kept in BUILD_DIR/fuzz/campaign/<target>/artifacts. One line per target is
# appended to fuzz/campaign.csv: executions, the coverage reached (libFuzzer's
# `cov`, edges, and `ft`, features), the corpus and the crashes, timeouts
# and out-of-memory kills found. Targets run one after another unless
# PARALLEL=2 (two at once: the machine's two cores). REPORT_ONLY=1 writes
# the CSV lines of the campaigns already in BUILD_DIR without fuzzing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:?usage: fuzz/campaign.sh BUILD_DIR [SECONDS] [TARGET...]}"
build="$(cd "$build" && pwd)"
seconds="${2:-3600}"
shift $(($# >= 2 ? 2 : $#))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_parse fuzz_compile fuzz_modal fuzz_cli)
csv="$root/fuzz/campaign.csv"
[ -f "$csv" ] || echo "date,commit,target,seconds,executions,cov,ft,corpus,crashes,timeouts,ooms" > "$csv"
commit=$(git -C "$root" rev-parse --short HEAD)

seeds_of() {
  case "$1" in
    fuzz_modal) echo "$build/fuzz/seeds/mbm" ;;
    fuzz_cli) echo "$root/fuzz/cli_seeds" ;;
    *) echo "$build/fuzz/seeds/mbg" ;;
  esac
}

# The CSV line of a finished campaign, from fork mode's last status line:
# "#N: cov: C ft: F corp: K exec/s E oom/timeout/crash: O/T/X time: Ss job: J"
summarise() {
  local t="$1" log="$build/fuzz/campaign/$1/log.txt" last
  last=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 || true)
  [ -n "$last" ] || { echo "$t: no status line in $log" >&2; return 1; }
  local execs cov ft corp oom timeout crash
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
  cov=$(sed -E 's/.* cov: ([0-9]+).*/\1/' <<<"$last")
  ft=$(sed -E 's/.* ft: ([0-9]+).*/\1/' <<<"$last")
  corp=$(sed -E 's/.* corp: ([0-9]+).*/\1/' <<<"$last")
  IFS=/ read -r oom timeout crash <<<"$(sed -E 's#.* oom/timeout/crash: ([0-9]+/[0-9]+/[0-9]+).*#\1#' <<<"$last")"
  echo "$(date -u +%F),$commit,$t,$seconds,$execs,$cov,$ft,$corp,$crash,$timeout,$oom" | tee -a "$csv"
}

one() {
  local t="$1" dir="$build/fuzz/campaign/$1"
  if [ -z "${REPORT_ONLY:-}" ]; then
    rm -rf "$dir"
    mkdir -p "$dir/corpus" "$dir/artifacts"
    echo "==> $t: $seconds s (log: $dir/log.txt)"
    (cd "$dir" && "$build/fuzz/$t" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
      -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -close_fd_mask=3 \
      -artifact_prefix="$dir/artifacts/" "$dir/corpus" "$(seeds_of "$t")" > "$dir/log.txt" 2>&1) || true
  fi
  summarise "$t"
}

if [ "${PARALLEL:-1}" = 2 ]; then
  for ((k = 0; k < ${#targets[@]}; k += 2)); do
    one "${targets[k]}" &
    [ $((k + 1)) -lt ${#targets[@]} ] && one "${targets[k + 1]}" &
    wait
  done
else
  for t in "${targets[@]}"; do one "$t"; done
fi
