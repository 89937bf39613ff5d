"""The URDF's mesh files as compact triangle meshes: decimated, sent as binary arrays.

Pinocchio loads every mesh file of a URDF (STL, OBJ, Collada) through coal into a triangle
model, already scaled by the URDF's ``scale``. Sending the files themselves makes heavy pages:
Collada is XML, and the go2's 17 visuals were 11 MB of it (a 15.7 MB page for two seconds of
walking). Here the loaded triangles are read back (`mesh_arrays`), vertices closer than a
tolerance are merged (`decimate`, vertex clustering: a cell of a grid becomes one vertex,
triangles that collapse are dropped) and the result is sent as binary arrays
(`TriangleMesh`: float32 positions, 16-bit indices when they fit, no normals: the browser
shades each face flat). `MeshCache` decimates each file once, however many links use it.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ElementTree

import numpy as np
import umsgpack
from meshcat.geometry import Geometry

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


def collada_arrays(path: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Vertices and triangles of a Collada file's scene, placed by its nodes, in metres.

    Reads ``<triangles>`` and ``<polylist>`` / ``<polygons>`` (fans) of the geometries the
    scene's nodes instantiate, each placed by its nodes' ``<matrix>``, ``<translate>``,
    ``<rotate>`` and ``<scale>``, times the file's unit (the up axis is not applied: MeshCat's
    loader does not apply it either).

    Returns:
        ``(vertices, triangles)``, or None for a file this reader does not cover (it is then
        sent as it is).

    """
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError):
        return None
    ns = root.tag[: root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    unit = root.find(f"{ns}asset/{ns}unit")
    meters = float(unit.get("meter", 1.0)) if unit is not None else 1.0
    meshes = {g.get("id"): g.find(f"{ns}mesh") for g in root.iter(f"{ns}geometry")}
    scene = root.find(f"{ns}library_visual_scenes/{ns}visual_scene")
    if scene is None:
        return None
    pieces: list[tuple[np.ndarray, np.ndarray]] = []
    stack = [(node, np.eye(4)) for node in scene.findall(f"{ns}node")]
    while stack:
        node, above = stack.pop()
        matrix = above @ _node_matrix(node, ns)
        if node.find(f"{ns}instance_node") is not None:
            return None
        for instance in node.findall(f"{ns}instance_geometry"):
            mesh = meshes.get(instance.get("url", "")[1:])
            arrays = None if mesh is None else _collada_mesh(mesh, ns)
            if arrays is None:
                return None
            vertices, triangles = arrays
            pieces.append((vertices @ matrix[:3, :3].T + matrix[:3, 3], triangles))
        stack.extend((child, matrix) for child in node.findall(f"{ns}node"))
    if not pieces:
        return None
    offsets = np.cumsum([0] + [len(v) for v, _ in pieces[:-1]])
    vertices = np.concatenate([v for v, _ in pieces]) * meters
    triangles = np.concatenate([t + o for (_, t), o in zip(pieces, offsets, strict=True)])
    return vertices, triangles


def _node_matrix(node: ElementTree.Element, ns: str) -> np.ndarray:
    """A Collada node's placement: its transform elements composed in order."""
    matrix = np.eye(4)
    for element in node:
        tag = element.tag[len(ns) :]
        values = np.array(element.text.split(), dtype=float) if element.text else np.zeros(0)
        step = np.eye(4)
        if tag == "matrix":
            step = values.reshape(4, 4)
        elif tag == "translate":
            step[:3, 3] = values
        elif tag == "scale":
            step[:3, :3] = np.diag(values)
        elif tag == "rotate":
            axis = values[:3] / np.linalg.norm(values[:3])
            angle = math.radians(values[3])
            k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
            step[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
        else:
            continue
        matrix = matrix @ step
    return matrix


def _collada_mesh(mesh: ElementTree.Element, ns: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Positions and triangles of one Collada ``<mesh>`` (None if it has other primitives)."""
    sources = {}
    for source in mesh.findall(f"{ns}source"):
        array = source.find(f"{ns}float_array")
        if array is not None and array.text:
            sources[source.get("id")] = np.array(array.text.split(), dtype=float)
    vertices_element = mesh.find(f"{ns}vertices")
    if vertices_element is None:
        return None
    vertices_id = vertices_element.get("id")
    position = [
        i for i in vertices_element.findall(f"{ns}input") if i.get("semantic") == "POSITION"
    ]
    if not position or position[0].get("source", "")[1:] not in sources:
        return None
    positions = sources[position[0].get("source")[1:]].reshape(-1, 3)
    triangles = []
    for primitive in mesh:
        kind = primitive.tag[len(ns) :]
        if kind in ("source", "vertices", "extra", "lines", "linestrips"):  # not surfaces
            continue
        if kind not in ("triangles", "polylist"):
            return None
        inputs = primitive.findall(f"{ns}input")
        stride = 1 + max(int(i.get("offset", 0)) for i in inputs)
        vertex = [int(i.get("offset", 0)) for i in inputs if i.get("source") == f"#{vertices_id}"]
        indices_element = primitive.find(f"{ns}p")
        if not vertex or indices_element is None or not indices_element.text:
            continue
        indices = np.array(indices_element.text.split(), dtype=np.int64)
        corners = indices.reshape(-1, stride)[:, vertex[0]]
        if kind == "triangles":
            triangles.append(corners.reshape(-1, 3))
            continue
        counts = primitive.find(f"{ns}vcount")
        sizes = np.array(counts.text.split(), dtype=np.int64) if counts is not None else None
        if sizes is None or sizes.sum() != len(corners):
            return None
        starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
        for start, size in zip(starts, sizes, strict=True):  # fans
            for k in range(1, size - 1):
                triangles.append(corners[[start, start + k, start + k + 1]].reshape(1, 3))
    if not triangles:
        return None
    return positions, np.concatenate(triangles)


def decimate(
    vertices: np.ndarray, triangles: np.ndarray, tolerance: float
) -> tuple[np.ndarray, np.ndarray]:
    """Merge the vertices of each cube of side ``tolerance`` into their mean (vertex clustering).

    Triangles with two corners in one cell collapse and are dropped, duplicates are dropped,
    unused vertices removed. Every vertex moves by at most ``sqrt(3) * tolerance``.

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
    distinct = (
        (corners[:, 0] != corners[:, 1])
        & (corners[:, 1] != corners[:, 2])
        & (corners[:, 0] != corners[:, 2])
    )
    corners = corners[distinct]
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
    """A three.js ``BufferGeometry`` of positions and triangle indices (no normals).

    Draw it with a ``flatShading`` material: the browser shades each face from its own plane.

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
