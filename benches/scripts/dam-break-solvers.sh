#!/usr/bin/env bash
# Accuracy against run time of the four fluid solvers on the default dam break
# (docs/performance.md, "Incompressible solvers"). Run on an idle machine:
#   [END_TIME=s] [KERNEL="name h/dx wall-layers"] bash benches/scripts/dam-break-solvers.sh [dx ...]
#   (default dx: 0.02 0.015)
# END_TIME (default: the scene's 2 s) shortens the runs; 1.35 s covers every front and all
# but the last height point of Martin & Moyce. KERNEL replaces the scene's kernel, smoothing
# ratio and wall layers, e.g. KERNEL="cubic-spline 1.0 2" for SPlisHSPlasH's kernel and
# support (2 dx). Prints one Markdown table row per run.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -q -p dam-break
out=$(mktemp -d)
scene=data/scenes/dam-break-2d.ron
if [ -n "${KERNEL:-}" ]; then
    read -r kernel ratio layers <<<"$KERNEL"
    sed -e "s/kernel: \"wendland-c2\"/kernel: \"$kernel\"/" -e "s/smoothing_ratio: 1.3/smoothing_ratio: $ratio/" \
        -e "s/layers: 3/layers: $layers/" "$scene" > "$out/scene.ron"
    scene=$out/scene.ron
fi
resolutions=("$@")
[ ${#resolutions[@]} -eq 0 ] && resolutions=(0.02 0.015)
echo "| dx (m) | solver | target | steps | wall s per simulated s | mean iterations | mean compression % | max compression % | ΔZ at T = 2 | ΔZ at T = 3 | front RMS ΔZ | height RMS ΔH |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for dx in "${resolutions[@]}"; do
    for run in "wcsph -" "pcisph 0.01" "pcisph 0.001" "iisph 0.01" "iisph 0.001" "dfsph 0.01" "dfsph 0.001"; do
        read -r solver target <<<"$run"
        args=(--scene "$scene" --solver "$solver" --dx "$dx" --no-vtk --quiet --out "$out/$solver-$target-$dx")
        [ "$target" != "-" ] && args+=(--target-error "$target")
        [ -n "${END_TIME:-}" ] && args+=(--end-time "$END_TIME")
        log=$(./target/release/dam-break "${args[@]}" 2>&1) || { echo "| $dx | $solver | $target | failed: $(echo "$log" | tail -1 | sed "s|$out|<out>|g") |"; continue; }
        python3 - "$dx" "$solver" "$target" <<PY
import re, sys
log = """$log"""
dx, solver, target = sys.argv[1:]
def grab(pattern):
    m = re.search(pattern, log)
    return m.group(1) if m else "-"
steps = grab(r"steps\s+(\d+) to t")
t_end = float(grab(r"to t = ([0-9.]+) s"))
wall = float(grab(r"wall time\s+([0-9.]+) s"))
iters = grab(r"iterations\s+([0-9.]+) per step")
div = grab(r"divergence solve ([0-9.]+)\)")
if div not in ("-", "0.0"):
    iters = f"{iters} + {div}"
mean = grab(r"density error\s+mean ([0-9.]+) %")
mx = grab(r"max ([0-9.]+) %")
z2 = grab(r"front at T = 2\s+ΔZ = ([-+0-9.]+)")
z3 = grab(r"front at T = 3\s+ΔZ = ([-+0-9.]+)")
zr = grab(r"RMS ΔZ = ([0-9.]+)")
hr = grab(r"RMS ΔH = ([0-9.]+)")
target = "-" if target == "-" else f"{100*float(target):g} %"
print(f"| {dx} | {solver} | {target} | {steps} | {wall/t_end:.1f} | {iters} | {mean} | {mx} | {z2} | {z3} | {zr} | {hr} |")
PY
    done
done
rm -rf "$out"
