#!/usr/bin/env bash
# Issue 11 side by side, processes timed end to end, best of ROUNDS
# interleaved rounds on this machine:
#  - the chaos game into a 1024² PNG: bcifs (the fern in ink; the gasket
#    coloured by its maps, as flam3 colours) against flam3-render on the same
#    three Sierpinski maps (quality 100: 1024² · 100 samples, density
#    estimation and log filtering) and a plain C chaos loop writing nothing;
#  - the gasket in ink into a 4096² PNG, one thread, 10⁸ samples (issue 29:
#    at least 10⁸ samples/s per core; the PNG's encoding is counted too);
#  - Lévy's curve at depth 24 to PNG; the Doo-Sabin torus at depth 8 to OBJ.
#
#   benches/peers/density.sh [ROUNDS]     (installs flam3-utils with apt when missing)
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-5}
if ! command -v flam3-render >/dev/null; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y -qq flam3-utils >/dev/null 2>&1 \
        || { apt-get update -qq >/dev/null 2>&1 && apt-get install -y -qq flam3-utils >/dev/null 2>&1; } \
        || { echo "flam3-utils could not be installed" >&2; exit 1; }
fi
mkdir -p target/peers
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
gcc -O2 -o target/peers/chaos_loop benches/peers/chaos_loop.c -lm
cargo build --release --quiet
b=target/release/bcifs
samples=104857600 # flam3's quality 100 at 1024²
python3 - "$out/gasket.flam3" <<'PY'
import sys
palette = "\n".join(f'<color index="{i}" rgb="{min(255, 110 + i)} {max(0, i - 60)} 0"/>' for i in range(256))
open(sys.argv[1], "w").write(f'''<flames><flame name="gasket" size="1024 1024" center="0.5 0.433" scale="950"
 oversample="1" filter="0.5" quality="100" background="0 0 0" brightness="4" gamma="4"
 estimator_radius="9" estimator_minimum="0" estimator_curve="0.4">
<xform weight="1" color="0" linear="1" coefs="0.5 0 0 0.5 0 0"/>
<xform weight="1" color="0.5" linear="1" coefs="0.5 0 0 0.5 0.5 0"/>
<xform weight="1" color="1" linear="1" coefs="0.5 0 0 0.5 0.25 0.4330127018922193"/>
{palette}
</flame></flames>''')
PY
run() { # NAME COMMAND...: appends "NAME seconds KiB" to $out/times
    local name=$1; shift
    rm -f "$out"/*.png "$out"/*.obj; sync
    /usr/bin/time -f "$name %e %M" "$@" >/dev/null 2>>"$out/times.raw" || true
    tail -n 1 "$out/times.raw" >> "$out/times"
}
for _ in $(seq "$rounds"); do
    for t in 1 2; do
        run "flam3-gasket-t$t" env nthreads=$t isaac_seed=bcifs out="$out/f.png" flam3-render < "$out/gasket.flam3"
        run "bcifs-gasket-colour-t$t" $b render gasket --random $samples --palette fire --blur 2 --size 1024x1024 --threads $t -o "$out/g.png"
        run "bcifs-fern-t$t" $b render fern --random 100000000 --size 1024x1024 --threads $t -o "$out/h.png"
        run "bcifs-torus8-obj-t$t" $b render doo_sabin_torus --depth 8 --threads $t -o "$out/t.obj"
    done
    run c-loop-fern target/peers/chaos_loop fern 100000000
    run c-loop-gasket target/peers/chaos_loop gasket $samples
    run bcifs-gasket-4096-t1 $b render gasket --random 100000000 --size 4096x4096 --threads 1 -o "$out/k.png"
    run bcifs-levy24-png $b render levy --depth 24 -o "$out/l.png"
done
$b render doo_sabin_torus --depth 8 -o "$out/t.obj" >/dev/null 2>&1
obj_bytes=$(stat -c %s "$out/t.obj")
awk -v bytes="$obj_bytes" -v n="$samples" '
  { if (!($1 in best) || $2 < best[$1]) best[$1] = $2; if ($3 > mem[$1]) mem[$1] = $3 }
  END {
    printf "%-26s %9s %10s\n", "run", "best s", "peak MiB"
    for (k in best) printf "%-26s %9.3f %10.1f\n", k, best[k], mem[k] / 1024
    printf "\ngasket coloured, samples/s per thread vs flam3: %.1fx (1 thread), %.1fx (2 threads)\n", \
      best["flam3-gasket-t1"] / best["bcifs-gasket-colour-t1"], best["flam3-gasket-t2"] / best["bcifs-gasket-colour-t2"]
    printf "fern 1e8 to PNG vs the C loop writing nothing: %.2fx its time (1 thread), %.2fx (2 threads)\n", \
      best["bcifs-fern-t1"] / best["c-loop-fern"], best["bcifs-fern-t2"] / best["c-loop-fern"]
    printf "gasket 1e8 in ink at 4096^2, 1 thread, end to end: %.0f M samples/s (the C loop writing nothing: %.0f M/s)\n", \
      100 / best["bcifs-gasket-4096-t1"], n / 1e6 / best["c-loop-gasket"]
    printf "torus depth 8 OBJ (%.0f MB): %.2f GB/s (1 thread), %.2f GB/s (2 threads)\n", bytes / 1e6, \
      bytes / 1e9 / best["bcifs-torus8-obj-t1"], bytes / 1e9 / best["bcifs-torus8-obj-t2"]
  }' "$out/times"
