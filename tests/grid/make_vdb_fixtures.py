#!/usr/bin/env python3
"""Writes the OpenVDB fixtures of src/scene/grid/vdb_tests.rs with OpenVDB itself.

Needs Debian's OpenVDB bindings (apt-get install python3-openvdb; run with
/usr/bin/python3, whose numpy they were built against). Run from this folder:
    /usr/bin/python3 make_vdb_fixtures.py
The fixtures are committed; this script documents how they were made.
"""
import numpy as np
import pyopenvdb as vdb


def sphere(radius, centre, half=False):
    """A narrow-band level set sphere (half width 3 voxels, voxel 0.05),
    with its transform translated, so the file has a UniformScaleTranslateMap."""
    g = vdb.createLevelSetSphere(radius=radius, center=centre, voxelSize=0.05, halfWidth=3.0)
    t = g.transform
    t.translate((0.02, -0.01, 0.03))
    g.transform = t
    g.name = "surface"
    g.saveFloatAsHalf = half
    return g


g = sphere(0.3, (0.1, 0.0, 0.0))
vdb.write("sphere.vdb", grids=[g])
vdb.write("sphere_half.vdb", grids=[sphere(0.3, (0.1, 0.0, 0.0), half=True)])

# OpenVDB's own dense copy of the active bounding box (inactive voxels at
# +-background, as the tree stores them), as a .npy of shape (nz, ny, nx).
lo, hi = g.evalActiveVoxelBoundingBox()
dense = np.zeros([hi[k] - lo[k] + 1 for k in range(3)], dtype=np.float32)
g.copyToArray(dense, ijk=lo)  # dense[i, j, k] = value at lo + (i, j, k)
np.save("sphere_dense.npy", np.ascontiguousarray(dense.transpose(2, 1, 0)))
print("sphere: active box", lo, hi, "origin", g.transform.indexToWorld(lo),
      "voxel size", g.transform.voxelSize(), "background", g.background)

# Several grids: a fog volume and two level sets, one with a rotated transform.
fog = vdb.FloatGrid()
fog.name = "density"
fog.gridClass = vdb.GridClass.FOG_VOLUME
fog.getAccessor().setValueOn((1, 2, 3), 0.5)
a = vdb.createLevelSetSphere(radius=0.1, voxelSize=0.05, halfWidth=2.0)
a.name = "a"
rotated = vdb.createLevelSetSphere(radius=0.1, voxelSize=0.05, halfWidth=2.0)
t = rotated.transform
t.rotate(0.5, vdb.Axis.Z)
rotated.transform = t
rotated.name = "rotated"
vdb.write("several.vdb", grids=[fog, a, rotated])
