"""Collada (``.dae``) mesh files read as vertices and triangles, with numpy and the XML parser.

Used by the viewer and the MuJoCo model (MuJoCo reads only STL and OBJ); coal's Collada
triangles (through assimp) are not all right, so nothing here goes through it.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ElementTree

import numpy as np


def collada_arrays(path: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Vertices and triangles of a Collada file's scene, placed by its nodes, in metres.

    Reads ``<triangles>`` and ``<polylist>`` (as fans); the up axis is ignored, as by MeshCat.

    Returns:
        ``(vertices, triangles)``, or None for a file this reader does not cover.
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
