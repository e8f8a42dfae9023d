#!/usr/bin/env bash
# Optional: the Khronos glTF validator (npm gltf-validator) for
# KhronosValidator.EveryExportHasNoErrorAndNoWarning (tests/builtin/gltf_validator_test.cpp), which
# is skipped without it. Installs under /opt/gltf-validator (or $1). Never fails the caller: with
# no node, npm or network it says so and exits 0.
set -uo pipefail
prefix="${1:-/opt/gltf-validator}"
if [ -f "$prefix/node_modules/gltf-validator/package.json" ]; then exit 0; fi
if ! command -v npm >/dev/null; then
  echo "install-gltf-validator: npm not found; the validator test will be skipped"
  exit 0
fi
if ! npm install --no-audit --no-fund --prefix "$prefix" gltf-validator >/dev/null 2>&1; then
  echo "install-gltf-validator: npm install failed (offline?); the validator test will be skipped"
fi
exit 0
