#!/usr/bin/env bash
# ThreadSanitizer over the suites whose code runs in parallel (docs/reliability.md,
# "ThreadSanitizer"): configures the `tsan` preset, builds only those suites
# (target sarmap_tsan_suites, listed in tests/CMakeLists.txt as
# SARMAP_TSAN_SUITES) and runs their tests (label tsan) with the preset's
# TSAN_OPTIONS (halt_on_error=1, suppressions=tools/tsan.supp). Exits non-zero
# on any race report, deadlock report or failing test; prints the elapsed time.
#   tools/tsan.sh            configure, build, run
#   tools/tsan.sh -R REGEX   only the tests whose names match (ctest -R)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
log=build/tsan/tsan-ctest.log

cmake --preset tsan
cmake --build --preset tsan
configured_built=$(( $(date +%s) - start ))

status=0
ctest --preset tsan -j2 "$@" 2>&1 | tee "$log" || status=$?
# halt_on_error already fails the test that raced; this also catches a report
# from a test that would otherwise pass (e.g. one printed at exit).
if grep -q "WARNING: ThreadSanitizer" "$log"; then
  echo "tsan: ThreadSanitizer reports (see $log):" >&2
  grep -E "SUMMARY: ThreadSanitizer" "$log" | sort | uniq -c >&2
  status=1
fi
if ! grep -q "tests passed" "$log"; then
  echo "tsan: ctest ran no tests" >&2
  status=1
fi
echo "tsan: configure + build ${configured_built} s, total $(( $(date +%s) - start )) s, exit ${status}"
exit "$status"
