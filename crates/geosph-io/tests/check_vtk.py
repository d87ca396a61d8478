#!/usr/bin/env python3
"""Reads geosph output with VTK itself, as ParaView would.

Usage: python3 check_vtk.py FOLDER   (needs `pip install vtk`)

For every `.vtu` under FOLDER: vtkXMLUnstructuredGridReader must read it without errors, with
as many points as the file declares, one vertex cell per point, and every point array with one
tuple per point and 1, 3 or 9 components. For every `.vtp` (surfaces): vtkXMLPolyDataReader
must read it without errors, with the declared points and triangles only, and the surface must
be watertight (vtkFeatureEdges finds no boundary and no non-manifold edge). For every `.pvtu`
(a frame in pieces, one per rank): vtkXMLPUnstructuredGridReader must read it without errors,
with as many points as its pieces declare together and the arrays it declares. For every `.pvd`: VTK's vtkXMLDataParser and Python's
xml.etree must parse it, it must be a `Collection` whose DataSets have numeric, non-decreasing
timesteps and existing files. Prints one line per file; exits with status 1 on any failure.

Sample output to check: `GEOSPH_IO_SAMPLE_DIR=FOLDER cargo test -p geosph-io sample_output`.
"""

import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import vtk


def catch_errors(vtk_object):
    """Returns the list that collects the VTK error messages of `vtk_object` from now on."""
    messages = []

    @vtk.calldata_type(vtk.VTK_STRING)
    def on_error(_caller, _event, message):
        messages.append(message)

    vtk_object.AddObserver("ErrorEvent", on_error)
    return messages


def declared_layout(path):
    """Number of points (summed over pieces) and point arrays (of the first piece) in the XML."""
    points, arrays, in_point_data, pieces = 0, 0, False, 0
    for event, element in ElementTree.iterparse(path, events=("start", "end")):
        if event == "start":
            if element.tag == "Piece":
                pieces += 1
                points += int(element.get("NumberOfPoints", "-1"))
            elif element.tag == "PointData":
                in_point_data = True
            elif element.tag == "DataArray" and in_point_data and pieces == 1:
                arrays += 1
        else:
            if element.tag == "PointData":
                in_point_data = False
            element.clear()  # keep memory flat on large frames
    return points, arrays


def read_grid(reader, path, declared, declared_arrays):
    """Reads the unstructured grid at `path` with `reader` and returns the grid and its
    problems: VTK errors, points other than the `declared` ones, cells other than one vertex per
    point, point arrays other than the `declared_arrays` or without one tuple per point and 1,
    3 or 9 components."""
    errors = catch_errors(reader)
    reader.SetFileName(str(path))
    reader.Update()
    problems = [f"VTK error: {m.strip()}" for m in errors]
    grid = reader.GetOutput()
    points = grid.GetNumberOfPoints()
    if points != declared:
        problems.append(f"{points} points read, {declared} declared")
    if grid.GetNumberOfCells() != points:
        problems.append(f"{grid.GetNumberOfCells()} cells for {points} points")
    elif points > 0 and grid.GetCellType(points - 1) != vtk.VTK_VERTEX:
        problems.append("cells are not VTK_VERTEX")
    data = grid.GetPointData()
    for i in range(data.GetNumberOfArrays()):
        array = data.GetArray(i)
        name, components = array.GetName(), array.GetNumberOfComponents()
        if array.GetNumberOfTuples() != points:
            problems.append(f"array {name}: {array.GetNumberOfTuples()} tuples for {points} points")
        if components not in (1, 3, 9):
            problems.append(f"array {name}: {components} components")
    if declared_arrays != data.GetNumberOfArrays():
        problems.append(f"{data.GetNumberOfArrays()} point arrays read, {declared_arrays} declared")
    return grid, problems


def array_names(grid):
    """The point arrays of `grid` as name[components]."""
    data = grid.GetPointData()
    return [
        f"{data.GetArray(i).GetName()}[{data.GetArray(i).GetNumberOfComponents()}]"
        for i in range(data.GetNumberOfArrays())
    ]


def check_vtu(path):
    """Returns a list of problems with the .vtu at `path` (empty when fine)."""
    try:
        declared, declared_arrays = declared_layout(path)
    except (ElementTree.ParseError, ValueError) as error:
        return [f"not the expected XML: {error}"]
    grid, problems = read_grid(vtk.vtkXMLUnstructuredGridReader(), path, declared, declared_arrays)
    points = grid.GetNumberOfPoints()
    print(f"  {path.name}: {points} points, arrays {', '.join(array_names(grid)) or '-'}")
    return problems


def check_vtp(path):
    """Returns a list of problems with the .vtp surface at `path` (empty when fine)."""
    try:
        declared, _ = declared_layout(path)
    except (ElementTree.ParseError, ValueError) as error:
        return [f"not the expected XML: {error}"]
    reader = vtk.vtkXMLPolyDataReader()
    errors = catch_errors(reader)
    reader.SetFileName(str(path))
    reader.Update()
    problems = [f"VTK error: {m.strip()}" for m in errors]
    surface = reader.GetOutput()
    points, cells = surface.GetNumberOfPoints(), surface.GetNumberOfPolys()
    if points != declared:
        problems.append(f"{points} points read, {declared} declared")
    if surface.GetNumberOfCells() != cells:
        problems.append(f"{surface.GetNumberOfCells() - cells} cells that are not polygons")
    for i in range(cells):
        if surface.GetCell(i).GetNumberOfPoints() != 3:
            problems.append(f"cell {i} is not a triangle")
            break
    edges = vtk.vtkFeatureEdges()
    edges.SetInputData(surface)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    open_edges = edges.GetOutput().GetNumberOfLines()
    if open_edges:
        problems.append(f"not watertight: {open_edges} boundary or non-manifold edges")
    print(f"  {path.name}: {points} points, {cells} triangles, watertight: {open_edges == 0}")
    return problems


def check_pvtu(path):
    """Returns a list of problems with the parallel .pvtu at `path` (empty when fine)."""
    root = ElementTree.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "PUnstructuredGrid":
        return [f"root is <{root.tag} type={root.get('type')!r}>, not a PUnstructuredGrid"]
    sources = [piece.get("Source") for piece in root.iter("Piece")]
    declared_arrays = len(list(root.iter("PPointData"))[0].findall("PDataArray"))
    declared = 0
    for source in sources:
        if source is None or not (path.parent / source).is_file():
            return [f"piece {source!r} does not exist"]
        declared += declared_layout(path.parent / source)[0]
    grid, problems = read_grid(
        vtk.vtkXMLPUnstructuredGridReader(), path, declared, declared_arrays
    )
    arrays = grid.GetPointData().GetNumberOfArrays()
    print(f"  {path.name}: {len(sources)} pieces, {grid.GetNumberOfPoints()} points, {arrays} arrays")
    return problems


def check_pvd(path):
    """Returns a list of problems with the .pvd at `path` (empty when fine)."""
    problems = []
    parser = vtk.vtkXMLDataParser()
    errors = catch_errors(parser)
    parser.SetFileName(str(path))
    if not parser.Parse():
        problems.append("vtkXMLDataParser failed: " + "; ".join(errors))
    root = ElementTree.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        problems.append(f"root is <{root.tag} type={root.get('type')!r}>, not a VTK Collection")
    times = []
    for data_set in root.iter("DataSet"):
        file = data_set.get("file")
        try:
            times.append(float(data_set.get("timestep")))
        except (TypeError, ValueError):
            problems.append(f"DataSet {file}: timestep {data_set.get('timestep')!r}")
        if file is None or not (path.parent / file).is_file():
            problems.append(f"DataSet file {file!r} does not exist")
    if any(later < earlier for earlier, later in zip(times, times[1:])):
        problems.append(f"timesteps decrease: {times}")
    print(f"  {path.name}: {len(times)} data sets, times {times}")
    return problems


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = Path(sys.argv[1])
    files = sorted(folder.rglob("*.vtu")) + sorted(folder.rglob("*.vtp"))
    files += sorted(folder.rglob("*.pvtu")) + sorted(folder.rglob("*.pvd"))
    files = [f for f in files if not f.name.startswith(".")]  # skip temporaries of a live run
    if not files:
        sys.exit(f"no .vtu, .vtp, .pvtu or .pvd files under {folder}")
    print(f"VTK {vtk.vtkVersion.GetVTKVersion()}, {len(files)} files under {folder}")
    failures = 0
    for path in files:
        check = {
            ".vtu": check_vtu,
            ".vtp": check_vtp,
            ".pvtu": check_pvtu,
            ".pvd": check_pvd,
        }[path.suffix]
        problems = check(path)
        for problem in problems:
            print(f"FAIL {path}: {problem}")
        failures += bool(problems)
    print(f"{len(files) - failures} of {len(files)} files OK")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
