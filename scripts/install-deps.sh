#!/usr/bin/env bash
# Installs, with apt-get, every Debian package relief needs that is not installed yet.
# Idempotent: a machine that has everything runs no apt-get at all.
set -euo pipefail

packages=(
  g++ cmake make pkg-config
  libglm-dev libhwy-dev  # libhwy-dev: SIMD targets and dispatch (base/simd.h)
  libopenimageio-dev openimageio-tools
  libtinygltf-dev nlohmann-json3-dev
  libmeshoptimizer-dev libdraco-dev  # compressed glTF (scene/gltf_decode.cpp)
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev
  libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libglx-mesa0
  clang-14 libclang-rt-14-dev  # libFuzzer targets (scripts/ci-fuzz.sh)
  clang-format-14  # ctest format.SourcesMatchClangFormat (scripts/check-format.sh)
  chromium  # headless check of the `relief bench --report` page (tests/apps)
  slurmctld slurmd slurm-client munge  # scripts/slurm-test.sh: a one-node Slurm cluster
  python3  # scripts/architecture-graph.sh, scripts/check-function-length.sh
  dpkg-dev file  # `make package` (CPack's DEB generator runs dpkg-shlibdeps on the binary)
)
if [ "${RELIEF_EXTRA_PACKAGES:-}" != "" ]; then
  # shellcheck disable=SC2206
  packages+=(${RELIEF_EXTRA_PACKAGES})
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
