#!/usr/bin/env bash
# CI entry point: installs the dependencies, then builds and tests three times, then fuzzes:
#   build/       RelWithDebInfo, PENUMBRA_TEST_SCALE=0.5
#   build-sanitize/  clang, RelWithDebInfo with -DPENUMBRA_SANITIZE=ON (ASan + UBSan, and in
#                the engine the instrumentation for libFuzzer), PENUMBRA_TEST_SCALE=0.25; it also
#                builds the libFuzzer harnesses of tests/fuzz/. Its tests run as 20 GoogleTest
#                shards, not one process each (run_shards). The CGAL reference is compiled
#                without the sanitizers (the oracle, not the product), and its own tests
#                (ExactReference.*: against closed forms and Monte Carlo) run in the release
#                suite alone. ASan keeps 15 frames of each allocation's and free's stack (instead
#                of 30): a report still shows where the memory came from, and the exact-core
#                tests, which allocate in their inner loops, run about a fifth faster. Freed
#                memory stays poisoned until 32 MB more has been freed (instead of 256): a use
#                after free within that window is still reported, and the tests spent a quarter
#                of their CPU time in the kernel mapping fresh pages for the larger quarantine
#                (a renderer test and a query test: 24 s of CPU -> 17 s, system time 6.5 -> 1.8).
#   build-tsan/  RelWithDebInfo with -DPENUMBRA_TSAN=ON (ThreadSanitizer): only
#                penumbra_concurrency_tests is built (the scheduler's and the store's tests, less
#                the one that needs the CGAL reference and runs no threads) with what it links,
#                penumbra_engine_core (no scene formats, images, renderer or studies), and only
#                they run
#   fuzz:        every harness of tests/fuzz/ (from build-sanitize/) for PENUMBRA_FUZZ_SECONDS
#                (2) each, one per core at a time (scripts/fuzz.sh). 2 s is some 1000-2000
#                inputs per harness on 2 cores, a smoke test on top of the seeds and regression
#                inputs that the FuzzRegressions test replays; at 12 s a clean run took 913 s of
#                CI's 900 (2026-12-05). Longer runs: scripts/fuzz.sh SECONDS.
# Every build is a unity build (CMAKE_UNITY_BUILD: the files of a target compiled sixteen at a
# time, each heavy header parsed once per batch; a developer's build stays per file; sixteen
# rather than CMake's eight: the release build 233 -> 209 s on 2 cores, its compilers' CPU 670 ->
# 566 s, 2026-12-06). The sanitizer build compiles the app's own code at -O0 (app/CMakeLists.txt:
# some 75 s of its compilers' CPU, against 12 s more CPU in its tests). The release and
# ThreadSanitizer builds compile with line tables only (-g1: file and line in every backtrace and
# sanitizer report, a quarter less compile time than -g); the ASan + UBSan build with none (-g0):
# there line tables cost a quarter of the compile time (the engine's largest batch 38 s of CPU
# against 28 s), some 85 s of a clean run's wall time. Its reports still name every function of a
# stack (the symbol table) and UBSan's still give file and line (compiled into each check); for
# lines in an ASan stack, rerun the test in a build with -g. Together they keep a clean run under 15
# minutes on 2 cores. Runs every configuration even after a failure, prints "N passed, M failed"
# over all runs as its last line, and exits non-zero if anything (configure, build or a test)
# failed.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1

bash scripts/install_deps.sh || { echo "run_tests: installing dependencies failed" >&2; exit 1; }

total_passed=0
total_failed=0
problems=()

# run_suite NAME BUILD_DIR TEST_SCALE [extra cmake args...]
# Optional, set in front of the call: SUITE_TARGET (build only this target), SUITE_TESTS (a
# ctest -R regular expression: run only the tests it matches), SUITE_SKIP (a ctest -E one:
# leave out the tests it matches), or SUITE_SHARDS and SUITE_GTEST_FILTER (run_shards below).
run_suite() {
  local name=$1 dir=$2 scale=$3
  shift 3
  echo "=== ${name}: configure ${dir}"
  local generator=()
  # Keep whatever generator an existing build directory was made with (cmake refuses to switch).
  [[ -f "${dir}/CMakeCache.txt" ]] || generator=(-G Ninja)
  if ! cmake -S . -B "${dir}" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 "$@"; then
    problems+=("${name}: configure failed")
    return
  fi
  echo "=== ${name}: build"
  local built_at=${SECONDS}
  local target=()
  # shellcheck disable=SC2206 # a list of targets, split on blanks
  [[ -n "${SUITE_TARGET:-}" ]] && target=(--target ${SUITE_TARGET})
  if ! cmake --build "${dir}" "${target[@]}"; then
    problems+=("${name}: build failed")
    return
  fi
  # (Each stage's wall seconds, so that the run's 15 minutes can be kept where they go.)
  echo "=== ${name}: built in $((SECONDS - built_at)) s"
  echo "=== ${name}: test (PENUMBRA_TEST_SCALE=${scale})"
  if [[ -n "${SUITE_SHARDS:-}" ]]; then
    run_shards "${name}" "${dir}" "${scale}"
    return
  fi
  local log
  log=$(mktemp)
  local select=()
  [[ -n "${SUITE_TESTS:-}" ]] && select=(-R "${SUITE_TESTS}")
  [[ -n "${SUITE_SKIP:-}" ]] && select+=(-E "${SUITE_SKIP}")
  (cd "${dir}" && PENUMBRA_TEST_SCALE="${scale}" ctest --output-on-failure --no-tests=error -j2 \
    "${select[@]}") \
    2>&1 | tee "${log}"
  local rc=${PIPESTATUS[0]}
  # ctest's summary: "100% tests passed, 0 tests failed out of 42"
  local summary failed total
  summary=$(grep -Eo '[0-9]+ tests? failed out of [0-9]+' "${log}" | tail -n 1)
  rm -f "${log}"
  if [[ -n "${summary}" ]]; then
    failed=$(awk '{print $1}' <<<"${summary}")
    total=$(awk '{print $NF}' <<<"${summary}")
    total_passed=$((total_passed + total - failed))
    total_failed=$((total_failed + failed))
    echo "=== ${name}: $((total - failed)) passed, ${failed} failed"
  fi
  if ((rc != 0)); then
    problems+=("${name}: ctest exited with ${rc}")
  elif [[ -z "${summary}" ]]; then
    problems+=("${name}: no ctest summary found")
  fi
}

# run_shards NAME BUILD_DIR TEST_SCALE: instead of ctest's one process per test, each test
# executable of BUILD_DIR runs as SUITE_SHARDS GoogleTest shards (GTEST_TOTAL_SHARDS: every
# SUITE_SHARDS-th test, in order), three at a time on CI's two cores, with SUITE_GTEST_FILTER:
# the MPI tests wait for ranks and launchers (the killed-rank tests some 9 s and 3 s, the
# interrupted run 6 s) with a core idle, which a third shard fills. Under AddressSanitizer
# a test process takes some 0.2 s of CPU to start and to check for leaks at exit, which over 450
# tests was a minute of a 15-minute CI run (0.05 s in the release build). A shard prints its tests' failures and its summary;
# one that ends without a summary (a sanitizer report, a crash, a leak at exit, the timeout) counts
# as one failure and prints its whole log, the report and the test that was running included.
run_shards() {
  local name=$1 dir=$2 scale=$3
  local logs started_at=${SECONDS}
  logs=$(mktemp -d)
  local jobs=() exe n i
  for exe in penumbra_tests penumbra_concurrency_tests; do
    n=${SUITE_SHARDS}
    [[ ${exe} == penumbra_concurrency_tests ]] && n=1  # 13 tests, a few seconds
    for ((i = 0; i < n; i++)); do jobs+=("${exe} ${n} ${i}"); done
  done
  local running=0 job filter=()
  [[ -n "${SUITE_GTEST_FILTER:-}" ]] && filter=("--gtest_filter=${SUITE_GTEST_FILTER}")
  for job in "${jobs[@]}"; do
    read -r exe n i <<<"${job}"
    (cd "${dir}" && GTEST_TOTAL_SHARDS=${n} GTEST_SHARD_INDEX=${i} PENUMBRA_TEST_SCALE="${scale}" \
      timeout 1500 "tests/${exe}" "${filter[@]}" >"${logs}/${exe}.${i}.log" 2>&1
    echo $? >"${logs}/${exe}.${i}.rc") &
    running=$((running + 1))
    if ((running >= 3)); then
      wait -n
      running=$((running - 1))
    fi
  done
  wait
  local passed=0 failed=0 log rc p f s
  for job in "${jobs[@]}"; do
    read -r exe n i <<<"${job}"
    log="${logs}/${exe}.${i}.log"
    rc=$(cat "${logs}/${exe}.${i}.rc")
    # "[  PASSED  ] 12 tests.", "[  SKIPPED ] 1 test, listed below:", "[  FAILED  ] 2 tests, listed below:"
    p=$(grep -Eo '^\[  PASSED  \] [0-9]+' "${log}" | grep -Eo '[0-9]+$' || true)
    s=$(grep -Eo '^\[  SKIPPED \] [0-9]+ tests?,' "${log}" | grep -Eo '[0-9]+' || true)
    f=$(grep -Eo '^\[  FAILED  \] [0-9]+ tests?,' "${log}" | grep -Eo '[0-9]+' || true)
    if [[ -z "${p}" ]]; then
      echo "=== ${name}: ${exe} shard ${i} of ${n} ended without a summary (exit ${rc}):"
      cat "${log}"
      failed=$((failed + 1))
      continue
    fi
    passed=$((passed + p + ${s:-0}))
    failed=$((failed + ${f:-0}))
    if [[ "${rc}" != 0 ]]; then
      grep -v -E '^\[ +(RUN|OK) +\]' "${log}"
      # Every test passed but the process failed (a leak found at exit): one failure.
      [[ -z "${f}" ]] && failed=$((failed + 1))
    fi
    echo "${exe} shard ${i} of ${n}: $(grep -E '^\[==========\] .* ran\.' "${log}"), exit ${rc}"
  done
  rm -rf "${logs}"
  if ((passed + failed == 0)); then
    problems+=("${name}: no test ran")
  fi
  total_passed=$((total_passed + passed))
  total_failed=$((total_failed + failed))
  echo "=== ${name}: ${passed} passed, ${failed} failed in $((SECONDS - started_at)) s"
  ((failed == 0)) || problems+=("${name}: ${failed} failed")
}

# The release suite as shards too: no process per test to start, and 20 shards balance the two
# cores better than ctest's order of registration (ctest has no costs of earlier runs in a clean
# clone). ctest stays the way to run one test or a subset by hand.
# At half the heavy tests' point counts (PENUMBRA_TEST_SCALE 0.5): twice the sanitizer run's; the
# whole count runs by hand (ctest, or the test executable, with no PENUMBRA_TEST_SCALE).
SUITE_SHARDS=20 run_suite release build 0.5
# Assignments in front of a function call are exported to what the function runs (ctest).
# Built with clang: the same instrumented build also holds the fuzz harnesses (fuzz step below).
# Only what the tests and the fuzzing run (the tools are compiled by the release build).
fuzz_targets="fuzz_scene fuzz_visibility_file penumbra_fuzz_seed"
asan_options="${ASAN_OPTIONS:-malloc_context_size=15:quarantine_size_mb=32}"
# Run in the release suite only (each still runs there, at full scale): the reference's self-tests
# (test code), the viewer walked through 640 frames of its states (74 s under ASan; the same panels
# and modes run under ASan in ViewerScreenshot and ViewerFrames), the layout measured at three
# content scales (45 s under ASan: the same panels drawn, at one scale, by those tests; what it
# checks is text widths, not memory), and two bench command tests of which rows and sizes the bench
# picks (35 s; the whole quick bench still runs under ASan in BenchCommand.AQuickRunSays...).
asan_skip='-ExactReference.*:ViewerPanelText.EveryStateSaysWhatTheViewShows'
asan_skip+=':ViewerLayout.NoLabelIsCutOffAtScales1To2'
asan_skip+=':BenchCommand.SkipsTheScalingRowsWhoseMeshesAreMissing'
asan_skip+=':BenchCommand.MeasuresEveryPointExactOnASmallerImageAboveTheAllPairsSize'
# and six image comparisons whose renders take 12-17 s each under ASan (the renderer and the
# viewer's preview run under ASan in the other renderer and screenshot tests; these compare
# whole images with each other, which the release suite does).
asan_skip+=':ViewerScreenshot.RenderedViewIsTheImagePenumbraRenderWrites'
asan_skip+=':ViewerScreenshot.AccuracyPanelPlotsTheStudyOfThisView'
asan_skip+=':ViewerScreenshot.SavedViewReopensAsTheSameView'
asan_skip+=':ViewerScreenshot.SampledPreviewConvergesToTheExactOne'
asan_skip+=':Renderer.ClosedBoxLeavesOutItsBackFacesWithTheSameImage'
asan_skip+=':Renderer.PairsWhoseShaftTheGroupsAnswerGetNoTreeAndTheSameImage'
# and the renderer's light-edge test (eight 24x24 renders, 2.7 s in the release build, 27-54 s
# under ASan): the light-edge path runs under ASan against the exact reference in the
# BoundaryChainQuery tests and the cull of its edges in the SilhouetteCull tests.
asan_skip+=':Renderer.PointsOverTheWorkLimitTakeTheLightEdgePathWithTheExactImage'
# The viewer test that draws in process (tests/app/viewer/panels/panel_text_test.cpp) opens OSMesa
# in the test binary itself: its LeakSanitizer ignores what the GL libraries keep at exit, as the
# child processes' does (tests/app/viewer/lsan_gl.supp).
CXX=clang++ CC=clang UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" \
  ASAN_OPTIONS="${asan_options}" SUITE_GTEST_FILTER="${asan_skip}" SUITE_SHARDS=20 \
  LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=${PWD}/tests/app/viewer/lsan_gl.supp}" \
  SUITE_TARGET="penumbra_tests penumbra_concurrency_tests ${fuzz_targets}" \
  run_suite sanitize build-sanitize 0.25 -DPENUMBRA_SANITIZE=ON \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g0 -DNDEBUG"
# oneTBB and Embree are not instrumented: tests/tsan.supp lists (and justifies) what that hides.
TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1 second_deadlock_stack=1 suppressions=${PWD}/tests/tsan.supp}" \
  SUITE_TARGET=penumbra_concurrency_tests SUITE_TESTS='^(PrecomputeScheduler|VisibilityStore|PatchLayout)\.' \
  run_suite tsan build-tsan 0.25 -DPENUMBRA_TSAN=ON

# The include graph: no include from a lower room of the source to a higher one (the rooms and
# their order are in scripts/check_includes.sh). One test.
echo "=== includes"
if bash scripts/check_includes.sh; then
  total_passed=$((total_passed + 1))
else
  total_failed=$((total_failed + 1))
  problems+=("includes: an include from a lower room to a higher one (scripts/check_includes.sh)")
fi

# The libFuzzer harnesses, each for PENUMBRA_FUZZ_SECONDS (4 here; scripts/fuzz.sh runs them
# longer on demand), one per core at a time. A finding fails the run; it counts as one test.
echo "=== fuzz: ${PENUMBRA_FUZZ_SECONDS:-2} s per harness"
if ASAN_OPTIONS="${asan_options}" PENUMBRA_FUZZ_SEED="${PENUMBRA_FUZZ_SEED:-1}" \
  PENUMBRA_FUZZ_BUILD=build-sanitize bash scripts/fuzz.sh "${PENUMBRA_FUZZ_SECONDS:-2}"; then
  total_passed=$((total_passed + 1))
else
  total_failed=$((total_failed + 1))
  problems+=("fuzz: a harness found an input that breaks the contract (build-sanitize/findings/)")
fi

for p in "${problems[@]}"; do
  echo "run_tests: ${p}" >&2
done
echo "run_tests: ${SECONDS} s in all"
echo "${total_passed} passed, ${total_failed} failed"
if ((${#problems[@]} > 0 || total_failed > 0)); then
  exit 1
fi
