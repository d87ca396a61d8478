#!/usr/bin/env bash
# geosph against a peer code on the same 2D dam break, run interleaved (peer, geosph, peer,
# geosph, ...) so that both see the same machine; prints every run and the ratio of the
# fastest run of each (docs/performance.md, "Against the peers").
#
#   bash benches/scripts/peers.sh install          # PySPH (~5 min build) and SPlisHSPlasH
#   bash benches/scripts/peers.sh pysph  [ROUNDS]  # WCSPH, dx = 0.015 m, to t = 0.3 s
#   bash benches/scripts/peers.sh splash [ROUNDS] [METHOD]
#        # DFSPH (or IISPH, PCISPH) at 0.1 % mean compression, dx = 0.015 m, to t = 1.35 s,
#        # geosph with SPlisHSPlasH's kernel and support (cubic spline, h = dx, 2 wall layers)
#
# `install` puts the peers' PyPI packages (pysph, pysplishsplash; unpinned, the versions are
# printed) in virtual environments in PEERS_DIR (default ~/.cache/geosph-peers). The runs use
# the peers' dam-break drivers (pysph_dambreak.py, splash_dambreak.py), which are not part of
# this repository: they are in the peers' folder beside it (PEERS_SCRIPTS, default
# ../shared/peers). Both codes run on two threads (OMP_NUM_THREADS=2, geosph --threads 2);
# the order alternates from round to round. Run it on an otherwise idle machine: nothing else
# may build or run beside it.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
peers=${PEERS_DIR:-$HOME/.cache/geosph-peers}
mode=${1:-}
rounds=${2:-3}
export OMP_NUM_THREADS=2

gldispatch() {
    # SPlisHSPlasH's wheel segfaults at import with Debian 12's libGLX unless the system
    # libGLdispatch is preloaded (../shared/peers/README.md).
    PATH=$PATH:/sbin:/usr/sbin ldconfig -p | awk '/libGLdispatch.so.0 /{print $NF; exit}'
}

# Prints the one RESULT line of a peer's log as "<wall s> <simulated s> <steps> <M fluid
# particle-steps/s>" with the JSON keys wall, time, steps, rate; a run without it ends the
# script with its log.
peer_result() {
    python3 -c '
import json, sys
log = open(sys.argv[1]).read()
lines = [l for l in log.splitlines() if l.startswith("RESULT ")]
r = json.loads(lines[-1][7:]) if lines else {}
keys = sys.argv[2:]
if not all(r.get(k) for k in keys):
    sys.exit("the peer run gave no usable RESULT line; its log:\n" + log[-3000:])
print(r[keys[0]], r[keys[1]], r[keys[2]], r[keys[3]] / 1e6)' "$@"
}

install() {
    mkdir -p "$peers"
    if [ ! -x "$peers/venv-pysph/bin/pysph" ]; then
        python3 -m venv "$peers/venv-pysph"
        "$peers/venv-pysph/bin/pip" install -q --upgrade pip
        "$peers/venv-pysph/bin/pip" install -q pysph
    fi
    # the first run compiles PySPH's generated extension modules (serial and OpenMP)
    (cd "$peers" && "$peers/venv-pysph/bin/pysph" run dam_break_2d --tf 0.001 -d warm --disable-output --openmp > /dev/null)
    if [ ! -x "$peers/venv-splash/bin/splash" ]; then
        python3 -m venv "$peers/venv-splash"
        "$peers/venv-splash/bin/pip" install -q --upgrade pip
        "$peers/venv-splash/bin/pip" install -q pysplishsplash numpy
    fi
    local gld
    gld=$(gldispatch)
    [ -n "$gld" ] || { echo "SPlisHSPlasH needs the system libGLdispatch.so.0 (Debian: apt-get install -y libglvnd0 libgl1 libglx0)"; exit 1; }
    LD_PRELOAD=$gld "$peers/venv-splash/bin/python" -c "import pysplishsplash"
    "$peers/venv-pysph/bin/pip" list 2>/dev/null | grep -iE "^(pysph|compyle|cython|numpy) "
    "$peers/venv-splash/bin/pip" list 2>/dev/null | grep -iE "^(pysplishsplash|numpy) "
    echo "peers installed in $peers"
}

# Each run prints "<wall s> <simulated s> <steps> <M fluid particle-steps/s>".
geosph() {
    local log
    log=$("$root/target/release/dam-break" "$@" --no-vtk --quiet --out "$work/geosph" 2>&1) || { echo "$log" >&2; exit 1; }
    rm -rf "$work/geosph"
    python3 -c '
import re, sys
log = sys.stdin.read()
grab = lambda p: re.search(p, log).group(1)
steps = re.search(r"steps\s+(\d+) to t = ([0-9.eE+-]+) s", log)
print(grab(r"wall time\s+([0-9.]+) s"), steps.group(2), steps.group(1), grab(r"([0-9.]+) M particle-steps/s"))' <<<"$log"
}

pysph_run() {
    (cd "$work" && "$peers/venv-pysph/bin/python" "$scripts/pysph_dambreak.py" --tf 0.3 --dx 0.015 --openmp \
        -d "$work/pysph" --disable-output > "$work/peer.log" 2>&1) || true
    rm -rf "$work/pysph"
    peer_result "$work/peer.log" run_s t_end steps fluid_particle_steps_per_s
}

# The loop time of SPlisHSPlasH leaves out its first step, which builds the volume maps.
splash_run() {
    (cd "$work" && LD_PRELOAD=$(gldispatch) "$peers/venv-splash/bin/python" -u "$scripts/splash_dambreak.py" \
        --method "$1" --max-error 0.1 --tf 1.35 --dx 0.015 --map-res 60 60 20 --out "$work/splash" \
        > "$work/peer.log" 2>&1) || true
    rm -rf "$work/splash"
    peer_result "$work/peer.log" loop_s_steps_2_to_n t_end steps fluid_particle_steps_per_s
}

case "$mode" in
install) install; exit 0 ;;
pysph | splash) ;;
*) sed -n 2,14p "$0"; exit 2 ;;
esac
[ -d "$peers/venv-$mode" ] || { echo "run '$0 install' first"; exit 1; }
scripts=${PEERS_SCRIPTS:-$root/../shared/peers}
[ -f "$scripts/pysph_dambreak.py" ] || { echo "the peers' dam-break drivers are not in $scripts: set PEERS_SCRIPTS"; exit 1; }
cargo build --release -q -p dam-break
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ "$mode" = pysph ]; then
    echo "WCSPH, dx = 0.015 m, to t = 0.3 s, 2 threads"
    geosph_args=(--dx 0.015 --end-time 0.3 --threads 2)
else
    method=${3:-DFSPH}
    echo "$method at 0.1 % mean compression, dx = 0.015 m, to t = 1.35 s, 2 threads"
    scene=$work/scene.ron
    sed -e 's/kernel: "wendland-c2"/kernel: "cubic-spline"/' -e 's/smoothing_ratio: 1.3/smoothing_ratio: 1.0/' \
        -e 's/layers: 3/layers: 2/' data/scenes/dam-break-2d.ron > "$scene"
    geosph_args=(--scene "$scene" --solver "${method,,}" --target-error 0.001 --dx 0.015 --end-time 1.35 --threads 2)
fi
printf '%-8s %-5s %10s %12s %8s %26s\n' code round "wall s" "simulated s" steps "M fluid particle-steps/s"
runs=()
peer_round() {
    local run
    if [ "$mode" = pysph ]; then run=$(pysph_run); else run=$(splash_run "$method"); fi
    runs+=("$mode $run")
    printf '%-8s %-5s %10.2f %12.3f %8d %26.3f\n' "$mode" "$1" $run
}
geosph_round() {
    local run
    run=$(geosph "${geosph_args[@]}")
    runs+=("geosph $run")
    printf '%-8s %-5s %10.2f %12.3f %8d %26.3f\n' geosph "$1" $run
}
for ((i = 1; i <= rounds; i++)); do
    if ((i % 2)); then peer_round "$i"; geosph_round "$i"; else geosph_round "$i"; peer_round "$i"; fi
done
printf '%s\n' "${runs[@]}" | python3 -c '
import sys
best = {}
for line in sys.stdin:
    code, wall, t, steps, rate = line.split()
    per_sim = float(wall) / float(t)
    b = best.setdefault(code, [float("inf"), 0.0])
    b[0], b[1] = min(b[0], per_sim), max(b[1], float(rate))
(peer, (pw, pr)), (_, (gw, gr)) = [(c, best[c]) for c in best if c != "geosph"][0], ("geosph", best["geosph"])
print(f"fastest runs: {peer} {pw:.2f}, geosph {gw:.2f} wall s per simulated s: geosph {pw / gw:.2f}x faster")
print(f"most fluid particle-steps/s: {peer} {pr:.3f} M, geosph {gr:.3f} M: ratio {gr / pr:.2f}")'
