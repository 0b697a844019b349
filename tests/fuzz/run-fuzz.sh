#!/usr/bin/env bash
# Runs the libFuzzer targets of a FAIRSPLINE_FUZZ build (see `make fuzz`, docs/fuzzing.md).
#   tests/fuzz/run-fuzz.sh [--smoke] BUILD_DIR SECONDS [TARGET...]
# Each target runs SECONDS seconds (-max_total_time) on two corpora: its writable corpus
# BUILD_DIR/fuzz-corpus/<target> (new inputs go there; not committed) and the committed seeds
# tests/fuzz/corpus/<target>, read only; fuzz_fit also on the seeds of the registry as it is now
# (make_fit_seeds.py: each method's example requests and the hand-made shapes, with a dictionary
# of the method names) when a fairspline CLI is at hand ($FAIRSPLINE_CLI, BUILD_DIR/apps/cli/ or
# build/apps/cli/), so that a method added since the committed seeds were written is fuzzed from
# its examples. A crash, leak, timeout (> 10 s for one input) or
# out-of-memory stops the run with the reproducer's path; the last lines of each log
# (executions, exec/s, cov, ft, corpus) are printed as a summary.
# --smoke (the CTest tests fuzz.smoke.*): exit 77 (skipped) when the target is not built; a
# fixed seed and a fresh writable corpus each time, so that the run does not depend on earlier
# ones.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
smoke=0
if [ "${1:-}" = "--smoke" ]; then
  smoke=1
  shift
fi
build="${1:?usage: run-fuzz.sh [--smoke] BUILD_DIR SECONDS [TARGET...]}"
seconds="${2:?usage: run-fuzz.sh [--smoke] BUILD_DIR SECONDS [TARGET...]}"
shift 2
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(fuzz_csv fuzz_json fuzz_fit fuzz_server); fi

for t in "${targets[@]}"; do
  exe="$build/tests/fuzz/$t"
  if [ ! -x "$exe" ]; then
    echo "run-fuzz: $exe is missing (make fuzz-build; needs clang and libFuzzer)" >&2
    if [ "$smoke" = 1 ]; then exit 77; fi
    exit 2
  fi
  corpus="$build/fuzz-corpus/$t"
  artifacts="$build/fuzz-artifacts/$t"
  log="$build/fuzz-logs/$t.log"
  seed=()
  if [ "$smoke" = 1 ]; then
    corpus="$build/fuzz-smoke-corpus/$t"
    log="$build/fuzz-logs/smoke-$t.log"
    rm -rf "$corpus"
    seed=(-seed=1)
  fi
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  dict=()
  case "$t" in
    fuzz_csv) dict=(-dict="$here/csv.dict") ;;
    fuzz_json | fuzz_server) dict=(-dict="$here/json.dict") ;;
    fuzz_fit) dict=(-dict="$here/fit.dict") ;;
  esac
  seeds=()
  if [ "$t" = fuzz_fit ]; then
    cli="${FAIRSPLINE_CLI:-}"
    for c in "$build/apps/cli/fairspline" "$here/../../build/apps/cli/fairspline"; do
      if [ -z "$cli" ] && [ -x "$c" ]; then cli="$c"; fi
    done
    out="$build/fuzz-seeds/fuzz_fit"
    if [ -n "$cli" ] && /usr/bin/python3 "$here/make_fit_seeds.py" --cli "$cli" --out "$out" \
      --dict "$out.dict" >/dev/null; then
      seeds=("$out")
      dict=(-dict="$out.dict")
    else
      echo "run-fuzz: fuzz_fit from the committed seeds only (no fairspline CLI to read" \
        "the registry's examples from)"
    fi
  fi
  echo "run-fuzz: $t for ${seconds}s (log $log)"
  status=0
  "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "${dict[@]}" "${seed[@]}" \
    "$corpus" "$here/corpus/$t" "${seeds[@]}" >"$log" 2>&1 || status=$?
  # Summary: the last status line (#N DONE/pulse cov ft corp exec/s) and the final stats.
  grep -E '^#[0-9]+' "$log" | tail -n 1 || true
  grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)' "$log" || true
  if [ "$status" -ne 0 ]; then
    echo "run-fuzz: $t FAILED (exit $status); last lines of $log:" >&2
    tail -n 40 "$log" >&2
    repro="$(grep -Eo "(Test unit written to|written to) [^ ]+" "$log" | tail -n 1 | awk '{print $NF}')"
    if [ -n "$repro" ]; then
      echo "run-fuzz: reproducer: $repro" >&2
      echo "run-fuzz: replay it with: $exe $repro" >&2
    fi
    exit 1
  fi
done
