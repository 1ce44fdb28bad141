#!/usr/bin/env bash
# Installs the Debian 12 packages conftrack needs, only those missing.
# Called by `make run` and `make test`; safe to run by hand. With --fuzz it
# also installs the compiler of the fuzzing build (`make fuzz`, clang's
# libFuzzer and sanitizer runtimes), with --slurm the Slurm daemons and
# munge of the cluster test (`make test-slurm`); the rest needs neither.
set -euo pipefail

packages=(
  g++ cmake make pkg-config
  libeigen3-dev libtbb-dev libnanoflann-dev libcli11-dev
  libtomlplusplus-dev nlohmann-json3-dev libboost-dev libhepmc3-dev
  zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib python3-numpy
  python3-dev pybind11-dev python3-pandas python3-pytest
)
fuzz_packages=(clang-14 libclang-rt-14-dev)
slurm_packages=(slurm-wlm munge)
case "${1:-}" in
  --fuzz) packages+=("${fuzz_packages[@]}") ;;
  --slurm) packages+=("${slurm_packages[@]}") ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "conftrack: installing missing Debian packages: ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo=(sudo -n)
else
  echo "conftrack: cannot install ${missing[*]}: not root and no password-less sudo." >&2
  echo "conftrack: install them with: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
if ! "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"; then
  "${sudo[@]}" apt-get update -q
  "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" || {
    echo "conftrack: apt-get install failed for: ${missing[*]}" >&2
    exit 1
  }
fi
