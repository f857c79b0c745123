#!/usr/bin/env bash
# scripts/cluster_bench.sh: `penumbra precompute` and `penumbra render` with 1, 2 and 3 ranks of
# an MPI job on this machine (docs/cluster.md, "Measured").
#
#   scripts/cluster_bench.sh [SCENE...]        (default: assets/scenes/table.json and stairs.json)
#
# Per scene, command and rank count: the wall time and the CPU time of every process (user +
# system, the launcher and all ranks: bash's `time` counts the children mpirun waited for), the
# bytes sent per tree (the workers' trees to rank 0) and, for the render, per image (pixels, tile
# costs and what the tiles found, gathered by rank 0; and the trees rank 0 sent the workers), the
# coordinator's share (rank 0's main thread decoding and copying, over the wall time), and
# whether the file or the image is byte for byte the single process's (cmp). One rank is a plain
# process (no launcher); every run uses one thread per rank (--threads 1), so that N ranks are N
# cores' worth of work. Settings: SIZE (256x256), SPP (4), RANKS ("1 2 3"), PENUMBRA
# (build/app/penumbra), MPIRUN (mpirun).
set -euo pipefail
cd "$(dirname "$0")/.."
PENUMBRA=${PENUMBRA:-build/app/penumbra}
MPIRUN=${MPIRUN:-mpirun}
SIZE=${SIZE:-256x256}
SPP=${SPP:-4}
RANKS=${RANKS:-"1 2 3"}
if [ $# -eq 0 ]; then set -- assets/scenes/table.json assets/scenes/stairs.json; fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# run RANKS NAME ARGS...: runs penumbra ARGS (as RANKS ranks), its stdout in $tmp/NAME.out and
# "wall user system" in $tmp/NAME.time.
run() {
    local ranks=$1 name=$2
    shift 2
    local TIMEFORMAT="%R %U %S"
    local launcher=()
    [ "$ranks" -gt 1 ] && launcher=("$MPIRUN" --allow-run-as-root --oversubscribe -np "$ranks")
    if ! { time nice -n 19 "${launcher[@]}" "$PENUMBRA" "$@" --threads 1 \
        >"$tmp/$name.out" 2>"$tmp/$name.err"; } 2>"$tmp/$name.time"; then
        echo "penumbra $* failed with $ranks ranks:" >&2
        cat "$tmp/$name.err" >&2
        exit 1
    fi
}

# field FILE REGEX: the first match's first group (sed -E), or "-".
field() { sed -nE "s/$2/\\1/p" "$1" | head -1 | grep . || echo -; }

printf '%-12s %-10s %5s %8s %8s %10s %12s %12s %8s %s\n' scene command ranks wall_s cpu_s \
    trees B/tree B/image coord% same
for scene in "$@"; do
    label=$(basename "$scene" .json)
    for ranks in $RANKS; do
        # precompute: every pair of the scene, written to a fresh file.
        rm -f "$tmp/p$ranks.pvis"
        run "$ranks" "p$ranks" precompute "$scene" -o "$tmp/p$ranks.pvis"
        read -r wall user sys <"$tmp/p$ranks.time"
        trees=$(field "$tmp/p$ranks.out" '^pairs +([0-9]+) of.*')
        perTree=$(field "$tmp/p$ranks.out" '.*bytes \(([0-9]+) bytes per tree\).*')
        coord=$(field "$tmp/p$ranks.out" '.*decoded them in ([0-9.]+) s.*')
        same=$(cmp -s "$tmp/p1.pvis" "$tmp/p$ranks.pvis" && echo identical || echo DIFFERENT)
        share=-
        [ "$coord" != - ] && share=$(awk -v c="$coord" -v w="$wall" 'BEGIN{printf "%.1f", 100*c/w}')
        printf '%-12s %-10s %5s %8s %8.2f %10s %12s %12s %8s %s\n' "$label" precompute "$ranks" \
            "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$trees" "$perTree" - \
            "$share" "$same"

        # render: the exact image at SIZE, SPP passes.
        run "$ranks" "r$ranks" render "$scene" --size "$SIZE" --spp "$SPP" --out "$tmp/r$ranks.pfm"
        read -r wall user sys <"$tmp/r$ranks.time"
        trees=$(field "$tmp/r$ranks.out" '^time: precompute [0-9.]+ s \(([0-9]+) trees.*')
        perTree=$(field "$tmp/r$ranks.out" '.*trees: [0-9]+ bytes to rank 0 \(([0-9]+) per tree\).*')
        image=$(sed -nE 's/.*image: ([0-9]+) bytes of pixels and tile costs, ([0-9]+) of findings, ([0-9]+) of pass starts, ([0-9]+) of tile batches.*/\1 \2 \3 \4/p' \
            "$tmp/r$ranks.out" | awk '{print $1+$2+$3+$4}' | grep . || echo -)
        coord=$(field "$tmp/r$ranks.out" '.*rank 0 handled them in ([0-9.]+) s.*')
        same=$(cmp -s "$tmp/r1.pfm" "$tmp/r$ranks.pfm" && echo identical || echo DIFFERENT)
        share=-
        [ "$coord" != - ] && share=$(awk -v c="$coord" -v w="$wall" 'BEGIN{printf "%.1f", 100*c/w}')
        printf '%-12s %-10s %5s %8s %8.2f %10s %12s %12s %8s %s\n' "$label" render "$ranks" \
            "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN{print u+s}')" "$trees" "$perTree" \
            "$image" "$share" "$same"
        grep -E '^(time:|ranks |sent )' "$tmp/r$ranks.out" | sed 's/^/    /'
    done
done
