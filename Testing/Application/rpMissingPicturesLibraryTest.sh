#!/bin/sh
# A library loaded when a command draws (issue 41) that is missing, or cannot load because a
# library it needs is missing, gives a clear error naming the file, never a crash, and the command
# exits 1: `roboplan drill --picture` without the drilling pictures or the chart library, and, in
# builds with the viewer, `roboplan screenshot` and the viewer's window without libRoboPlanViewer.so;
# `roboplan plan` and `roboplan mesh` on a DICOM file without the DICOM library (libRoboPlanDicom.so,
# loaded on the first DICOM read: Libs/Imaging/rpDicomEntries.h).
# Runs from a copy of the build's layout (bin/roboplan copied, lib/ and lib/roboplan-modules/ as
# symbolic links, without the file and without the modules' manifests, whose library paths are the
# build's): every library then resolves through $ORIGIN in the copy.
# usage: rpMissingPicturesLibraryTest.sh <roboplan> <lib folder> <with viewer: 1|0>
set -u
roboplan=$1
libdir=$(cd "$2" && pwd)
viewer=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
# check <file to leave out> <what the error must name (a grep pattern)> <output that must not be written> <roboplan arguments...>
check() {
  leftOut=$1 named=$2 output=$3
  shift 3
  rm -rf "$work/lib" "$work/bin" "$output" && mkdir -p "$work/lib/roboplan-modules" "$work/bin"
  cp "$roboplan" "$work/bin/roboplan"
  for f in "$libdir"/*.so*; do
    [ "$(basename "$f")" = "$leftOut" ] || ln -s "$f" "$work/lib/"
  done
  for f in "$libdir"/roboplan-modules/*.so; do ln -s "$f" "$work/lib/roboplan-modules/"; done
  "$work/bin/roboplan" "$@" >"$work/out.txt" 2>"$work/err.txt"
  code=$?
  what="roboplan ${1:-(no command)} without $leftOut"
  if [ "$code" -ne 1 ]; then echo "FAIL $what: exit code $code (want 1)"; cat "$work/err.txt"; status=1; fi
  if ! grep -q "$named" "$work/err.txt"; then echo "FAIL $what: the error does not name $named:"; cat "$work/err.txt"; status=1; fi
  # (an output folder a command creates before it reads may stay, empty)
  if [ -e "$output" ] && ! { [ -d "$output" ] && [ -z "$(ls -A "$output")" ]; }; then
    echo "FAIL $what: $output was written"; status=1
  fi
  echo "$what: exit $code: $(head -c 400 "$work/err.txt")"
}
drill() {
  check "$1" "$2" "$work/tunnel.png" drill --block --burr-radius 2 --speed 5 --voxel 0.4 --from 0,0,10 --to 0,0,4 \
    --picture "$work/tunnel.png" --json
}
drill libRoboPlanDrillingPictures.so libRoboPlanDrillingPictures.so
drill libRoboPlanChartsDraw.so libRoboPlanChartsDraw.so
# A DICOM Part 10 file (preamble and magic only): the loader's DICOM reader claims it without DCMTK.
head -c 128 /dev/zero >"$work/ct.dcm" && printf 'DICM' >>"$work/ct.dcm"
# The error names the file read and the library: the reader's own message, not a module's.
dicomError="ct.dcm: DICOM is not available: cannot load .*libRoboPlanDicom.so"
check libRoboPlanDicom.so "$dicomError" "$work/plan.mrk.json" plan trajectory --volume "$work/ct.dcm" \
  --entry 0,0,10 --target 0,0,0 --diameter 2 --out "$work/plan.mrk.json"
check libRoboPlanDicom.so "$dicomError" "$work/meshes" mesh "$work/ct.dcm" --out "$work/meshes"
if [ "$viewer" = 1 ]; then
  # A 2x2x2 volume (NRRD, raw) for the screenshot to load before it draws.
  printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspace: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nencoding: raw\n\n' >"$work/v.nrrd"
  printf '\000\001\002\003\004\005\006\007' >>"$work/v.nrrd"
  check libRoboPlanViewer.so libRoboPlanViewer.so "$work/view.png" screenshot "$work/v.nrrd" --out "$work/view.png"
  # The viewer's window: no command (every module loads, then the window's library does not).
  check libRoboPlanViewer.so libRoboPlanViewer.so "$work/none"
fi
exit $status
