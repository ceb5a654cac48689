#!/usr/bin/env bash
# Runs the libFuzzer targets of fuzz/ (docs/reliability.md, "Fuzzing"):
#   tools/fuzz.sh TARGET SECONDS     one target, e.g. tools/fuzz.sh ply 120
#   tools/fuzz.sh all SECONDS        every target, one after another, SECONDS each
#   tools/fuzz.sh list               the target names
# Configures and builds the `fuzz` preset when needed (clang-14; see
# tools/install-deps.sh). Each run starts from a fresh copy of the target's
# seeds, fuzz/corpus/TARGET, in build/fuzz/runs/TARGET/, so the committed
# corpus never grows. Exits non-zero when any target crashes, leaks, times out
# or runs out of memory, and prints the reproducer's path and the command that
# replays it.
set -euo pipefail
cd "$(dirname "$0")/.."

# Target and the longest input it gets (-max_len), by format: a few times the
# largest seed, small enough that every execution stays fast.
declare -A MAX_LEN=(
  [ply]=4096 [pcd]=4096 [npy]=1024 [safetensors]=8192 [dgcnn_model]=8192
  [arena]=8192 [sarmap_sequence]=4096 [tum]=2048 [seven_scenes]=1024
  [depth_png]=4096 [map_file]=16384 [ros_messages]=4096
)
TARGETS=(ply pcd npy safetensors dgcnn_model arena sarmap_sequence tum seven_scenes depth_png map_file ros_messages)

# A run of one input over this many seconds is a timeout; one allocation or a
# resident size over this many MB is an out-of-memory finding (a parser must
# refuse a huge declared size before allocating, not after).
TIMEOUT=5
RSS_LIMIT_MB=2048

usage() {
  echo "usage: tools/fuzz.sh TARGET|all SECONDS   (targets: ${TARGETS[*]})" >&2
  exit 2
}

if [[ "${1:-}" == "list" ]]; then
  printf '%s\n' "${TARGETS[@]}"
  exit 0
fi
[[ $# -eq 2 ]] || usage
what=$1
seconds=$2
[[ "$seconds" =~ ^[0-9]+$ && "$seconds" -gt 0 ]] || usage
if [[ "$what" == "all" ]]; then
  selected=("${TARGETS[@]}")
elif [[ -n "${MAX_LEN[$what]:-}" ]]; then
  selected=("$what")
else
  usage
fi

# Build (a no-op when up to date).
if [[ ! -f build/fuzz/build.ninja ]]; then
  cmake --preset fuzz >/dev/null
fi
build_start=$(date +%s)
cmake --build --preset fuzz
echo "fuzz: build took $(( $(date +%s) - build_start )) s"

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"

failed=()
summary=()
for target in "${selected[@]}"; do
  binary="build/fuzz/fuzz/${target}_fuzz"
  if [[ "$target" == ros_messages && ! -x "$binary" ]]; then
    # Built only with librosbag-storage-dev (fuzz/CMakeLists.txt).
    summary+=("$(printf '%-16s %10s execs %5s s  skipped (no librosbag-storage-dev)' "$target" 0 0)")
    continue
  fi
  run_dir="build/fuzz/runs/$target"
  rm -rf "$run_dir"
  mkdir -p "$run_dir/corpus"
  cp fuzz/corpus/"$target"/* "$run_dir/corpus/"
  log="$run_dir/fuzz.log"
  start=$(date +%s)
  status=0
  "$binary" -max_total_time="$seconds" -max_len="${MAX_LEN[$target]}" -timeout="$TIMEOUT" \
    -rss_limit_mb="$RSS_LIMIT_MB" -print_final_stats=1 -artifact_prefix="$run_dir/" \
    "$run_dir/corpus" >"$log" 2>&1 || status=$?
  took=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  execs=${execs:-?}
  artifacts=$(find "$run_dir" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' \
    -o -name 'oom-*' \) | sort)
  if [[ $status -ne 0 || -n "$artifacts" ]]; then
    failed+=("$target")
    summary+=("$(printf '%-16s %10s execs %5s s  FAILED (exit %s)' "$target" "$execs" "$took" "$status")")
    echo "fuzz: $target FAILED (exit $status) after $took s; last lines of $log:" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written|terminate called|what\(\)' "$log" | tail -8 >&2 || true
    for a in $artifacts; do
      echo "fuzz: reproducer $a  (replay: $binary $a)" >&2
    done
  else
    summary+=("$(printf '%-16s %10s execs %5s s  ok' "$target" "$execs" "$took")")
  fi
done

echo "fuzz: target            executions   time  result"
printf 'fuzz: %s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: findings in: ${failed[*]} (logs in build/fuzz/runs/TARGET/fuzz.log)" >&2
  exit 1
fi
