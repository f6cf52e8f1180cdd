#!/bin/sh
# A picture library that is missing (or cannot load because the chart library it needs is missing)
# gives a clear error naming the file, never a crash, and the command exits 1 (issue 41: the
# pictures load when a command draws). Runs `roboplan drill --picture` from a copy of the build's
# layout (bin/roboplan copied, lib/ and lib/roboplan-modules/ as symbolic links, without the file and
# without the modules' manifests, whose library paths are the build's): every library then resolves
# through $ORIGIN in the copy.
# usage: rpMissingPicturesLibraryTest.sh <roboplan> <lib folder>
set -u
roboplan=$1
libdir=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
check() {  # <file to leave out> <file the error must name>
  rm -rf "$work/lib" "$work/bin" && mkdir -p "$work/lib/roboplan-modules" "$work/bin"
  cp "$roboplan" "$work/bin/roboplan"
  for f in "$libdir"/*.so*; do
    [ "$(basename "$f")" = "$1" ] || ln -s "$f" "$work/lib/"
  done
  for f in "$libdir"/roboplan-modules/*.so; do ln -s "$f" "$work/lib/roboplan-modules/"; done
  "$work/bin/roboplan" drill --block --burr-radius 2 --speed 5 --voxel 0.4 --from 0,0,10 --to 0,0,4 \
    --picture "$work/tunnel.png" --json >"$work/out.json" 2>"$work/err.txt"
  code=$?
  if [ "$code" -ne 1 ]; then echo "FAIL without $1: exit code $code (want 1)"; cat "$work/err.txt"; status=1; fi
  if ! grep -q "$2" "$work/err.txt"; then echo "FAIL without $1: the error does not name $2:"; cat "$work/err.txt"; status=1; fi
  if [ -e "$work/tunnel.png" ]; then echo "FAIL without $1: a picture was written"; status=1; fi
  echo "without $1: exit $code: $(head -c 400 "$work/err.txt")"
}
check libRoboPlanDrillingPictures.so libRoboPlanDrillingPictures.so
check libRoboPlanChartsDraw.so libRoboPlanChartsDraw.so
exit $status
