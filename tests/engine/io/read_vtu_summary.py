#!/usr/bin/env python3
"""Prints what VTK's own reader finds in a .vtu file, as JSON: point and cell counts, and for each
array its components, minimum, maximum and sum; the field data strings. Used by
tests/engine/io/test_output_files.cpp to check xcut's output with the reader ParaView uses."""
import json
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy


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
    fd = g.GetFieldData()
    for i in range(fd.GetNumberOfArrays()):
        arr = fd.GetAbstractArray(i)
        out["fields"][arr.GetName()] = arr.GetValue(0)
    return out


print(json.dumps(summary(sys.argv[1])))
