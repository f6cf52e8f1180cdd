#!/usr/bin/env bash
# Installs the Debian packages RoboPlan builds on, only those missing, and says which.
#   install-dependencies.sh          what building RoboPlan and running it (the demo) needs
#   install-dependencies.sh --test   also what only the tests use (tools that write their inputs,
#                                    the fuzzers' clang, gdb, the workflow's snakemake and Slurm)
set -euo pipefail
packages=(
  build-essential cmake ninja-build ccache pkg-config
  lld                                  # a linker 4-10x faster than GNU ld on our links (setup.sh picks it)
  libvtk9-dev libvtk9-qt-dev           # VTK 9.1 (+ Qt widgets)
  libinsighttoolkit5-dev               # ITK 5.2
  libdcmtk-dev                         # DCMTK 3.6.7
  libgdcm-dev libcharls-dev            # GDCM 3.0 decodes JPEG 2000 (OpenJPEG); CharLS 2 decodes JPEG-LS
  qtbase5-dev                          # Qt 5.15
  libeigen3-dev                        # Eigen 3.4
  libopenigtlink-dev                   # OpenIGTLink 1.11
  nlohmann-json3-dev                   # JSON for scene files, .mrk.json and --json output
  libdeflate-dev                       # whole-buffer gzip/zlib: gzip NRRD voxels in, .vtp blocks out
  libarchive-dev                       # zip: 3D Slicer's .mrb scene bundles in and out
  libfftw3-dev                         # referenced by ITK's and VTK's exported CMake targets
  libgtest-dev libgmock-dev libbenchmark-dev  # found at configure time (tests and benchmarks are on by default)
  xvfb xauth libgl1-mesa-dri libglx-mesa0  # offscreen rendering with Mesa's software OpenGL (demo, charts, GUI tests)
)
if [ "${1:-}" = "--test" ]; then
  packages+=(
    libteem-dev rapidjson-dev          # 3D Slicer's MRML library as a test oracle (Testing/Oracles/SlicerMRML; + libarchive-dev)
    dcmtk libgdcm-tools                # dcmcjpeg, dcmcjpls, dcmcrle, dcmconv, dcmodify, gdcmconv: tests encode real series with them
    python3-pydicom python3-numpy      # pydicom: the independent reader (and RTSTRUCT writer) of the DICOM segmentation tests
    dicom3tools                        # dciodvfy: our SEG checked against the IOD by David Clunie's verifier
    clang libclang-rt-14-dev           # libFuzzer targets of every parser (ctest -L fuzz)
    gdb                                # rpXvfbTeardownTest stages Xvfb's SIGTERM race with it
    snakemake                          # workflow/: cohorts, locally or on a cluster
    slurm-wlm munge                    # the workflow's Slurm test starts a one-node cluster
  )
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "== dependencies: all ${#packages[@]} Debian packages present"
  exit 0
fi
echo "== dependencies: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
