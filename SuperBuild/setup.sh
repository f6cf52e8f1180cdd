#!/usr/bin/env bash
# RoboPlan set-up: installs what is missing from Debian's packages, then configures and builds
# with Ninja, ccache and a fast linker (lld). Idempotent: a second run installs nothing and builds
# incrementally. Each action builds only what it runs: --demo the application and its modules,
# --test everything (the benchmarks too: their smoke test runs them; not with --no-benchmarks), no
# action everything with the benchmarks. ccache's paths
# are relative to the source folder, so a fresh clone elsewhere reuses an earlier clone's cache.
#
#   SuperBuild/setup.sh [--build-dir DIR] [--type Release|Debug|RelWithDebInfo]
#                       [--sanitize address|undefined|address,undefined|thread] [--no-gui] [--no-benchmarks]
#                       [--test [ctest args...]] [--demo [demo args...]]
set -euo pipefail
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$src_dir/build"
build_type=Release
sanitize=""
gui=ON
benchmarks=ON
action=build
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir=$2; shift 2 ;;
    --type) build_type=$2; shift 2 ;;
    --sanitize) sanitize=$2; shift 2 ;;
    --no-gui) gui=OFF; shift ;;
    --no-benchmarks) benchmarks=OFF; shift ;;
    --test) action=test; shift; extra=("$@"); break ;;
    --demo) action=demo; shift; extra=("$@"); break ;;
    -h|--help) sed -n 2,8p "$0"; exit 0 ;;
    *) echo "setup.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done

packages=()
if [ "$action" = test ]; then packages=(--test); fi  # the tests' own tools only where tests run
"$src_dir/SuperBuild/install-dependencies.sh" "${packages[@]}"

export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$src_dir}"
jobs=$(nproc 2>/dev/null || echo 2)
# Tests wait on X servers, sockets, serial ports and child processes: half as many tests again as
# cores keeps the cores busy (the whole suite on 2 cores: 378 s at -j2, 293 s at -j3, 6 % idle).
test_jobs=$((jobs + (jobs + 1) / 2))
# Configure again when the test tools arrived after a first configure without them (the fuzzers'
# clang is looked for at configure time).
stamp="$build_dir/.roboplan-packages"
if [ ! -f "$build_dir/build.ninja" ] || [ "$src_dir/CMakeLists.txt" -nt "$build_dir/build.ninja" ] \
   || ! grep -q "ROBOPLAN_SANITIZE:STRING=$sanitize\$" "$build_dir/CMakeCache.txt" 2>/dev/null \
   || { [ "$action" = test ] && ! grep -qx test "$stamp" 2>/dev/null; }; then
  echo "== configure ($build_type, sanitize='${sanitize}', gui=$gui, benchmarks=$benchmarks) in $build_dir"
  cmake -S "$src_dir" -B "$build_dir" -G Ninja \
    -DCMAKE_BUILD_TYPE="$build_type" \
    -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
    -DROBOPLAN_BUILD_GUI=$gui -DROBOPLAN_BUILD_BENCHMARKS=$benchmarks \
    -DROBOPLAN_SANITIZE="$sanitize"
  if [ "$action" = test ]; then echo test >"$stamp"; fi
fi
case "$action" in
  demo) targets=(--target roboplan) ;;  # the application and the modules it loads
  test) targets=() ;;                   # the default target: with tests on, the benchmarks too
  *) targets=(--target all); if [ "$benchmarks" = ON ]; then targets+=(benchmarks); fi ;;
esac
echo "== build (-j$jobs${targets[*]:+ ${targets[*]}})"
cmake --build "$build_dir" -j "$jobs" "${targets[@]}"

case "$action" in
  test)
    echo "== test"
    cd "$build_dir"
    ctest --output-on-failure -j "$test_jobs" "${extra[@]}"
    ;;
  demo)
    echo "== roboplan demo"
    # Without a display the demo draws its pictures on a private Xvfb of its own (Libs/Charts/rpXDisplay.h).
    exec "$build_dir/bin/roboplan" demo "${extra[@]}"
    ;;
esac
