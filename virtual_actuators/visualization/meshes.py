"""The URDF's mesh files as decimated triangle meshes, sent as binary arrays (small pages)."""

from __future__ import annotations

import numpy as np
import umsgpack
from meshcat.geometry import Geometry

from ..models.collada import collada_arrays

#: MessagePack extension codes of typed arrays in MeshCat's viewer.
_UINT16, _UINT32, _FLOAT32 = 0x14, 0x16, 0x17


def mesh_arrays(geometry: object, scale: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Vertices ``(n, 3)`` and triangles ``(m, 3)`` of a loaded mesh, or None if not a mesh.

    Args:
        geometry: A coal geometry (``BVHModel*``: vertices already scaled by ``scale``).
        scale: The URDF's ``scale`` of the mesh: a mirroring scale (negative product) turns the
            triangles inside out, so their winding is reversed back.
    """
    if not (hasattr(geometry, "num_vertices") and hasattr(geometry, "tri_indices")):
        return None
    vertices = np.asarray(geometry.vertices(), dtype=float).reshape(-1, 3)
    corners = [geometry.tri_indices(i) for i in range(geometry.num_tris)]
    triangles = np.array([(t[0], t[1], t[2]) for t in corners], dtype=np.int64).reshape(-1, 3)
    if len(vertices) == 0 or len(triangles) == 0:
        return None
    if np.prod(scale) < 0:
        triangles = triangles[:, ::-1]
    return vertices, triangles


def decimate(
    vertices: np.ndarray, triangles: np.ndarray, tolerance: float
) -> tuple[np.ndarray, np.ndarray]:
    """Merge the vertices of each cube of side ``tolerance`` into their mean (vertex clustering).

    Collapsed and duplicate triangles are dropped; a vertex moves by at most
    ``sqrt(3) * tolerance``.

    Args:
        vertices: ``(n, 3)`` [m].
        triangles: ``(m, 3)`` indices into ``vertices``.
        tolerance: Side of the grid's cells [m]; 0 keeps the mesh as it is.

    Returns:
        ``(vertices, triangles)`` of the decimated mesh.
    """
    if tolerance <= 0:
        return vertices, triangles
    cells = np.floor((vertices - vertices.min(axis=0)) / tolerance).astype(np.int64)
    _, cluster = np.unique(cells, axis=0, return_inverse=True)
    cluster = cluster.reshape(-1)
    merged = np.zeros((cluster.max() + 1, 3))
    np.add.at(merged, cluster, vertices)
    merged /= np.bincount(cluster)[:, None]
    corners = cluster[triangles]
    a, b, c = corners.T
    corners = corners[(a != b) & (b != c) & (a != c)]
    first = np.argmin(corners, axis=1)  # rotate each triangle to start at its least index
    rolled = corners[np.arange(len(corners))[:, None], (first[:, None] + np.arange(3)) % 3]
    corners = np.unique(rolled, axis=0)
    used, compact = np.unique(corners, return_inverse=True)
    return merged[used], compact.reshape(-1, 3)


def _typed(values: np.ndarray, code: int, dtype: type) -> dict:
    return {
        "itemSize": values.shape[1],
        "type": {_UINT16: "Uint16Array", _UINT32: "Uint32Array", _FLOAT32: "Float32Array"}[code],
        "array": umsgpack.Ext(code, np.ascontiguousarray(values, dtype=dtype).tobytes()),
        "normalized": False,
    }


class TriangleMesh(Geometry):
    """A three.js ``BufferGeometry`` of positions and triangle indices, for ``flatShading``.

    Args:
        vertices: ``(n, 3)`` [m].
        triangles: ``(m, 3)`` indices into ``vertices``.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray) -> None:
        super().__init__()
        self.vertices = np.asarray(vertices, dtype=np.float32).reshape(-1, 3)
        self.triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)

    def lower(self, object_data: object) -> dict:
        """The ``BufferGeometry`` JSON with binary arrays."""
        small = len(self.vertices) <= 65536
        code, dtype = (_UINT16, np.uint16) if small else (_UINT32, np.uint32)
        index = _typed(self.triangles.reshape(-1, 1), code, dtype)
        return {
            "uuid": self.uuid,
            "type": "BufferGeometry",
            "data": {
                "attributes": {"position": _typed(self.vertices, _FLOAT32, np.float32)},
                "index": index,
            },
        }

    def __repr__(self) -> str:
        return f"TriangleMesh({len(self.vertices)} vertices, {len(self.triangles)} triangles)"


class MeshCache:
    """Decimated meshes by file and scale: a file used by several links is decimated once.

    Args:
        tolerance: Side of the decimation's grid cells [m] (0: no decimation).
    """

    def __init__(self, tolerance: float) -> None:
        self.tolerance = float(tolerance)
        self._meshes: dict[tuple, tuple[np.ndarray, np.ndarray] | None] = {}

    def get(self, geometry_object: object) -> TriangleMesh | None:
        """The decimated mesh of a Pinocchio ``GeometryObject``, or None if it has none."""
        scale = np.asarray(geometry_object.meshScale, dtype=float)
        key = (str(geometry_object.meshPath), *np.round(scale, 9))
        if key not in self._meshes:
            if key[0].lower().endswith(".dae"):  # coal's Collada triangles are not all right
                arrays = collada_arrays(key[0])
                if arrays is not None:
                    vertices, triangles = arrays
                    flip = triangles[:, ::-1] if np.prod(scale) < 0 else triangles
                    arrays = (vertices * scale, flip)
            else:
                arrays = mesh_arrays(geometry_object.geometry, scale)
            self._meshes[key] = None if arrays is None else decimate(*arrays, self.tolerance)
        arrays = self._meshes[key]
        return None if arrays is None else TriangleMesh(*arrays)

    def __repr__(self) -> str:
        return f"MeshCache(tolerance={self.tolerance:g} m, {len(self._meshes)} files)"
