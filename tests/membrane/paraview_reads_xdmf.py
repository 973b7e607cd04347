# SPDX-License-Identifier: MIT
"""Opens every XDMF file of a coupled run with ParaView's default reader (what OpenDataFile picks;
issue 18, item 11) and checks it against the HDF5 beside it: the cells' meshes at every time step
(points = nodes, cells = triangles, bounds = the sample's positions), the fluid's fields (points
= lattice nodes, velocity component ranges = the snapshot's). Run by pvpython:
    pvpython paraview_reads_xdmf.py RUN_FOLDER
Prints one line per file checked; exits non-zero naming the first difference."""
import glob
import os
import sys

import h5py
import numpy as np
from paraview.simple import OpenDataFile


def fail(what):
    print(f"paraview_reads_xdmf: {what}")
    sys.exit(1)


def times_of(reader):
    t = reader.TimestepValues
    return list(t) if hasattr(t, "__len__") else [t]


def close(a, b):
    return abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


def check_cells(path, reader):
    with h5py.File(path[:-4] + ".h5", "r") as f:
        positions = f["cells/mesh/positions"][...]
        faces = f["cells/mesh/faces"].shape[0]
    times = times_of(reader)
    if len(times) != positions.shape[0]:
        fail(f"{path}: {len(times)} time steps, the file has {positions.shape[0]} samples")
    for i, t in enumerate(times):
        reader.UpdatePipeline(t)
        info = reader.GetDataInformation()
        if info.GetNumberOfPoints() != positions.shape[1] or info.GetNumberOfCells() != faces:
            fail(f"{path} at t {t}: {info.GetNumberOfPoints()} points, {info.GetNumberOfCells()} "
                 f"cells; expected {positions.shape[1]} and {faces}")
        bounds = info.GetBounds()
        want = [v for a in range(3) for v in (positions[i, :, a].min(), positions[i, :, a].max())]
        if not all(close(b, w) for b, w in zip(bounds, want)):
            fail(f"{path} at t {t}: bounds {bounds}, the sample's are {want}")
    print(f"{path}: {len(times)} meshes of {positions.shape[1]} points read by {reader.GetXMLName()}")


def check_fluid(path, reader):
    with h5py.File(path[:-4] + ".h5", "r") as f:
        steps = sorted(k for k in f["fields"] if k.startswith("step_"))
        u = f[f"fields/{steps[-1]}/velocity_m_s"][...]
    times = times_of(reader)
    if len(times) != len(steps):
        fail(f"{path}: {len(times)} time steps, the file has {len(steps)} snapshots")
    if len(set(times)) != len(times):
        fail(f"{path}: a time step listed twice: {times}")
    for t in times:  # every snapshot reads whole (none empty)
        reader.UpdatePipeline(t)
        info = reader.GetDataInformation()
        if info.GetNumberOfPoints() != u.size // 3:
            fail(f"{path} at t {t}: {info.GetNumberOfPoints()} points, the lattice has "
                 f"{u.size // 3} nodes")
    array = info.GetPointDataInformation().GetArrayInformation("velocity_m_s")
    if array is None:
        fail(f"{path}: no velocity_m_s array")
    for a in range(3):
        got, want = array.GetComponentRange(a), (u[..., a].min(), u[..., a].max())
        if not (close(got[0], want[0]) and close(got[1], want[1])):
            fail(f"{path}: velocity component {a} range {got}, the snapshot's is {want}")
    print(f"{path}: {len(times)} snapshots of {u.size // 3} nodes read by {reader.GetXMLName()}")


def main(folder):
    files = sorted(glob.glob(os.path.join(os.path.abspath(folder), "*.xmf")))
    kinds = set()
    for path in files:  # the coupled run's, and a fluid-only run's (fluid-only.xmf)
        reader = OpenDataFile(path)
        if reader is None:
            fail(f"{path}: ParaView has no reader for it")
        if reader.GetXMLName() != "Xdmf3ReaderS":
            fail(f"{path}: opened by {reader.GetXMLName()}, expected ParaView's default Xdmf3ReaderS")
        if path.endswith("-fluid.xmf") or path.endswith("fluid-only.xmf"):
            check_fluid(path, reader)
            kinds.add("fluid")
        elif "-cells-" in path:
            check_cells(path, reader)
            kinds.add("cells")
    if kinds != {"fluid", "cells"}:
        fail(f"expected the fluid's and the cells' XDMF files in {folder}, found {sorted(kinds)}")
    print("paraview_reads_xdmf: ok")


if __name__ == "__main__":
    main(sys.argv[1])
