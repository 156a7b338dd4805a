#!/usr/bin/env python3
"""Prints what VTK's own reader finds in a .vtu file, as JSON: point and cell counts, and for each
array its components, minimum, maximum and sum; the field data strings; and the cells' volumes at
rest (the points less displacement_m) as VTK's vtkCellSizeFilter measures them, signed: a cell whose
nodes are out of VTK's order measures negative or wrong. Used by
tests/engine/io/test_output_files.cpp to check xcut's output with the reader ParaView uses."""
import json
import sys

import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy


def rest_volumes(g):
    rest = vtk.vtkUnstructuredGrid()
    rest.DeepCopy(g)
    x = vtk_to_numpy(g.GetPoints().GetData()) - vtk_to_numpy(g.GetPointData().GetArray("displacement_m"))
    rest.GetPoints().SetData(numpy_to_vtk(x, deep=True))
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(rest)
    f.Update()
    v = vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume"))
    return {"sum": float(v.sum()), "min": float(v.min()) if len(v) else 0.0}


def summary(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    out = {"points": g.GetNumberOfPoints(), "cells": g.GetNumberOfCells(), "cell_data": {}, "point_data": {}, "fields": {},
           "cell_types": sorted({g.GetCellType(i) for i in range(g.GetNumberOfCells())})}
    for kind, data in (("cell_data", g.GetCellData()), ("point_data", g.GetPointData())):
        for i in range(data.GetNumberOfArrays()):
            a = vtk_to_numpy(data.GetArray(i))
            out[kind][data.GetArrayName(i)] = {"components": data.GetArray(i).GetNumberOfComponents(),
                                               "min": float(a.min()), "max": float(a.max()), "sum": float(a.sum()),
                                               "values": sorted(set(a.tolist())) if a.ndim == 1 and len(set(a.tolist())) < 8 else []}
    if g.GetPointData().GetArray("displacement_m") is not None:
        out["rest_volume"] = rest_volumes(g)
    fd = g.GetFieldData()
    for i in range(fd.GetNumberOfArrays()):
        arr = fd.GetAbstractArray(i)
        out["fields"][arr.GetName()] = arr.GetValue(0)
    return out


print(json.dumps(summary(sys.argv[1])))
