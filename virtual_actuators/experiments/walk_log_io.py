"""The ``.npz`` file of a `WalkLog`: one compressed NumPy archive, read without pickle."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from virtual_actuators.exceptions import InvalidInputError

__all__ = ["META_ARRAY_PREFIX", "NPZ_FORMAT", "StoredLog", "read_npz", "write_npz"]

#: Version of the file layout.
NPZ_FORMAT = 1

#: Prefix of the archive entries that hold metadata arrays.
META_ARRAY_PREFIX = "meta_array__"


@dataclass(frozen=True, slots=True)
class StoredLog:
    """The parts of a log as written to a file and read back (``data`` in channel order)."""

    data: dict[str, np.ndarray]
    state: np.ndarray
    state_names: tuple[str, ...]
    metadata: dict[str, Any]


def write_npz(log: StoredLog, path: str | os.PathLike[str]) -> Path:
    """Write a log's parts to ``path`` as a compressed ``.npz`` (see ``WalkLog.save_npz``).

    Raises:
        InvalidInputError: If a metadata value cannot be stored (the message names its key).
    """
    path = Path(path)
    arrays: dict[str, np.ndarray] = {}
    plain: dict[str, Any] = {}
    for key, value in log.metadata.items():
        if not isinstance(key, str):
            raise InvalidInputError(f"metadata: keys must be str, got {key!r}.")
        if isinstance(value, np.ndarray):
            if value.dtype == object:
                raise InvalidInputError(f"metadata[{key!r}]: object arrays cannot be saved.")
            arrays[META_ARRAY_PREFIX + key] = value
        else:
            try:
                json.dumps(value, default=_json_default)
            except (TypeError, ValueError) as err:
                raise InvalidInputError(f"metadata[{key!r}]: cannot be saved ({err}).") from None
            plain[key] = value
    names = tuple(log.data)
    matrix = (
        np.column_stack([log.data[n] for n in names])
        if len(log.state)
        else np.zeros((0, len(names)))
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as f:
        np.savez_compressed(
            f,
            format=np.asarray(NPZ_FORMAT),
            channels=np.asarray(names, dtype=str),
            data=matrix,
            state=log.state,
            state_names=np.asarray(log.state_names, dtype=str),
            metadata_json=np.asarray(json.dumps(plain, default=_json_default)),
            **arrays,
        )
    return path


def read_npz(path: str | os.PathLike[str]) -> StoredLog:
    """Read the parts of a log written by `write_npz`.

    Raises:
        InvalidInputError: If the file is not a walk log.
    """
    path = Path(path)
    with np.load(path, allow_pickle=False) as npz:
        missing = [k for k in ("channels", "data", "state") if k not in npz.files]
        if missing:
            raise InvalidInputError(f"{path}: not a walk log (no {', '.join(missing)}).")
        names = [str(n) for n in npz["channels"]]
        matrix = npz["data"]
        metadata = json.loads(str(npz["metadata_json"])) if "metadata_json" in npz else {}
        for key in npz.files:
            if key.startswith(META_ARRAY_PREFIX):
                metadata[key[len(META_ARRAY_PREFIX) :]] = npz[key]
        state_names = tuple(str(s) for s in npz["state_names"]) if "state_names" in npz else ()
        state = npz["state"]
    if matrix.ndim != 2 or matrix.shape[1] != len(names):
        raise InvalidInputError(
            f"{path}: 'data' has shape {matrix.shape}, expected (n, {len(names)})."
        )
    data = {n: np.ascontiguousarray(matrix[:, j]) for j, n in enumerate(names)}
    return StoredLog(data, state, state_names, metadata)


def _json_default(value: Any) -> Any:
    """Convert NumPy values and sets for `json.dumps`."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, set | frozenset):
        return sorted(value, key=str)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")
