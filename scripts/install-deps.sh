#!/usr/bin/env bash
# Installs the Debian 12 packages that vdbappear builds and tests with.
# Idempotent: asks dpkg first and calls apt-get only for what is missing.
# Usage: scripts/install-deps.sh [--print]   (--print lists the packages and exits)
set -euo pipefail

packages=(
  # toolchain, and python3 for the demo and benchmark scripts
  g++ make cmake ninja-build ccache pkg-config python3
  # OpenVDB 10 (+ the Boost iostreams its FindOpenVDB asks for: build note 2)
  libopenvdb-dev libboost-iostreams-dev libboost-dev libtbb-dev
  # maths, flags, JSON, formatting
  libeigen3-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  # the codecs of VDB files, for the checked chunk readers (io/vdb_chunk_guard.cpp)
  libblosc-dev zlib1g-dev
  # content hashes (the reference-image cache of vdb_optimize_weights)
  libxxhash-dev
  # quadratic programming (the altered phase functions of vdb_similarity)
  libalglib-dev
  # images: EXR through OpenEXR; PNG previews and other formats through OpenImageIO, found
  # through pkg-config (build note 3)
  libopenexr-dev libopenimageio-dev
  # surfaces in renders: ray tracing kernels and mesh files (OBJ, PLY)
  libembree-dev libassimp-dev
  # several processes: vdb_render and vdb_optimize_weights under mpirun or srun (docs/scaling.md)
  libopenmpi-dev openmpi-bin
  # a single-node Slurm cluster for the test of the example batch script (tests/slurm)
  slurm-wlm
  # tests
  libgtest-dev
  # sanitizer builds and libFuzzer harnesses (make test-sanitize)
  clang-14 libclang-rt-14-dev
  # benchmarks (bench/, run by scripts)
  libbenchmark-dev
  # man pages from the tools' --help (make install), and man to read them in the install test
  help2man man-db
)

if [[ "${1:-}" == "--print" ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends -o Dpkg::Use-Pty=0 "${missing[@]}" >/dev/null
