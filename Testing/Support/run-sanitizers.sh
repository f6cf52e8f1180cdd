#!/usr/bin/env bash
# run-sanitizers.sh [asan|tsan|both] [extra ctest arguments...]
# The tests labelled `sanitize` (the readers and doors that take outside input: Slicer's
# .mrml/.mrb and .mrk.json, PLUS recordings and commands, NDI .rom files, DICOM SEG/RTSTRUCT, the
# served OpenIGTLink port, the viewer's loading thread) under AddressSanitizer + UBSan (build dir
# build-asan) and ThreadSanitizer (build-tsan): configures the build dir when needed (as
# SuperBuild/setup.sh does), builds only those tests (and what they need), runs `ctest -L
# sanitize`. Prints one summary line per sanitizer; exits non-zero when a test failed.
# Environment: ROBOPLAN_SHARED_DATA_DIR (default ../shared/data beside the source folder).
set -uo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
which=${1:-both}
shift || true
case "$which" in
  asan) runs=("asan:address,undefined") ;;
  tsan) runs=("tsan:thread") ;;
  both) runs=("asan:address,undefined" "tsan:thread") ;;
  *) echo "run-sanitizers.sh: asan, tsan or both, not '$which'" >&2; exit 2 ;;
esac
export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$src_dir}"
shared=${ROBOPLAN_SHARED_DATA_DIR:-$src_dir/../shared/data}
status=0
summary=()
for run in "${runs[@]}"; do
  name=${run%%:*} sanitize=${run#*:}
  build_dir="$src_dir/build-$name"
  if ! grep -q "ROBOPLAN_SANITIZE:STRING=$sanitize\$" "$build_dir/CMakeCache.txt" 2>/dev/null; then
    cmake -S "$src_dir" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
      -DROBOPLAN_BUILD_GUI=ON -DROBOPLAN_BUILD_BENCHMARKS=OFF -DROBOPLAN_SANITIZE="$sanitize" \
      -DROBOPLAN_SHARED_DATA_DIR="$shared" -DROBOPLAN_ORACLES_DIR="$shared/../oracles" >/dev/null || exit 1
  fi
  # The labelled tests are roboplan_add_test targets: the test's name is its target's.
  mapfile -t tests < <(cd "$build_dir" && ctest -N -L sanitize | sed -n 's/^ *Test *#[0-9]*: *//p')
  echo "== $name ($sanitize): building ${#tests[@]} tests: ${tests[*]}"
  cmake --build "$build_dir" -j "$(nproc 2>/dev/null || echo 2)" --target "${tests[@]}" || exit 1
  echo "== $name: ctest -L sanitize"
  (cd "$build_dir" && ctest -L sanitize --output-on-failure "$@") | tee "$build_dir/sanitize-run.log"
  result=${PIPESTATUS[0]}
  summary+=("$name: $(grep -E 'tests passed|tests failed' "$build_dir/sanitize-run.log" | tail -n 1)")
  [ "$result" -eq 0 ] || status=1
done
printf '%s\n' "${summary[@]}"
exit $status
