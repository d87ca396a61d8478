#!/usr/bin/env bash
# Same results before and after a change: records the outputs of the default runs of both
# apps, of every solver on the coarse dam break, of the granular collapse at dx = 5 mm and of
# `geosph-bench --quick`, and compares two such records file by file.
#
#   bash benches/scripts/regression.sh record DIR [BIN]   # BIN: folder of release binaries
#                                                         # (default: build them into target/)
#   bash benches/scripts/regression.sh compare OLD NEW
#
# `record` writes each run into DIR/<case>/ (frames, CSV, plots) and its printed summary into
# DIR/<case>.log. `compare` reports, per case, whether every output file is bitwise the same;
# wall-clock figures (the summary's wall time and speed, `geosph-bench`'s timing columns, its
# plots and Markdown report) and the record's own folder name are the only things left out. Where a file differs it prints the
# largest relative difference of the numbers in it, so a change of summation order shows as
# round-off (~1e-15) and a change of physics as more. Takes about 6 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."

record() {
    local dir=$1 bin=${2:-}
    if [ -z "$bin" ]; then
        cargo build --release -q -p dam-break -p slope-failure -p geosph-bench
        bin=target/release
    fi
    mkdir -p "$dir"
    run() {
        local case=$1
        shift
        rm -rf "${dir:?}/$case"
        echo "== $case: $*"
        "$@" --out "$dir/$case" >"$dir/$case.log" 2>&1 || echo "   exit $? (see $dir/$case.log)"
    }
    run dam-break-default "$bin/dam-break" --quiet
    run slope-failure-default "$bin/slope-failure" --quiet
    for solver in wcsph pcisph iisph dfsph; do
        run "dam-break-$solver-0.04" "$bin/dam-break" --solver "$solver" --dx 0.04 \
            --end-time 0.75 --quiet
    done
    run collapse-0.005 "$bin/slope-failure" --dx 0.005 --quiet
    run bench-quick "$bin/geosph-bench" --quick
}

compare() {
    python3 - "$1" "$2" <<'PY'
import pathlib, re, sys

old, new = map(pathlib.Path, sys.argv[1:])
NUMBER = re.compile(rb"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
# Wall-clock figures change from run to run by design: they are masked, not compared.
CLOCK = [
    re.compile(rb"wall time\s+[0-9.]+ s"),
    re.compile(rb"[0-9.]+ M particle-steps/s"),
    re.compile(rb"\(elapsed [^)]*\)"),
    re.compile(rb"[0-9.]+ s, (?=\d+ steps)"),
    re.compile(rb" in [0-9.]+ s;"),
    re.compile(rb"\([0-9.]+ s, error"),
]
CLOCK_COLUMNS = {b"wall_time_s", b"particle_steps_per_s"}


def comparable(root, path, data):
    if (path.suffix == ".png" and path.parent.name == "img") or path.name == "benchmarks.md":
        # The harness's plots and its Markdown report (whose Pareto fronts are chosen by wall
        # time) depend on the clock; benchmarks.csv holds every run's figures and is compared.
        return None
    if path.suffix not in (".log", ".md", ".csv", ".txt", ".pvd"):
        return data
    data = data.replace(str(root).encode(), b"<out>")
    data = re.sub(rb"\S*/(dam-break|slope-failure|geosph-bench) ", rb"\1 ", data)
    for pattern in CLOCK:
        data = pattern.sub(b"<clock>", data)
    lines = data.splitlines()
    if path.suffix == ".csv" and lines:
        header = lines[0].split(b",")
        clock = {k for k, name in enumerate(header) if name in CLOCK_COLUMNS}
        lines = [b",".join(c for k, c in enumerate(line.split(b",")) if k not in clock) for line in lines]
    return b"\n".join(lines)


def largest_relative_difference(a, b):
    x, y = NUMBER.findall(a), NUMBER.findall(b)
    if len(x) != len(y):
        return None
    worst = 0.0
    for p, q in zip(x, y):
        p, q = float(p), float(q)
        if p != q:
            worst = max(worst, abs(p - q) / max(abs(p), abs(q), 1e-300))
    return worst


same = True
for case in sorted(p for p in old.iterdir() if p.is_dir()):
    files = sorted(f.relative_to(case) for f in case.rglob("*") if f.is_file())
    files.append(pathlib.Path("..") / (case.name + ".log"))
    differ = []
    for rel in files:
        a_path, b_path = case / rel, new / case.name / rel
        if not b_path.exists():
            differ.append(f"{rel}: missing")
            continue
        a = comparable(old, rel, a_path.read_bytes())
        b = comparable(new, rel, b_path.read_bytes())
        if a is None or a == b:
            continue
        if rel.suffix in (".vtu", ".png", ".bin"):
            differ.append(f"{rel}: bytes differ")
        else:
            worst = largest_relative_difference(a, b)
            differ.append(f"{rel}: " + ("text differs" if worst is None else f"largest relative difference {worst:.2e}"))
    status = "bitwise identical" if not differ else f"{len(differ)} of {len(files)} files differ"
    print(f"{case.name}: {len(files)} files, {status}")
    for line in differ[:12]:
        print("    " + line)
    same = same and not differ
sys.exit(0 if same else 1)
PY
}

case ${1:-} in
record) record "${2:?record needs a folder}" "${3:-}" ;;
compare) compare "${2:?compare needs two folders}" "${3:?compare needs two folders}" ;;
*) echo "usage: $0 record DIR [BIN] | compare OLD NEW" >&2; exit 2 ;;
esac
