#!/usr/bin/python3
"""Read files back with a real VTK reader for tests/unit/test_vtk.c.

    vtk_readback.py FILE.vtu        dump a .vtu read by vtkXMLUnstructuredGridReader
    vtk_readback.py --pvd FILE      dump a .pvd collection parsed with xml.etree
    vtk_readback.py --series FILE   dump a .vtu.series parsed with json

VTK reports problems through ErrorEvent/WarningEvent and its output window,
not exceptions, so both are watched; any report, a reader error code or an
unexpected structure makes the exit status non-zero.  Floating-point values
are printed with float.hex() so that the C test can compare them bit for bit
(strtod reads hex floats exactly).  Output of a .vtu:

    npoints N
    ncells M
    time HEX | time none
    array NAME TYPE NCOMP NTUPLES     TYPE is Float64, Int32, UInt8, ...
    v v v                             one line per tuple
    cell TYPE NPTS ID...              one line per cell
    end

For --pvd and --series: one line "entry HEX FILE" per data set, then "end".
Run with Debian's /usr/bin/python3 (python3-vtk9) or ParaView's pvpython.
"""
import json
import sys
import xml.etree.ElementTree as ET

import vtkmodules.vtkCommonCore as vcc
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def fail(msg):
    print("vtk_readback: " + msg, file=sys.stderr)
    sys.exit(1)


def is_float(arr):
    return arr.GetDataType() in (vcc.VTK_FLOAT, vcc.VTK_DOUBLE)


def type_name(arr):
    """VTK type of an array in the VTK XML spelling (Float64, UInt32, ...)."""
    bits = 8 * arr.GetDataTypeSize()
    if is_float(arr):
        return "Float%d" % bits
    return ("Int%d" if arr.GetDataTypeMin() < 0 else "UInt%d") % bits


def dump_array(name, arr):
    ncomp, ntup = arr.GetNumberOfComponents(), arr.GetNumberOfTuples()
    print("array %s %s %d %d" % (name, type_name(arr), ncomp, ntup))
    # GetValue of the concrete array is exact for 64-bit integers too, where
    # GetComponent would round through a double.
    text = (lambda v: float(v).hex()) if is_float(arr) else (lambda v: str(int(v)))
    for i in range(ntup):
        print(" ".join(text(arr.GetValue(i * ncomp + k)) for k in range(ncomp)))


def read_vtu(path):
    reports = []

    def on_report(obj, event):
        reports.append("%s from %s" % (event, obj.GetClassName()))

    # Errors of helper objects (the XML parser, the decompressor) reach only
    # the output window, so capture that as well as the reader's events.
    window = vcc.vtkStringOutputWindow()
    vcc.vtkOutputWindow.SetInstance(window)
    reader = vtkXMLUnstructuredGridReader()
    reader.AddObserver("ErrorEvent", on_report)
    reader.AddObserver("WarningEvent", on_report)
    reader.SetFileName(path)
    reader.Update()
    text = window.GetOutput()
    if reports or text.strip() or reader.GetErrorCode() != 0:
        fail("VTK reported problems reading %s: %s %s (error code %d)"
             % (path, "; ".join(reports), text.strip(), reader.GetErrorCode()))
    return reader.GetOutput()


def dump_vtu(path):
    grid = read_vtu(path)
    print("npoints %d" % grid.GetNumberOfPoints())
    print("ncells %d" % grid.GetNumberOfCells())
    tv = grid.GetFieldData().GetArray("TimeValue")
    print("time " + (float(tv.GetComponent(0, 0)).hex() if tv else "none"))
    pd = grid.GetPointData()
    for i in range(pd.GetNumberOfArrays()):
        dump_array(pd.GetArrayName(i), pd.GetArray(i))
    if grid.GetPoints() is not None:
        dump_array("Points", grid.GetPoints().GetData())
    ids = vcc.vtkIdList()
    for c in range(grid.GetNumberOfCells()):
        grid.GetCellPoints(c, ids)
        pts = [str(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]
        print("cell %d %d %s" % (grid.GetCellType(c), len(pts), " ".join(pts)))
    print("end")


def dump_pvd(path):
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        fail("%s is not a VTK Collection" % path)
    coll = root.find("Collection")
    if coll is None:
        fail("%s has no Collection element" % path)
    for ds in coll.findall("DataSet"):
        print("entry %s %s" % (float(ds.get("timestep")).hex(), ds.get("file")))
    print("end")


def dump_series(path):
    with open(path) as f:
        doc = json.load(f)
    if doc.get("file-series-version") != "1.0":
        fail("%s: file-series-version is not \"1.0\"" % path)
    for entry in doc["files"]:
        print("entry %s %s" % (float(entry["time"]).hex(), entry["name"]))
    print("end")


def main(argv):
    if len(argv) == 2:
        dump_vtu(argv[1])
    elif len(argv) == 3 and argv[1] == "--pvd":
        dump_pvd(argv[2])
    elif len(argv) == 3 and argv[1] == "--series":
        dump_series(argv[2])
    else:
        fail("usage: vtk_readback.py FILE.vtu | --pvd FILE | --series FILE")


if __name__ == "__main__":
    main(sys.argv)
