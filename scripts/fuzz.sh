#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/: one per scene format, each a link to one executable,
# and one for the visibility file) with clang, AddressSanitizer and UndefinedBehaviorSanitizer in
# build-fuzz/, and runs each for SECONDS (default 60; CI uses PENUMBRA_FUZZ_SECONDS). The corpus of
# each harness starts from its seeds (tests/fuzz/seeds/FORMAT/, the committed assets, a generated
# visibility file) and grows in build-fuzz/corpus/ from run to run. A crash, a sanitizer report, an
# input slower than 10 s or one using more than 2 GB is a finding: its input is left in
# build-fuzz/findings/ and the script exits 1. Turn each finding into a regression input under
# tests/fuzz/regressions/FORMAT/ (the FuzzRegressions test loads every file there) once it is fixed.
# PENUMBRA_FUZZ_TIMEOUT is the seconds one input may take before it counts as a finding (default
# 10; the inputs take milliseconds: a longer campaign on a machine shared at low priority raises it
# so that being descheduled is not reported as a hang).
# PENUMBRA_FUZZ_SEED fixes libFuzzer's random seed (0, the default: a new one each run; CI uses 1
# so that a run repeats the same mutations). PENUMBRA_FUZZ_JOBS harnesses run at a time (default:
# the cores). PENUMBRA_FUZZ_BUILD names an existing clang build with the harnesses instead (the
# sanitizer build of scripts/run_tests.sh: -DPENUMBRA_SANITIZE=ON with clang builds them too); by
# default build-fuzz/ is configured and built here.
# Usage: bash scripts/fuzz.sh [SECONDS] [HARNESS...]
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1

seconds="${1:-${PENUMBRA_FUZZ_SECONDS:-60}}"
shift || true
bash scripts/install_deps.sh || { echo "fuzz: installing dependencies failed" >&2; exit 1; }

dir="${PENUMBRA_FUZZ_BUILD:-build-fuzz}"
if [[ -z "${PENUMBRA_FUZZ_BUILD:-}" ]]; then
  generator=()
  [[ -f "${dir}/CMakeCache.txt" ]] || generator=(-G Ninja)
  CXX=clang++ CC=clang cmake -S . -B "${dir}" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" -DPENUMBRA_FUZZ=ON -DPENUMBRA_TESTS=OFF \
    >/dev/null || { echo "fuzz: configure failed" >&2; exit 1; }
fi
cmake --build "${dir}" --target fuzz_scene fuzz_visibility_file penumbra_fuzz_seed ||
  { echo "fuzz: build failed" >&2; exit 1; }

harnesses=("$@")
if ((${#harnesses[@]} == 0)); then
  harnesses=(fuzz_scene_obj fuzz_scene_ply fuzz_scene_off fuzz_scene_stl fuzz_scene_gltf
             fuzz_scene_glb fuzz_scene_json fuzz_visibility_file)
fi

mkdir -p "${dir}/findings" "${dir}/seeds/visibility_file" "${dir}/seeds/obj" "${dir}/seeds/json"
"${dir}/tests/fuzz/penumbra_fuzz_seed" "${dir}/seeds/visibility_file/grids.pvis" ||
  { echo "fuzz: writing the visibility-file seed failed" >&2; exit 1; }
cp assets/*.obj "${dir}/seeds/obj/"
cp assets/scenes/*.json "${dir}/seeds/json/"

# One harness: runs it, writes its table row to ${dir}/findings/HARNESS.row and returns 1 on a
# finding (its log is ${dir}/findings/HARNESS.log). Leak checking stays on (a leak is a finding).
fuzz_one() {
  local h=$1 name corpus log before after rc execs rate cov ft
  name=${h#fuzz_scene_}
  name=${name#fuzz_}
  corpus="${dir}/corpus/${h}"
  mkdir -p "${corpus}"
  local seeds=()
  [[ -d "tests/fuzz/seeds/${name}" ]] && seeds+=("tests/fuzz/seeds/${name}")
  [[ -d "${dir}/seeds/${name}" ]] && seeds+=("${dir}/seeds/${name}")
  [[ -d "tests/fuzz/regressions/${name}" ]] && seeds+=("tests/fuzz/regressions/${name}")
  log="${dir}/findings/${h}.log"
  # Artifacts of earlier runs stay (nothing is deleted); only new ones count as this run's.
  before=$(compgen -G "${dir}/findings/${h}-*" | sort)
  timeout $((seconds + 120)) "${dir}/tests/fuzz/${h}" -max_total_time="${seconds}" \
    -timeout="${PENUMBRA_FUZZ_TIMEOUT:-10}" \
    -seed="${PENUMBRA_FUZZ_SEED:-0}" \
    -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="${dir}/findings/${h}-" "${corpus}" "${seeds[@]}" >"${log}" 2>&1
  rc=$?
  execs=$(grep -aEo 'stat::number_of_executed_units:[[:space:]]+[0-9]+' "${log}" | awk '{print $2}' | tail -n 1)
  rate=$(grep -aEo 'stat::average_exec_per_sec:[[:space:]]+[0-9]+' "${log}" | awk '{print $2}' | tail -n 1)
  cov=$(grep -aEo 'cov: [0-9]+' "${log}" | awk '{print $2}' | tail -n 1)
  ft=$(grep -aEo 'ft: [0-9]+' "${log}" | awk '{print $2}' | tail -n 1)
  printf '%-22s %10s %12s %8s %8s %8s\n' "${h}" "${seconds}" "${execs:-?}" "${rate:-?}" \
    "${cov:-?}" "${ft:-?}" >"${dir}/findings/${h}.row"
  after=$(compgen -G "${dir}/findings/${h}-*" | sort)
  if ((rc != 0)) || [[ "${after}" != "${before}" ]]; then
    {
      echo "fuzz: ${h} found something (exit ${rc}); its log: ${log}"
      grep -aE 'ERROR|finding:|SUMMARY|Test unit written' "${log}" | head -n 20
    } >&2
    return 1
  fi
  return 0
}

# PENUMBRA_FUZZ_JOBS harnesses at a time (each is one process on one core).
jobs_max="${PENUMBRA_FUZZ_JOBS:-$(nproc)}"
status=0
running=0
for h in "${harnesses[@]}"; do
  if ((running >= jobs_max)); then
    wait -n || status=1
    running=$((running - 1))
  fi
  fuzz_one "${h}" &
  running=$((running + 1))
done
while ((running > 0)); do
  wait -n || status=1
  running=$((running - 1))
done
printf '%-22s %10s %12s %8s %8s %8s\n' harness seconds executions exec/s cov ft
for h in "${harnesses[@]}"; do cat "${dir}/findings/${h}.row" 2>/dev/null || echo "${h}: no result"; done
exit "${status}"
