#!/usr/bin/env bash
# Side by side, end to end (read the mesh, subdivide, write the OBJ), best of
# ROUNDS interleaved rounds on this machine: bcifs surface --net against
# CGAL's Subdivision_method_3 (Doo-Sabin, Catmull-Clark on the cube; Loop,
# √3 on the icosahedron) and OpenSubdiv's uniform refinement
# (Catmull-Clark); then the depth-10 peak memory of Doo-Sabin and Loop.
#
#   benches/peers/compare.sh [ROUNDS]      (needs libcgal-dev, libosd-dev, g++)
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-5}
mkdir -p target/peers
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
g++ -O2 -std=c++17 benches/peers/cgal_subdivide.cpp -o target/peers/cgal_subdivide -lgmp -lmpfr
g++ -O2 -std=c++17 benches/peers/osd_subdivide.cpp -o target/peers/osd_subdivide -losdCPU
cargo build --release --quiet
cube=tests/data/cube.off
ico=tests/data/icosahedron.off
run() { # NAME COMMAND...: appends "NAME seconds KiB" to $out/times
    local name=$1; shift
    /usr/bin/time -f "$name %e %M" "$@" >/dev/null 2>>"$out/times.raw" || true
    tail -n 1 "$out/times.raw" >> "$out/times"
}
for _ in $(seq "$rounds"); do
    run bcifs-doo-sabin target/release/bcifs surface $cube --scheme doo-sabin --depth 8 --net -o "$out/a.obj"
    run cgal-doo-sabin target/peers/cgal_subdivide doo-sabin 8 $cube "$out/b.obj"
    run bcifs-catmull-clark target/release/bcifs surface $cube --scheme catmull-clark --depth 8 --net -o "$out/c.obj"
    run cgal-catmull-clark target/peers/cgal_subdivide catmull-clark 8 $cube "$out/d.obj"
    run osd-catmull-clark target/peers/osd_subdivide 8 $cube "$out/e.obj"
    run bcifs-loop target/release/bcifs surface $ico --scheme loop --depth 7 --net -o "$out/h.obj"
    run cgal-loop target/peers/cgal_subdivide loop 7 $ico "$out/i.obj"
    run bcifs-sqrt3-depth10 target/release/bcifs surface $ico --scheme sqrt3 --depth 10 --net -o "$out/j.obj"
    run cgal-sqrt3-depth10 target/peers/cgal_subdivide sqrt3 10 $ico "$out/k.obj"
done
run bcifs-loop-depth10 target/release/bcifs surface $ico --scheme loop --depth 10 --net -o "$out/l.obj"
rm -f "$out/l.obj"
run bcifs-doo-sabin-depth10 target/release/bcifs surface $cube --scheme doo-sabin --depth 10 --net -o "$out/f.obj"
rm -f "$out/f.obj"
run cgal-doo-sabin-depth10 target/peers/cgal_subdivide doo-sabin 10 $cube "$out/g.obj"
awk '
  { if (!($1 in best) || $2 < best[$1]) best[$1] = $2; mem[$1] = $3 }
  END {
    printf "%-26s %9s %10s\n", "run (cube, end to end)", "best s", "peak MiB"
    for (k in best) printf "%-26s %9.3f %10.1f\n", k, best[k], mem[k] / 1024
    printf "\nDoo-Sabin depth 8: bcifs %.1fx CGAL\n", best["cgal-doo-sabin"] / best["bcifs-doo-sabin"]
    printf "Catmull-Clark depth 8: bcifs %.1fx CGAL, %.1fx OpenSubdiv\n", best["cgal-catmull-clark"] / best["bcifs-catmull-clark"], best["osd-catmull-clark"] / best["bcifs-catmull-clark"]
    printf "Loop depth 7 (icosahedron): bcifs %.1fx CGAL\n", best["cgal-loop"] / best["bcifs-loop"]
    printf "sqrt3 depth 10 (icosahedron): bcifs %.1fx CGAL\n", best["cgal-sqrt3-depth10"] / best["bcifs-sqrt3-depth10"]
  }' "$out/times"
