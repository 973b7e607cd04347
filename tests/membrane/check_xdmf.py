# SPDX-License-Identifier: MIT
"""Checks a membrane mesh XDMF file (membrane/mesh_output) the way a reader would follow it.

Usage: check_xdmf.py FILE.xmf. Parses the XML, and for every grid of the temporal collection
checks that the triangles and the node positions it names exist in the HDF5 file beside it with
the dimensions it states, that each sample's geometry (a view, /cells/mesh/sample/i) is slab i of
the positions, and
that the faces index existing nodes. Prints "grids N" and one "grid STEP TIME SLAB" line each;
exits non-zero naming the first thing that is wrong. Needs h5py (Debian's python3-h5py).
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py


def fail(what):
    print(f"check_xdmf: {what}")
    sys.exit(1)


def dims(item):
    return [int(v) for v in item.get("Dimensions").split()]


def hdf(item, folder):
    if item.get("Format") != "HDF":
        fail(f"expected an HDF DataItem, got {item.get('Format')}")
    name, path = item.text.strip().split(":", 1)
    f = h5py.File(os.path.join(folder, name), "r")
    if path not in f:
        fail(f"{name} has no dataset {path}")
    data = f[path]
    if list(data.shape) != dims(item):
        fail(f"{name}:{path} has shape {list(data.shape)}, the XDMF says {dims(item)}")
    return data


def main(path):
    folder = os.path.dirname(os.path.abspath(path))
    root = ET.parse(path).getroot()
    if root.tag != "Xdmf":
        fail(f"root element {root.tag}")
    collections = root.findall("./Domain/Grid")
    if len(collections) != 1 or collections[0].get("CollectionType") != "Temporal":
        fail("expected one temporal collection")
    grids = collections[0].findall("Grid")
    print(f"grids {len(grids)}")
    times = []
    for g in grids:
        if g.get("GridType") != "Uniform":
            fail("a grid is not Uniform")
        times.append(float(g.find("Time").get("Value")))
        topo = g.find("Topology")
        if topo.get("TopologyType") != "Triangle":
            fail(f"topology {topo.get('TopologyType')}")
        faces = hdf(topo.find("DataItem"), folder)
        if dims(topo.find("DataItem")) != [int(topo.get("NumberOfElements")), 3]:
            fail("NumberOfElements differs from the faces' dimensions")
        geo = g.find("Geometry")
        if geo.get("GeometryType") != "XYZ":
            fail(f"geometry {geo.get('GeometryType')}")
        item = geo.find("DataItem")
        view = hdf(item, folder)  # /cells/mesh/sample/i: a view of slab i of the positions
        name, path = item.text.strip().split(":", 1)
        positions = h5py.File(os.path.join(folder, name), "r")["/cells/mesh/positions"]
        nodes = positions.shape[1]
        index = int(path.rsplit("/", 1)[1])
        if not 0 <= index < positions.shape[0]:
            fail(f"{path} names sample {index} of {positions.shape[0]}")
        if dims(item) != [nodes, 3]:
            fail(f"geometry Dimensions {dims(item)}: expected one sample, [{nodes}, 3]")
        if not (view[()] == positions[index]).all():
            fail(f"{path} differs from slab {index} of the positions")
        start = [index]
        if faces[()].min() < 0 or faces[()].max() >= nodes:
            fail("faces index nodes that do not exist")
        for a in g.findall("Attribute"):
            if dims(a.find("DataItem")) != [nodes]:
                fail(f"attribute {a.get('Name')} is not one value per node")
            hdf(a.find("DataItem"), folder)
        print(f"grid {g.get('Name').split()[-1]} {times[-1]:.17g} {start[0]}")
    if times != sorted(times):
        fail("times are not increasing")


if __name__ == "__main__":
    main(sys.argv[1])
