#!/usr/bin/env python3
"""Writes one mesh in every VTK encoding, with the real writers: meshio's and VTK's own.

Used by tests/engine/io/test_mesh_formats.cpp, so the readers are tested on files the programs
users have wrote, not on files xcut's own writer made.

    write_vtk_meshes.py MESH OUT_DIR [--scale S]

MESH is any file meshio reads (a Gmsh .msh); its points are multiplied by S (default 1) first, so a
mesh in metres can be written in cm (S = 100). Writes into OUT_DIR:
  meshio_{ascii,raw,zlib}.vtu, meshio_{ascii,binary}.vtk       (meshio)
  vtk_{ascii,binary,binary_zlib,appended_raw,appended_zlib,appended_base64_u64}.vtu
  vtk_legacy{42,51}_{ascii,binary}.vtk, vtk_surface.vtk (POLYDATA)   (VTK's writers)
"""
import argparse
import os

import meshio
import vtk


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--scale", type=float, default=1.0)
    a = ap.parse_args()
    m = meshio.read(a.mesh)
    m.points = m.points * a.scale
    # Only the tetrahedra, as an organ model exported for a simulator would hold.
    m = meshio.Mesh(m.points, [("tetra", m.get_cells_type("tetra"))],
                    cell_data={k: [m.get_cell_data(k, "tetra")] for k in m.cell_data if k.startswith("gmsh:")})
    out = lambda name: os.path.join(a.out, name)
    m.write(out("meshio_ascii.vtu"), binary=False)
    m.write(out("meshio_raw.vtu"), binary=True, compression=None)
    m.write(out("meshio_zlib.vtu"), binary=True, compression="zlib")
    m.write(out("meshio_ascii.vtk"), binary=False)
    m.write(out("meshio_binary.vtk"), binary=True)

    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(out("meshio_raw.vtu"))
    r.Update()
    grid = r.GetOutput()
    modes = {"ascii": 0, "binary": 1, "appended": 2}
    for name, mode, zlib, encode, u64 in [("vtk_ascii", "ascii", False, False, False),
                                          ("vtk_binary", "binary", False, False, False),
                                          ("vtk_binary_zlib", "binary", True, False, False),
                                          ("vtk_appended_raw", "appended", False, False, False),
                                          ("vtk_appended_zlib", "appended", True, False, False),
                                          ("vtk_appended_base64_u64", "appended", False, True, True)]:
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetFileName(out(name + ".vtu"))
        w.SetInputData(grid)
        w.SetDataMode(modes[mode])
        w.SetEncodeAppendedData(encode)
        if zlib:
            w.SetCompressorTypeToZLib()
        else:
            w.SetCompressorTypeToNone()
        if u64:
            w.SetHeaderTypeToUInt64()
        w.Write()
    for version in (42, 51):
        for binary in (False, True):
            w = vtk.vtkUnstructuredGridWriter()
            w.SetFileName(out(f"vtk_legacy{version}_{'binary' if binary else 'ascii'}.vtk"))
            w.SetInputData(grid)
            w.SetFileVersion(version)
            if binary:
                w.SetFileTypeToBinary()
            w.Write()
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    surface.Update()
    w = vtk.vtkPolyDataWriter()
    w.SetFileName(out("vtk_surface.vtk"))
    w.SetInputData(surface.GetOutput())
    w.SetFileTypeToBinary()
    w.Write()


if __name__ == "__main__":
    main()
