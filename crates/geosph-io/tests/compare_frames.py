#!/usr/bin/env python3
"""Compares two frames of the same run read with VTK: one process's `.vtu` and a distributed
run's `.pvtu` (its pieces, one per rank), as ParaView would read them.

Usage: python3 compare_frames.py ONE.vtu PIECES.pvtu   (needs `pip install vtk numpy`)

Both must hold the same particles (set `kind` 0, matched by `id`) and the same walls (set 1,
matched by position), each exactly once, with the same arrays; every array must agree within
1e-9 of its largest magnitude in the frame (the runs differ only in the order each particle
sums its neighbours: docs/parallel.md, "The validation"). Exits with status 1 otherwise.
"""

import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

BOUND = 1e-9


def read(path):
    """The point arrays and positions of the frame at `path`, by name."""
    reader = (
        vtk.vtkXMLPUnstructuredGridReader()
        if path.endswith(".pvtu")
        else vtk.vtkXMLUnstructuredGridReader()
    )
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    data = grid.GetPointData()
    arrays = {
        data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
        for i in range(data.GetNumberOfArrays())
    }
    arrays["position"] = vtk_to_numpy(grid.GetPoints().GetData())
    return arrays


def sets(arrays):
    """The particles sorted by id and the walls sorted by position."""
    fluid, walls = arrays["kind"] == 0, arrays["kind"] == 1
    by_id = np.argsort(arrays["id"][fluid], kind="stable")
    x = arrays["position"][walls]
    by_position = np.lexsort((x[:, 2], x[:, 1], x[:, 0]))
    return (
        {name: values[fluid][by_id] for name, values in arrays.items()},
        {name: values[walls][by_position] for name, values in arrays.items()},
    )


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    one, pieces = read(sys.argv[1]), read(sys.argv[2])
    problems = []
    if sorted(one) != sorted(pieces):
        problems.append(f"arrays {sorted(one)} against {sorted(pieces)}")
    for name, (a, b) in zip(("particles", "walls"), zip(sets(one), sets(pieces))):
        count = len(a["position"])
        if count != len(b["position"]):
            problems.append(f"{name}: {count} against {len(b['position'])}")
            continue
        if name == "particles" and len(np.unique(b["id"])) != count:
            problems.append("a particle appears twice in the pieces")
        for array in sorted(set(a) & set(b)):
            x, y = a[array].astype(float), b[array].astype(float)
            finite = np.isfinite(x) & np.isfinite(y)
            scale = max(np.max(np.abs(x[finite]), initial=0.0), 1e-300)
            difference = np.max(np.abs(x - y)[finite], initial=0.0)
            if np.any(np.isfinite(x) != np.isfinite(y)) or difference > BOUND * scale:
                problems.append(f"{name} {array}: differ by {difference:.3g} (scale {scale:.3g})")
            print(f"  {name:9} {array:14} {count:7} points, largest difference {difference:.2e}")
    for problem in problems:
        print(f"FAIL {problem}")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
