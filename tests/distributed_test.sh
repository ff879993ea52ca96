#!/usr/bin/env bash
# `mpirun -np N lambert solve --distributed` on one machine (--oversubscribe), as make test runs it
# (CTest Distributed.*): the vertices of 1, 2 and 4 ranks against one process's Jacobi solve of
# the same scene, within 1e-6 relative (docs/distributed.md: every rank ends every sweep with the
# one process's values), and a lightmap and a lux grid alike; then the faults: a rank that cannot load the scene, a rank killed mid-
# solve, Ctrl-C. Each must stop the whole job with a non-zero exit and leave no output.
# Usage: tests/distributed_test.sh LAMBERT MPIRUN SCRATCH
set -uo pipefail
lambert=$1 mpirun=$2 scratch=$3
rm -rf "$scratch" && mkdir -p "$scratch"
# Debian's CI and containers run as root, which OpenMPI refuses unless told.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# One machine, more ranks than cores; no network interfaces needed between them.
run=("$mpirun" --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none)
fail() { echo "distributed: FAIL: $*"; exit 1; }

"$lambert" generate building --rooms 16 -o "$scratch/building/building.json" > /dev/null || fail "generate"
# The largest relative difference between two vertex files (x,y,z,nx,ny,nz,r,g,b rows).
compare() {
  awk -F, 'NR == FNR { if (FNR > 1) for (i = 7; i <= 9; ++i) v[FNR, i] = $i; rows = FNR; next }
           FNR > 1 { for (i = 7; i <= 9; ++i) { a = v[FNR, i]; b = $i; d = a - b; if (d < 0) d = -d;
                     m = (a < 0 ? -a : a); if ((b < 0 ? -b : b) > m) m = (b < 0 ? -b : b);
                     r = m > 1e-12 ? d / m : 0; if (r > worst) worst = r } }
           END { if (FNR != rows) { print "rows differ"; exit 1 } printf "%.3g\n", worst + 0 }' "$1" "$2"
}
for scene in cornell "$scratch/building/building.json" "$(dirname "$0")/../scenes/cornell/cornell-spots.json"; do
  name=$(basename "$scene" .json)
  "$lambert" solve --scene "$scene" --solver jacobi --no-cache -q --export-vertices "$scratch/$name-1process.csv" || fail "$name: one process"
  for n in 1 2 4; do
    "${run[@]}" -np $n "$lambert" solve --distributed --scene "$scene" -q --export-vertices "$scratch/$name-$n.csv" ||
      fail "$name: $n ranks exited $?"
    worst=$(compare "$scratch/$name-1process.csv" "$scratch/$name-$n.csv") || fail "$name: $n ranks: $worst"
    awk -v w="$worst" 'BEGIN { exit !(w <= 1e-6) }' || fail "$name: $n ranks differ from one process by $worst"
    echo "distributed: $name, $n ranks: largest relative difference from one process $worst"
  done
done

# The same refinement decisions: the ranks' links, each counted once, are one process's links.
links() { sed -n 's/.*"links": *\([0-9]*\).*/\1/p'; }
one=$("$lambert" solve --scene "$scratch/building/building.json" --solver jacobi --no-cache --json | links)
four=$("${run[@]}" -np 4 "$lambert" solve --distributed --scene "$scratch/building/building.json" --json | links)
[ -n "$one" ] && [ "$one" = "$four" ] || fail "links: one process made '$one', 4 ranks '$four'"
echo "distributed: building: 4 ranks hold the $four links one process makes"

# The outputs rank 0 writes from final gathers at points spread over the ranks (each gathering
# the points on its own leaves through its own links): lightmap texels and a lux grid, to the bit.
spots="$(dirname "$0")/../scenes/cornell/cornell-spots.json"
outputs=(--lightmaps --lightmap-size 128 --grid floor -q)
mkdir -p "$scratch/points-1process" "$scratch/points-3"
"$lambert" solve --scene "$spots" --solver jacobi --no-cache "${outputs[@]}" --export "$scratch/points-1process/s.glb" \
  --export-grids "$scratch/points-1process/" || fail "points: one process"
"${run[@]}" -np 3 "$lambert" solve --distributed --scene "$spots" "${outputs[@]}" --export "$scratch/points-3/s.glb" \
  --export-grids "$scratch/points-3/" || fail "points: 3 ranks exited $?"
for file in s-lightmap-0.exr floor.csv; do
  cmp -s "$scratch/points-1process/$file" "$scratch/points-3/$file" || fail "points: $file differs between one process and 3 ranks"
done
echo "distributed: cornell-spots' lightmap and floor grid from 3 ranks: identical to one process's"

# A rank that cannot load the scene (a file missing on its node): one message naming the rank,
# a non-zero exit, no output.
"${run[@]}" -np 2 sh -c 'if [ "$OMPI_COMM_WORLD_RANK" = 1 ]; then scene=/nonexistent/scene.json; else scene=cornell; fi
  exec "$0" solve --distributed --scene "$scene" -q --export-vertices "$1"' "$lambert" "$scratch/bad.csv" 2> "$scratch/bad.err"
status=$?
[ $status -ne 0 ] || fail "a rank that cannot load: exit 0"
grep -q "rank 1: " "$scratch/bad.err" || fail "a rank that cannot load: no 'rank 1:' in: $(cat "$scratch/bad.err")"
[ "$(grep -c 'lambert solve:' "$scratch/bad.err")" = 1 ] || fail "a rank that cannot load: not one message: $(cat "$scratch/bad.err")"
[ ! -e "$scratch/bad.csv" ] || fail "a rank that cannot load: output written"
echo "distributed: a rank that cannot load stops the job (exit $status): $(grep 'lambert solve:' "$scratch/bad.err")"

# Out of memory: a refinement that would not fit the ranks' --memory-limit stops on every rank
# at the same wave (they agree on it), with one message, exit 2, no output.
"${run[@]}" -np 2 "$lambert" solve --distributed --scene "$scratch/building/building.json" -q --memory-limit 64K \
  --export-vertices "$scratch/oom.csv" 2> "$scratch/oom.err"
status=$?
[ $status -eq 2 ] || fail "out of memory: exit $status: $(cat "$scratch/oom.err")"
[ "$(grep -c 'lambert solve:' "$scratch/oom.err")" = 1 ] && grep -q -- '--memory-limit' "$scratch/oom.err" ||
  fail "out of memory: not one message naming --memory-limit: $(cat "$scratch/oom.err")"
[ ! -e "$scratch/oom.csv" ] || fail "out of memory: output written"
echo "distributed: a refinement over --memory-limit stops the job (exit 2), no output"

# Rank 0 failing to write while the others wait to serve its gathers: it lets them go, and the
# job stops with its one message and a non-zero exit (a hang would meet the timeout).
touch "$scratch/a-file"
timeout 120 "${run[@]}" -np 2 "$lambert" solve --distributed --scene cornell -q --export-vertices "$scratch/a-file/v.csv" 2> "$scratch/write.err"
status=$?
[ $status -ne 0 ] && [ $status -ne 124 ] || fail "rank 0 failing to write: exit $status"
[ "$(grep -c 'lambert solve:' "$scratch/write.err")" = 1 ] || fail "rank 0 failing to write: not one message: $(cat "$scratch/write.err")"
echo "distributed: rank 0 failing to write stops the job (exit $status): $(grep 'lambert solve:' "$scratch/write.err")"

# A rank killed a second into the job (one process takes 5 s over it), and Ctrl-C (SIGINT to
# mpirun, which forwards it): the job stops, exits non-zero, writes nothing.
"$lambert" generate building --rooms 64 -o "$scratch/big/big.json" > /dev/null || fail "generate"
big=("$scratch/big/big.json" --link-error 2e-5)
"${run[@]}" -np 2 sh -c 'if [ "$OMPI_COMM_WORLD_RANK" = 1 ]; then (sleep 1; kill -9 $$) & fi
  exec "$0" solve --distributed --scene "$1" --link-error 2e-5 -q --export-vertices "$2"' "$lambert" "$scratch/big/big.json" "$scratch/killed.csv" \
  > /dev/null 2>&1
status=$?
[ $status -ne 0 ] || fail "a killed rank: exit 0"
[ ! -e "$scratch/killed.csv" ] || fail "a killed rank: output written"
echo "distributed: a rank killed mid-solve stops the job (exit $status), no output"
"${run[@]}" -np 2 "$lambert" solve --distributed --scene "${big[@]}" -q --export-vertices "$scratch/interrupted.csv" > /dev/null 2>&1 &
job=$!
sleep 1
kill -INT $job
wait $job
status=$?
[ $status -ne 0 ] || fail "Ctrl-C: exit 0"
[ ! -e "$scratch/interrupted.csv" ] || fail "Ctrl-C: output written"
echo "distributed: Ctrl-C stops the job (exit $status), no output"
echo "distributed: ok"
