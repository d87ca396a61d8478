#!/usr/bin/env python3
"""Renders one 3D frame of a geosph run to a PNG, offscreen with VTK (no display needed):
the moving particles coloured by speed, the wall particles grey, from an oblique camera.

    python3 benches/scripts/render_frame.py FRAME.vtu OUT.png [--walls-below Z] [--azimuth DEG] [--title T]

FRAME.vtu is a frame of a run's `frames/` folder (its `kind` field: 0 moving, 1 wall).
`--walls-below Z` draws only the wall particles below height Z (e.g. the floor and an
obstacle, leaving the tank's sides out of the way). For the pictures in docs/; ParaView opens
the same frames with the run's .pvd series.
"""
import argparse

import vtk
from vtk.util.numpy_support import vtk_to_numpy


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("frame")
    parser.add_argument("out")
    parser.add_argument("--walls-below", type=float, default=None)
    parser.add_argument("--title", default="")
    parser.add_argument("--azimuth", type=float, default=0.0, help="turn the camera about z (deg)")
    args = parser.parse_args()

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.frame)
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    kind = vtk_to_numpy(grid.GetPointData().GetArray("kind"))
    velocity = vtk_to_numpy(grid.GetPointData().GetArray("velocity"))
    speed = (velocity**2).sum(axis=1) ** 0.5

    def cloud(mask, scalars=None):
        vtk_points = vtk.vtkPoints()
        polydata = vtk.vtkPolyData()
        selected = points[mask]
        for p in selected:
            vtk_points.InsertNextPoint(*p)
        polydata.SetPoints(vtk_points)
        if scalars is not None:
            array = vtk.vtkDoubleArray()
            array.SetName("speed")
            for value in scalars[mask]:
                array.InsertNextValue(value)
            polydata.GetPointData().SetScalars(array)
        return polydata

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)

    fluid = cloud(kind == 0, speed)
    fluid_mapper = vtk.vtkPointGaussianMapper()
    fluid_mapper.SetInputData(fluid)
    fluid_mapper.SetScaleFactor(0.0)
    fluid_mapper.EmissiveOff()
    fluid_mapper.SetScalarRange(0.0, max(float(speed[kind == 0].max()), 1e-9))
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)
    lut.Build()
    fluid_mapper.SetLookupTable(lut)
    fluid_actor = vtk.vtkActor()
    fluid_actor.SetMapper(fluid_mapper)
    fluid_actor.GetProperty().SetPointSize(3)
    fluid_actor.GetProperty().RenderPointsAsSpheresOn()
    renderer.AddActor(fluid_actor)

    walls = kind != 0
    if args.walls_below is not None:
        walls &= points[:, 2] < args.walls_below
    wall_mapper = vtk.vtkPolyDataMapper()
    wall_vertices = vtk.vtkVertexGlyphFilter()
    wall_vertices.SetInputData(cloud(walls))
    wall_mapper.SetInputConnection(wall_vertices.GetOutputPort())
    wall_actor = vtk.vtkActor()
    wall_actor.SetMapper(wall_mapper)
    wall_actor.GetProperty().SetColor(0.6, 0.6, 0.6)
    wall_actor.GetProperty().SetPointSize(2)
    renderer.AddActor(wall_actor)

    outline = vtk.vtkOutlineFilter()
    outline.SetInputData(grid)
    outline_mapper = vtk.vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    outline_actor = vtk.vtkActor()
    outline_actor.SetMapper(outline_mapper)
    outline_actor.GetProperty().SetColor(0.2, 0.2, 0.2)
    renderer.AddActor(outline_actor)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(fluid_mapper.GetLookupTable())
    bar.SetTitle("speed (m/s)")
    bar.SetNumberOfLabels(5)
    bar.GetTitleTextProperty().SetColor(0, 0, 0)
    bar.GetLabelTextProperty().SetColor(0, 0, 0)
    bar.SetWidth(0.08)
    bar.SetHeight(0.5)
    bar.SetPosition(0.02, 0.3)
    renderer.AddViewProp(bar)
    if args.title:
        text = vtk.vtkTextActor()
        text.SetInput(args.title)
        text.GetTextProperty().SetColor(0, 0, 0)
        text.GetTextProperty().SetFontSize(20)
        text.SetDisplayPosition(20, 20)
        renderer.AddViewProp(text)

    (x0, x1, y0, y1, z0, z1) = grid.GetBounds()
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 3)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(centre[0] - 0.2 * (x1 - x0), centre[1] - 1.3 * (x1 - x0), centre[2] + 0.8 * (x1 - x0))
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCameraClippingRange()
    camera.Azimuth(args.azimuth)
    renderer.ResetCameraClippingRange()
    camera.Zoom(1.3)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(1200, 700)
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.out)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()


if __name__ == "__main__":
    main()
