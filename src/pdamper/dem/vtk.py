"""ParaView export of DEM particle snapshots, without extra dependencies.

:func:`write_vtk_series` writes one VTK XML PolyData file (``.vtp``) per snapshot -- the
particle centres as points, each a vertex cell, with point data ``radius`` [m],
``velocity`` [m/s] (3 components), ``speed`` [m/s] and ``angular_velocity`` [rad/s] --
and a ParaView collection file (``.pvd``) that indexes them by time. Open the ``.pvd`` in
ParaView and use the *Glyph* filter (sphere, scale by ``radius``, factor 2) to see the
spheres. :func:`write_container_vtk` writes the container outline as line cells.

Data arrays are written uncompressed, either as text (``encoding="ascii"``) or base64
(``encoding="binary"``, VTK's inline binary format: a UInt64 byte count followed by the
little-endian data, encoded together). Every file is written to a temporary name in the
target directory and then renamed over the target, so that a reader never sees a half
written file; the ``.pvd`` is written last. :func:`read_vtp` and :func:`read_pvd` read
these files back (they understand the subset of the format written here).
"""

from __future__ import annotations

import base64
import math
import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Literal

import numpy as np

from pdamper.errors import InputError
from pdamper.files import atomic_write_text

__all__ = ["read_pvd", "read_vtp", "write_container_vtk", "write_vtk_series"]

Encoding = Literal["ascii", "binary"]

_RESERVED = ("radius", "velocity", "speed", "angular_velocity")
#: Snapshots per second written for ParaView when none is asked for [Hz].
DEFAULT_SNAPSHOT_RATE = 200.0

_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")
_VTK_TYPES: dict[str, np.dtype] = {
    "Float64": np.dtype("<f8"), "Int64": np.dtype("<i8"), "Float32": np.dtype("<f4"),
    "Int32": np.dtype("<i4"), "UInt8": np.dtype("u1")}


# ------------------------------------------------------------------------------ helpers


def _check_encoding(encoding: str) -> None:
    if encoding not in ("ascii", "binary"):
        raise InputError("vtk.encoding", f"must be 'ascii' or 'binary', got {encoding!r}")


def _data_array(name: str, values: np.ndarray, vtk_type: str, components: int,
                encoding: str) -> str:
    """One ``<DataArray>`` element as text."""
    data = np.ascontiguousarray(values, dtype=_VTK_TYPES[vtk_type]).ravel()
    head = (f'<DataArray type="{vtk_type}" Name="{name}" NumberOfComponents="{components}" '
            f'format="{encoding}">')
    if encoding == "binary":
        raw = data.tobytes()
        body = base64.b64encode(np.uint64(len(raw)).astype("<u8").tobytes() + raw).decode()
    elif vtk_type.startswith("Float"):
        body = " ".join(map(repr, data.astype(float).tolist()))
    else:
        body = " ".join(map(str, data.tolist()))
    return f"{head}\n{body}\n</DataArray>\n"


def _polydata(points: np.ndarray, point_data: Sequence[tuple[str, np.ndarray]],
              encoding: str, lines: np.ndarray | None = None,
              scalars: str | None = None, vectors: str | None = None) -> str:
    """A complete ``.vtp`` document: points as vertices (or the given line segments)."""
    n = points.shape[0]
    parts = ['<?xml version="1.0"?>\n',
             '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
             'header_type="UInt64">\n<PolyData>\n']
    n_lines = 0 if lines is None else lines.shape[0]
    n_verts = n if lines is None else 0
    parts.append(f'<Piece NumberOfPoints="{n}" NumberOfVerts="{n_verts}" '
                 f'NumberOfLines="{n_lines}" NumberOfStrips="0" NumberOfPolys="0">\n')
    attrs = "".join(f' {k}="{v}"' for k, v in (("Scalars", scalars), ("Vectors", vectors)) if v)
    parts.append(f"<PointData{attrs}>\n")
    for name, arr in point_data:
        components = 1 if arr.ndim == 1 else arr.shape[1]
        parts.append(_data_array(name, arr, "Float64", components, encoding))
    parts.append("</PointData>\n<Points>\n")
    parts.append(_data_array("Points", points, "Float64", 3, encoding))
    parts.append("</Points>\n")
    if lines is None:
        parts.append("<Verts>\n")
        parts.append(_data_array("connectivity", np.arange(n), "Int64", 1, encoding))
        parts.append(_data_array("offsets", np.arange(1, n + 1), "Int64", 1, encoding))
        parts.append("</Verts>\n")
    else:
        parts.append("<Lines>\n")
        parts.append(_data_array("connectivity", lines.ravel(), "Int64", 1, encoding))
        parts.append(_data_array("offsets", 2 * np.arange(1, n_lines + 1), "Int64", 1,
                                 encoding))
        parts.append("</Lines>\n")
    parts.append("</Piece>\n</PolyData>\n</VTKFile>\n")
    return "".join(parts)


def _as_array(field: str, values: object) -> np.ndarray:
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, "must be an array of numbers") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(field, "must contain only finite numbers (found NaN or inf)")
    return arr


def _per_snapshot(field: str, values: object, nt: int, n: int,
                  components: int | None) -> np.ndarray:
    """Validate per-particle data: (nt, n[, c]); a (n[, c]) array is used for every step."""
    arr = _as_array(field, values)
    tail = (n,) if components == 1 else (n, components)
    if components is None:  # extra data: scalar or any number of components
        if arr.ndim in (2, 3) and arr.shape[:2] == (nt, n):
            return arr
        shape = f"({nt}, {n}) or ({nt}, {n}, k)"
    else:
        if arr.shape == (nt, *tail):
            return arr
        if arr.shape == tail:
            return np.broadcast_to(arr, (nt, *tail))
        shape = f"({nt}, {', '.join(map(str, tail))})"
    raise InputError(field, f"must have shape {shape} to match positions, got {arr.shape}")


# ------------------------------------------------------------------------------- writers


def _point_arrays(nt: int, n: int, radii, velocities, angular_velocities,
                  extra_point_data) -> list[tuple[str, np.ndarray]]:
    """The checked point data of ``nt`` snapshots of ``n`` particles, by name."""
    arrays: list[tuple[str, np.ndarray]] = []
    if radii is not None:
        r = _as_array("vtk.radii", radii)
        if r.ndim == 0:
            r = np.full(n, float(r))
        arrays.append(("radius", _per_snapshot("vtk.radii", r, nt, n, 1)))
    if velocities is not None:
        v = _per_snapshot("vtk.velocities", velocities, nt, n, 3)
        arrays.append(("velocity", v))
        arrays.append(("speed", np.linalg.norm(v, axis=-1)))
    if angular_velocities is not None:
        arrays.append(("angular_velocity",
                       _per_snapshot("vtk.angular_velocities", angular_velocities, nt, n, 3)))
    for name, values in (extra_point_data or {}).items():
        field = f"vtk.extra_point_data[{name!r}]"
        if not isinstance(name, str) or not _NAME_RE.match(name) or name in _RESERVED:
            raise InputError(field, "name must be letters, digits, '_', '.' or '-' and not "
                             f"one of {', '.join(_RESERVED)}")
        arrays.append((name, _per_snapshot(field, values, nt, n, None)))
    return arrays


def _write_series(out_dir: Path, prefix: str, t: np.ndarray, pos: np.ndarray,
                  arrays: list[tuple[str, np.ndarray]], encoding: Encoding,
                  scalars: str | None, vectors: str | None) -> Path:
    """One ``.vtp`` per snapshot and the ``.pvd`` collection of them; the latter's path."""
    nt = pos.shape[0]
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError("vtk.directory", f"cannot create {str(out_dir)!r}: {exc}") from None
    width = max(4, len(str(max(nt - 1, 0))))
    datasets = []
    for k in range(nt):
        name = f"{prefix}_{k:0{width}d}.vtp"
        text = _polydata(pos[k], [(a, arr[k]) for a, arr in arrays], encoding,
                         scalars=scalars, vectors=vectors)
        atomic_write_text(out_dir / name, text)
        datasets.append(f'<DataSet timestep="{float(t[k])!r}" group="" part="0" '
                        f'file="{name}"/>\n')
    pvd = ('<?xml version="1.0"?>\n'
           '<VTKFile type="Collection" version="1.0" byte_order="LittleEndian">\n'
           "<Collection>\n" + "".join(datasets) + "</Collection>\n</VTKFile>\n")
    pvd_path = out_dir / f"{prefix}.pvd"
    atomic_write_text(pvd_path, pvd)
    return pvd_path


def write_vtk_series(
    directory: str | os.PathLike[str],
    times: Sequence[float] | np.ndarray,
    positions: np.ndarray,
    velocities: np.ndarray | None = None,
    radii: float | np.ndarray | None = None,
    angular_velocities: np.ndarray | None = None,
    prefix: str = "particles",
    extra_point_data: Mapping[str, np.ndarray] | None = None,
    *,
    encoding: Encoding = "binary",
) -> Path:
    """Write a ParaView time series of particle snapshots; return the ``.pvd`` path.

    Parameters
    ----------
    directory
        Output directory; created if missing.
    times
        Snapshot times, shape ``(nt,)`` [s].
    positions
        Particle centres, shape ``(nt, n, 3)`` [m].
    velocities
        Particle velocities, shape ``(nt, n, 3)`` [m/s]; also written as ``speed``.
    radii
        Particle radii [m]: one number, shape ``(n,)`` or ``(nt, n)``.
    angular_velocities
        Angular velocities, shape ``(nt, n, 3)`` [rad/s].
    prefix
        Base name of the files: ``<prefix>.pvd`` and ``<prefix>_0000.vtp``, ...
    extra_point_data
        Further point data by name, each of shape ``(nt, n)`` or ``(nt, n, k)``.
    encoding
        ``"binary"`` (base64, compact) or ``"ascii"`` (readable).

    Returns
    -------
    pathlib.Path
        Path of the ``.pvd`` collection file.

    Raises
    ------
    InputError
        When a shape does not match ``positions``, data are not finite, or a name is
        invalid.
    """
    _check_encoding(encoding)
    if not isinstance(prefix, str) or not _NAME_RE.match(prefix):
        raise InputError("vtk.prefix", "must be a file name of letters, digits, '_', '.' or "
                         f"'-' starting with a letter or '_', got {prefix!r}")
    pos = _as_array("vtk.positions", positions)
    if pos.ndim != 3 or pos.shape[2] != 3:
        raise InputError("vtk.positions", f"must have shape (nt, n, 3), got {pos.shape}")
    nt, n = pos.shape[0], pos.shape[1]
    t = _as_array("vtk.times", times)
    if t.shape != (nt,):
        raise InputError("vtk.times", f"must have shape ({nt},) to match positions "
                         f"(nt = {nt} snapshots), got {t.shape}")

    arrays = _point_arrays(nt, n, radii, velocities, angular_velocities, extra_point_data)
    return _write_series(Path(directory), prefix, t, pos, arrays, encoding,
                         scalars="radius" if radii is not None else None,
                         vectors="velocity" if velocities is not None else None)


def write_container_vtk(
    path: str | os.PathLike[str],
    box: Sequence[float],
    z_offset: float = 0.0,
    *,
    encoding: Encoding = "ascii",
) -> Path:
    """Write the outline of the container box as a ``.vtp`` of 12 line cells.

    Parameters
    ----------
    path
        Output file (``.vtp``); its directory must exist.
    box
        Inner container dimensions ``(Lx, Ly, Lz)`` [m].
    z_offset
        Vertical displacement of the container [m] (e.g. its position at a snapshot).
    encoding
        ``"ascii"`` or ``"binary"``.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from pdamper.dem.packing import _as_box  # shared box validation

    _check_encoding(encoding)
    lx, ly, lz = _as_box(box)
    dz = float(z_offset)
    if not math.isfinite(dz):
        raise InputError("container.z_offset", f"must be a finite number in m, got {dz}")
    corners = np.array([[x, y, z + dz] for z in (0.0, lz) for y in (0.0, ly) for x in (0.0, lx)])
    # corner index = 4 iz + 2 iy + ix; edges join corners differing in one bit
    edges = np.array([[a, a | bit] for bit in (1, 2, 4) for a in range(8) if not a & bit])
    out = Path(path)
    atomic_write_text(out, _polydata(corners, [], encoding, lines=edges))
    return out


# ------------------------------------------------------------------------------- readers


def _decode(element: ET.Element) -> np.ndarray:
    vtk_type = element.get("type", "Float64")
    dtype = _VTK_TYPES[vtk_type]
    text = (element.text or "").strip()
    if element.get("format") == "binary":
        raw = base64.b64decode(text)
        nbytes = int(np.frombuffer(raw[:8], dtype="<u8")[0])
        data = np.frombuffer(raw[8:8 + nbytes], dtype=dtype).copy()
    else:
        data = np.array(text.split(), dtype=dtype)
    components = int(element.get("NumberOfComponents", "1"))
    return data.reshape(-1, components) if components > 1 else data


def read_vtp(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """Read a ``.vtp`` written by this module.

    Returns
    -------
    dict
        ``"Points"`` (shape ``(n, 3)``) and every point-data array by name.
    """
    root = ET.parse(path).getroot()
    piece = root.find("PolyData/Piece")
    if piece is None:
        raise InputError("vtk.path", f"{os.fspath(path)!r} is not a VTK PolyData file")
    points = piece.find("Points/DataArray")
    if points is None:
        raise InputError("vtk.path", f"{os.fspath(path)!r} has no points")
    out = {"Points": _decode(points).reshape(-1, 3)}
    for da in piece.findall("PointData/DataArray"):
        out[da.get("Name", "")] = _decode(da)
    return out


def read_pvd(path: str | os.PathLike[str]) -> list[tuple[float, Path]]:
    """Read a ``.pvd`` collection: ``(time [s], dataset path)`` in file order."""
    root = ET.parse(path).getroot()
    base = Path(path).parent
    out = []
    for ds in root.iter("DataSet"):
        timestep, file = ds.get("timestep"), ds.get("file")
        if timestep is None or file is None:
            raise InputError("vtk.path", f"{os.fspath(path)!r}: a DataSet lacks its timestep "
                             "or file")
        out.append((float(timestep), base / file))
    return out
