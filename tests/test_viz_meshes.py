"""Robot meshes in the viewer: Collada read without coal's help, decimated, and small pages."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("meshcat")

import virtual_actuators as va  # noqa: E402
from virtual_actuators.models.collada import collada_arrays  # noqa: E402
from virtual_actuators.visualization import OfflineWindow  # noqa: E402
from virtual_actuators.visualization.bodies import visual_model  # noqa: E402
from virtual_actuators.visualization.meshes import (  # noqa: E402
    MeshCache,
    TriangleMesh,
    decimate,
    mesh_arrays,
)


@pytest.mark.parametrize("name", ["go2", "ur5_robot"])
def test_collada_reader_spans_the_box_coal_loads(name):
    # coal (through assimp) loads every visual of the URDF: the reader shares no code with it
    for geometry_object in visual_model(va.load_robot(name)).geometryObjects:
        vertices, triangles = collada_arrays(geometry_object.meshPath)
        loaded = np.asarray(geometry_object.geometry.vertices())
        scale = float(np.ptp(loaded, axis=0).max())
        assert np.allclose(vertices.min(axis=0), loaded.min(axis=0), atol=1e-9 * scale)
        assert np.allclose(vertices.max(axis=0), loaded.max(axis=0), atol=1e-9 * scale)
        assert triangles.min() >= 0 and triangles.max() < len(vertices)


def test_decimation_moves_no_vertex_further_than_a_cell_diagonal():
    robot = va.load_robot("go2")
    thigh = next(g for g in visual_model(robot).geometryObjects if "thigh" in g.name)
    vertices, triangles = collada_arrays(thigh.meshPath)
    tolerance = 0.004
    fewer, corners = decimate(vertices, triangles, tolerance)
    assert len(fewer) < 0.6 * len(vertices) and len(corners) < 0.6 * len(triangles)
    nearest = np.min(np.linalg.norm(vertices[:, None, :] - fewer[None, :, :], axis=2), axis=1)
    assert nearest.max() <= np.sqrt(3.0) * tolerance
    assert corners.max() < len(fewer)
    assert np.all(np.diff(np.sort(corners, axis=1), axis=1) > 0)  # no collapsed triangle
    oriented = {min((a, b, c), (b, c, a), (c, a, b)) for a, b, c in corners.tolist()}
    assert len(oriented) == len(corners)  # no duplicate (a face and its back may both stay)
    assert decimate(vertices, triangles, 0.0)[0] is vertices


def test_a_mesh_file_used_by_several_links_is_decimated_once():
    robot = va.load_robot("go2")
    cache = MeshCache(0.002)
    meshes = [cache.get(g) for g in visual_model(robot).geometryObjects]
    assert all(isinstance(m, TriangleMesh) for m in meshes)
    assert "7 files" in repr(cache)  # 17 visuals, 7 mesh files


def test_go2_page_stays_small():
    # the Collada files sent as they were made a 15.6 MB page of the standing go2
    robot = va.load_robot("go2")
    viewer = va.viz.Viewer(robot, window=OfflineWindow(), legend=False)
    size = len(viewer.static_html().encode("utf-8"))
    assert size < 3_000_000, size


def binary_stl(path: str) -> np.ndarray:
    """Triangles ``(m, 3, 3)`` of a binary STL file, read with numpy alone."""
    raw = open(path, "rb").read()
    count = int(np.frombuffer(raw[80:84], np.uint32)[0])
    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    return np.frombuffer(raw[84:], record, count)["corners"].astype(float)


@pytest.mark.parametrize("name", ["solo12", "talos"])
def test_stl_triangles_are_the_files_own(name):
    # talos mirrors some meshes (scale 1 -1 1): their corners are mirrored and their winding
    # reversed, so that the faces still point outwards
    objects = visual_model(va.load_robot(name)).geometryObjects
    for geometry_object in [g for g in objects if g.meshPath.lower().endswith(".stl")][:12]:
        scale = np.asarray(geometry_object.meshScale, dtype=float)
        vertices, triangles = mesh_arrays(geometry_object.geometry, scale)
        expected = binary_stl(geometry_object.meshPath) * scale
        if np.prod(scale) < 0:
            expected = expected[:, ::-1]
        drawn = vertices[triangles]
        assert drawn.shape == expected.shape

        def canonical(corners):  # each triangle from its least corner, orientation kept
            first = np.lexsort(corners.transpose(2, 0, 1)[::-1], axis=1)[:, 0]
            rolled = corners[np.arange(len(corners))[:, None], (first[:, None] + np.arange(3)) % 3]
            order = np.lexsort(rolled.reshape(len(rolled), -1).T[::-1])
            return rolled[order]

        np.testing.assert_allclose(canonical(drawn), canonical(expected), atol=1e-6)
