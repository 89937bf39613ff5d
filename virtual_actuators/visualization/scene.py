"""Bookkeeping of the viewer's MeshCat nodes: objects, per-frame transforms and visibility.

Objects are created once; each frame places nodes (`Scene.place`) and shows dynamic ones
(`Scene.use`), `Scene.end_frame` hides the dynamic ones not used, and `Scene.sync` sends only
what changed.
"""

from __future__ import annotations

import numpy as np


class Scene:
    """The nodes under one prefix of a MeshCat visualizer.

    Args:
        vis: The ``meshcat.Visualizer`` of a `SceneWindow` (its root path is ``/meshcat``).
        prefix: Node under which everything is drawn.

    Attributes:
        matrices: Current world matrix of each placed node.
        visible: Current visibility of each dynamic node.
    """

    def __init__(self, vis: object, prefix: str) -> None:
        self.vis = vis
        self.prefix = prefix.strip("/")
        self._views: dict[str, object] = {}
        self._paths: dict[str, str] = {}
        self._created: set[str] = set()
        self.matrices: dict[str, np.ndarray] = {}
        self._sent: dict[str, np.ndarray] = {}
        self._dynamic: set[str] = set()
        self.visible: dict[str, bool] = {}
        self._sent_visible: dict[str, bool] = {}
        self._used: set[str] = set()

    def node(self, name: str) -> object:
        """The MeshCat view of a node (``/absolute`` names are outside the prefix)."""
        view = self._views.get(name)
        if view is None:  # no empty path element: MeshCat restarts the path at the root on one
            key = name if name.startswith("/") else "/".join(p for p in (self.prefix, name) if p)
            view = self._views[name] = self.vis[key]
        return view

    def path(self, name: str) -> str:
        """The node's full MeshCat path (``/meshcat/<prefix>/<name>``)."""
        path = self._paths.get(name)
        if path is None:
            path = self._paths[name] = self.node(name).path.lower()
        return path

    def has(self, name: str) -> bool:
        """Whether an object was created at ``name``."""
        return name in self._created

    def create(self, name: str, geometry: object, material: object = None) -> None:
        """Send the object at ``name`` once (later calls with the same name do nothing)."""
        if name in self._created:
            return
        self._created.add(name)
        self.node(name).set_object(geometry, material)

    def remove(self, name: str) -> None:
        """Delete the node ``name`` and everything under it (objects are created anew later)."""
        self.node(name).delete()
        inside = name.rstrip("/") + "/"
        for store in (self._created, self._dynamic):
            store.difference_update({n for n in store if n == name or n.startswith(inside)})
        for store in (self.matrices, self._sent, self.visible, self._sent_visible):
            for key in [n for n in store if n == name or n.startswith(inside)]:
                del store[key]

    def declare(self, name: str) -> None:
        """Make ``name`` dynamic: hidden in every frame that does not `use` it."""
        if name not in self._dynamic:
            self._dynamic.add(name)
            self.visible.setdefault(name, False)
            self._sent_visible.setdefault(name, True)  # three.js objects start visible

    def use(self, name: str) -> None:
        """Show the dynamic node ``name`` in this frame."""
        self._used.add(name)

    def place(self, name: str, matrix: np.ndarray) -> None:
        """Set the world matrix of ``name`` for this frame (sent at the next `sync`)."""
        self.matrices[name] = matrix

    def set_property(self, name: str, key: str, value: object) -> None:
        """Send a static property now (the background's colours, the camera)."""
        self.node(name).set_property(key, value)

    def end_frame(self) -> None:
        """Fix the visibility of every dynamic node for this frame."""
        used = self._used
        for name in self._dynamic:
            self.visible[name] = name in used
        self._used = set()

    def sync(self) -> None:
        """Send the transforms and visibilities that changed since the last sync, then commit."""
        window = self.vis.window  # a SceneWindow
        for name, matrix in self.matrices.items():
            previous = self._sent.get(name)
            if previous is matrix:
                continue
            self._sent[name] = matrix
            if previous is not None and np.array_equal(previous, matrix):
                continue  # placed again where it was (a frame that does not move)
            window.send_transform(self.path(name), matrix)
        for name, visible in self.visible.items():
            if self._sent_visible.get(name) != visible:
                self.node(name).set_property("visible", visible)
                self._sent_visible[name] = visible
        window.commit()  # windows that batch (the live window) send the frame now

    def __repr__(self) -> str:
        return (
            f"Scene(prefix={self.prefix!r}, {len(self._created)} objects, "
            f"{len(self.matrices)} placed, {len(self._dynamic)} dynamic)"
        )
