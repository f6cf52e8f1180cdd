#!/bin/sh
# A library loaded on first use (issue 41) that is missing, or cannot load because a library it
# needs is missing, gives a clear error naming the file, never a crash, and the command exits 1:
# `roboplan drill --picture` without the drilling pictures or the chart library, and, in builds with
# the viewer, `roboplan screenshot` and the viewer's window without libRoboPlanViewer.so;
# without the DICOM library (libRoboPlanDicom.so, Libs/Imaging/rpDicomEntries.h): `roboplan plan`
# and `roboplan mesh` on a DICOM file (the loader), `roboplan dicom` (the Volumes logic's scan),
# `roboplan convert` into a DICOM series and into a DICOM SEG (the logic's writes);
# `roboplan register-volumes` without the registration (libRoboPlanVolumeRegistration.so); `roboplan
# mesh` thresholding or splitting bones without segmentation's ITK (libRoboPlanSegmentationItk.so); and the
# storage's formats: a NRRD without ITK's image IO (libRoboPlanItkImageIO.so), an STL without VTK's
# geometry IO (libRoboPlanVtkGeometryIO.so), a Slicer .mrb without its zip (libRoboPlanMrmlBundle.so).
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
check libRoboPlanDicom.so "$dicomError" "$work/none" dicom "$work/ct.dcm"
# A 2x2x2 volume (NRRD, raw): read before a command registers, writes DICOM or draws.
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspace: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nencoding: raw\n\n' >"$work/v.nrrd"
printf '\000\001\002\003\004\005\006\007' >>"$work/v.nrrd"
check libRoboPlanDicom.so "series: DICOM is not available: cannot load .*libRoboPlanDicom.so" "$work/series" \
  convert "$work/v.nrrd" "$work/series"
# Its labels as a segmentation (the whole build), then written as a DICOM SEG on ct.dcm without DICOM.
"$roboplan" convert "$work/v.nrrd" "$work/v.seg.nrrd" --input-kind labelmap >/dev/null 2>&1 ||
  { echo "FAIL: cannot make v.seg.nrrd with the whole build"; status=1; }
check libRoboPlanDicom.so "seg.dcm: DICOM is not available: cannot load .*libRoboPlanDicom.so" "$work/seg.dcm" \
  convert "$work/v.seg.nrrd" "$work/seg.dcm" --reference "$work/ct.dcm"
check libRoboPlanVolumeRegistration.so "registration is not available: cannot load .*libRoboPlanVolumeRegistration.so" \
  "$work/t.tfm" register-volumes "$work/v.nrrd" "$work/v.nrrd" --out "$work/t.tfm"
check libRoboPlanItkImageIO.so "v.nrrd': NRRD, NIfTI and MetaImage are not available: cannot load .*libRoboPlanItkImageIO.so" \
  "$work/meshes" mesh "$work/v.nrrd" --out "$work/meshes"
# Segmentation's ITK filters (libRoboPlanSegmentationItk.so): a threshold, and the bone split's
# body outline (a morphological opening).
segmentationError="segmentation with ITK is not available: cannot load .*libRoboPlanSegmentationItk.so"
check libRoboPlanSegmentationItk.so "$segmentationError" "$work/meshes" mesh "$work/v.nrrd" --lower 1 --upper 7 \
  --out "$work/meshes"
check libRoboPlanSegmentationItk.so "$segmentationError" "$work/meshes" mesh "$work/v.nrrd" --split-bones --lower 1 \
  --out "$work/meshes"
# Three fiducials (Slicer's .fcsv) and an ASCII STL for the ICP of `roboplan register`.
printf '# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n1,0,0,0,0,0,0,1,1,1,0,A,,\n2,10,0,0,0,0,0,1,1,1,0,B,,\n3,0,10,0,0,0,0,1,1,1,0,C,,\n' >"$work/f.fcsv"
printf 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n' >"$work/s.stl"
check libRoboPlanVtkGeometryIO.so "s.stl': STL and OBJ are not available: cannot load .*libRoboPlanVtkGeometryIO.so" \
  "$work/r.tfm" register "$work/f.fcsv" "$work/f.fcsv" --out "$work/r.tfm" --icp-points "$work/f.fcsv" --icp-model "$work/s.stl"
printf 'PK\005\006' >"$work/b.mrb" && head -c 18 /dev/zero >>"$work/b.mrb"  # an empty zip
check libRoboPlanMrmlBundle.so "b.mrb': Slicer bundles (.mrb) are not available: cannot load .*libRoboPlanMrmlBundle.so" \
  "$work/b.rpscene" convert "$work/b.mrb" "$work/b.rpscene"
if [ "$viewer" = 1 ]; then
  check libRoboPlanViewer.so libRoboPlanViewer.so "$work/view.png" screenshot "$work/v.nrrd" --out "$work/view.png"
  # The viewer's window: no command (every module loads, then the window's library does not).
  check libRoboPlanViewer.so libRoboPlanViewer.so "$work/none"
fi
exit $status
