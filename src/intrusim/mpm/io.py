"""Run folder output: resolved config, time-series CSV, VTK snapshots, PNG plots, checkpoints."""

from __future__ import annotations

import csv
import json
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .config import REMOVED_BACKEND_KEYS, MPMConfig

if TYPE_CHECKING:
    from .backend import BenchmarkSwitches

SWITCHES_KEY = "switches"  # config.json and checkpoint meta: a run's BenchmarkSwitches other than the defaults


def package_version() -> str:
    try:
        from intrusim._version import __version__

        return __version__
    except Exception:  # pragma: no cover
        return "unknown"


def write_resolved_config(
    run_dir: Path, cfg: MPMConfig, extra: dict | None = None, switches: "BenchmarkSwitches | None" = None
) -> Path:
    """config.json with the validated config, the package version and derived numbers; the run's
    ``switches`` where they are not the defaults (``"switches"``, read back by :func:`split_switches`)."""
    run_dir.mkdir(parents=True, exist_ok=True)
    payload = {"intrusim_version": package_version(), "config": cfg.model_dump(mode="json")}
    if switches is not None and switches.changed():
        payload[SWITCHES_KEY] = switches.changed()
    if extra:
        payload["derived"] = extra
    path = run_dir / "config.json"
    atomic_write_bytes(path, json.dumps(payload, indent=2).encode())
    return path


def _file_mode() -> int:
    """The mode an ordinary new file gets here: 0o666 less the umask (mkstemp's files are 0o600)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: Path):
    """A temporary path in ``path``'s folder for a writer that takes a file name (meshio,
    matplotlib); it replaces ``path`` (with an ordinary file mode) once the block ends without
    error, and is removed on an error, so that ``path`` never holds a partial file."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


@contextmanager
def atomic_file(path: Path):
    """An open binary file in ``path``'s folder that replaces ``path`` once the block ends
    without error (written, fsynced, renamed: atomic on POSIX; the file gets an ordinary mode,
    0o666 less the umask); on an error it is removed and ``path`` is left as it was."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


LOCK = ".lock"  # in a run folder: held (flock) by the process writing the folder


@contextmanager
def run_lock(run_dir: Path | None):
    """Hold the run folder's lock for the block: a second run on the same folder is refused
    (InputError) instead of mixing its files with the first one's. On taking the lock, temporary
    files a killed writer left (``*.tmp``) are removed. On release the lock file is removed, and the
    folder too if the block left it empty (a run refused before writing anything leaves nothing).
    None: no folder, no lock."""
    if run_dir is None:
        yield
        return
    import fcntl

    from intrusim.errors import InputError

    run_dir = Path(run_dir)
    created = not run_dir.exists()
    run_dir.mkdir(parents=True, exist_ok=True)
    path = run_dir / LOCK
    while True:  # the lock file a releasing holder unlinks is not a lock: retry on the new one
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        except FileNotFoundError:  # a releasing holder removed the folder it had made: make it again
            run_dir.mkdir(parents=True, exist_ok=True)
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise InputError(
                f"{run_dir} is in use by another run (its lock {LOCK} is held); wait for it, "
                "or choose another output folder"
            ) from None
        try:
            if os.fstat(fd).st_ino == os.stat(path).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    try:
        for stale in list(run_dir.glob("*.tmp")) + list(run_dir.glob("*/*.tmp")):
            stale.unlink(missing_ok=True)
        yield
    finally:
        path.unlink(missing_ok=True)  # while still held: no one can take a lock on it in between
        os.close(fd)
        if created:
            try:
                run_dir.rmdir()  # only if empty
            except OSError:
                pass


def safe_child(root: str | Path, name: str) -> Path:
    """``root / name`` for a name made from user input (a scenario's name): a plain file name,
    never a path that leads out of ``root`` (InputError)."""
    from intrusim.errors import InputError

    if not name or name in (".", "..") or "/" in name or "\\" in name or "\0" in name or Path(name).name != name:
        raise InputError(f"name {name!r} is not a plain file name: it would write outside {root}")
    return Path(root) / name


CONFIG_KEY_IGNORED = frozenset(
    {"backend.cpu_threads", "output.directory", "time.t_end", "time.max_steps", "output.escaped"}
)


def checkpoint_config(cfg: MPMConfig) -> dict:
    """The configuration a checkpoint belongs to (stored in its meta, compared on loading)."""
    return cfg.model_dump(mode="json")


def split_switches(
    config: dict | None, recorded: dict | None = None, where: str = "saved configuration"
) -> tuple[dict | None, "BenchmarkSwitches"]:
    """A saved configuration (a run folder's config.json ``"config"``, a checkpoint's) without the
    keys that were settings of its ``backend`` table until they became internal switches
    (:data:`~intrusim.mpm.config.REMOVED_BACKEND_KEYS`), and the
    :class:`~intrusim.mpm.backend.BenchmarkSwitches` of its run: those keys, then ``recorded`` (the
    ``"switches"`` entry written beside the configuration of a run made with other switches than the
    defaults), the defaults for the rest. A folder written before the change thus loads as it was
    made: at the defaults (every run's, unless a benchmark changed them) as the same configuration
    as a run of today. A value that is no switch's true or false is an InputError naming it and ``where``."""
    from intrusim.errors import InputError

    from .backend import BenchmarkSwitches

    values: dict = {}
    backend = config.get("backend") if isinstance(config, dict) else None
    if isinstance(backend, dict) and any(k in backend for k in REMOVED_BACKEND_KEYS):
        backend = dict(backend)
        values = {k: backend.pop(k) for k in REMOVED_BACKEND_KEYS if k in backend}
        config = {**config, "backend": backend}
    if recorded is not None and not isinstance(recorded, dict):
        raise InputError(f"{where}: {SWITCHES_KEY} must be a table of switches, got {recorded!r}")
    for prefix, table in (("backend.", values), (f"{SWITCHES_KEY}.", recorded or {})):
        for key, value in table.items():
            if key not in REMOVED_BACKEND_KEYS or not isinstance(value, bool):
                raise InputError(
                    f"{where}: {prefix}{key} = {value!r} is not one of the switches "
                    f"{', '.join(REMOVED_BACKEND_KEYS)} set to true or false"
                )
    return config, BenchmarkSwitches(**{**values, **(recorded or {})})


def switch_differences(saved: "BenchmarkSwitches", switches: "BenchmarkSwitches | None") -> list[str]:
    """The switches (``backend.NAME``, as they were written when they were settings) at which a saved
    run's differ from ``switches`` (None: the defaults)."""
    from .backend import DEFAULT_SWITCHES

    now = switches or DEFAULT_SWITCHES
    return [f"backend.{k}" for k in REMOVED_BACKEND_KEYS if getattr(saved, k) != getattr(now, k)]


def checkpoint_mismatch(
    saved: dict | None,
    cfg: MPMConfig,
    switches: "BenchmarkSwitches | None" = None,
    recorded: dict | None = None,
) -> list[str]:
    """Dotted keys at which a checkpoint's configuration differs from ``cfg`` (the thread count,
    the folder, the end time, the step limit and the escape policy are not differences: see
    :func:`refuse_other_run`), and its switches (its config's former ``backend`` keys and
    ``recorded``, its meta's ``"switches"``: :func:`split_switches`) from ``switches`` (None: the
    defaults); [] for a checkpoint that stores no configuration (written by an older version)."""
    if not saved:
        return []
    saved, saved_switches = split_switches(saved, recorded, "checkpoint")
    try:  # a setting added since is its default there
        saved = MPMConfig.model_validate(saved).model_dump(mode="json")
    except ValueError:
        pass
    diff = config_differences(saved, cfg.model_dump(mode="json"), ignore=set(CONFIG_KEY_IGNORED))
    return sorted(diff + switch_differences(saved_switches, switches))


def refuse_other_run(run_dir: str | Path, cfg: MPMConfig, switches: "BenchmarkSwitches | None" = None) -> bool:
    """Raise InputError if ``run_dir`` holds a run (config.json) of a configuration other than
    ``cfg``, naming the differences. The thread count (the P2G sums do not depend on it) and the
    folder's own path (a moved folder) are not differences, and neither is a later end time: the
    same run, longer, goes on from the folder's checkpoint (nothing before the old end depends on
    the end time, so it equals a run made that long from the start), nor ``output.escaped`` turned from
    "stop" to "drop" (a run that went on to its checkpoint dropped no point, so that history is the
    same under either; a run stopped by an escape goes on from its last checkpoint). The folder's run
    switches (:func:`split_switches`: a folder written while they were settings included) must equal
    ``switches`` (None: the defaults). Returns True if the folder holds such a shorter run, which this
    one extends."""
    from intrusim.errors import InputError

    config_path = Path(run_dir) / "config.json"
    if not config_path.exists():
        return False
    payload = json.loads(config_path.read_text())
    saved, saved_switches = split_switches(payload.get("config") or {}, payload.get(SWITCHES_KEY), str(config_path))
    try:  # a setting added since the folder was written is its default there, as when it is loaded
        saved = MPMConfig.model_validate(saved).model_dump(mode="json")
    except ValueError:
        pass  # not a configuration of this version: compared as written
    diff = config_differences(
        saved, cfg.model_dump(mode="json"), ignore={"backend.cpu_threads", "output.directory", "time.max_steps"}
    )
    diff = sorted(diff + switch_differences(saved_switches, switches))
    saved_end = (saved.get("time") or {}).get("t_end")
    extends = "time.t_end" in diff and isinstance(saved_end, (int, float)) and cfg.time.t_end > saved_end
    if extends:
        diff.remove("time.t_end")
    if (
        "output.escaped" in diff
        and (saved.get("output") or {}).get("escaped") == "stop"
        and cfg.output.escaped == "drop"
    ):
        diff.remove("output.escaped")
    if diff:
        shown = ", ".join(diff[:6]) + (f" and {len(diff) - 6} more" if len(diff) > 6 else "")
        hint = " (a run can be extended to a later end time, not cut short)" if "time.t_end" in diff else ""
        raise InputError(
            f"{run_dir} holds a run of another configuration (differs in {shown}){hint}; "
            "choose another output folder, or delete that one to start afresh"
        )
    return extends


def config_differences(a: dict, b: dict, ignore: set[str] = frozenset(), prefix: str = "") -> list[str]:
    """Dotted keys at which two nested config dicts differ (keys in ``ignore`` left out)."""
    out = []
    for key in sorted(set(a) | set(b)):
        name = f"{prefix}{key}"
        if name in ignore:
            continue
        va, vb = a.get(key), b.get(key)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += config_differences(va, vb, ignore, name + ".")
        elif va != vb:
            out.append(name)
    return out


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_file`)."""
    with atomic_file(path) as fh:
        fh.write(data)


def cached_json(path: Path, compute):
    """The JSON in ``path``, or ``compute()``'s result written there atomically (a killed run leaves
    no half-written cache) and returned."""
    path = Path(path)
    if path.exists():
        return json.loads(path.read_text())
    data = compute()
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(path, json.dumps(data).encode())
    return data


def nonfinite_entries(arrays: dict[str, np.ndarray], meta: dict) -> list[str]:
    """Names of the float arrays, and of the bodies' state entries in ``meta``, holding NaN or inf."""
    bad = [k for k, a in arrays.items() if np.asarray(a).dtype.kind == "f" and not np.all(np.isfinite(a))]
    for k, body in enumerate(meta.get("bodies", []) or []):
        bad += [f"bodies.{k}.{n}" for n, v in body.items() if isinstance(v, float) and not np.isfinite(v)]
    return bad


def save_checkpoint(path: Path, arrays: dict[str, np.ndarray], meta: dict, require_finite: bool = True) -> None:
    """Atomic .npz checkpoint: particle arrays plus a JSON ``meta`` entry. With ``require_finite``
    (the default) a state holding NaN or inf is not written (SimulationError): a resumed run must
    never start from a broken state; a failure checkpoint (kept for the diagnosis) passes False."""
    if require_finite:
        bad = nonfinite_entries(arrays, meta)
        if bad:
            from .diagnostics import SimulationError

            raise SimulationError(f"checkpoint {path} not written: NaN/inf in {', '.join(bad[:5])}")
    with atomic_file(path) as fh:
        np.savez(fh, meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8), **arrays)


def load_checkpoint(path: Path) -> tuple[dict[str, np.ndarray], dict]:
    """(arrays, meta) of a checkpoint written by :func:`save_checkpoint`; a file that is not one
    (truncated, corrupt, another kind) is an InputError naming it."""
    import zipfile

    from intrusim.errors import InputError

    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files if k != "meta"}
            meta = json.loads(bytes(z["meta"]).decode())
    except (ValueError, KeyError, EOFError, zipfile.BadZipFile, UnicodeDecodeError, AttributeError) as err:
        raise InputError(f"{path} is not a readable checkpoint ({type(err).__name__}: {err})") from None
    if not isinstance(meta, dict):
        raise InputError(f"{path} is not a readable checkpoint (its meta is not a table)")
    return arrays, meta


def write_csv(path: Path, rows: list[dict]) -> None:
    """Time series as CSV (atomically rewritten, so a killed run never leaves half a line)."""
    if not rows:
        return
    import io as _io

    buf = _io.StringIO()
    # columns in order of first appearance: a run extended by a newer build may add some; the
    # rows written before them leave those cells empty
    fields = list(dict.fromkeys(k for row in rows for k in row))
    writer = csv.DictWriter(buf, fieldnames=fields, restval="")
    writer.writeheader()
    writer.writerows(rows)
    atomic_write_bytes(Path(path), buf.getvalue().encode())


# timeseries.csv: the unit of each of the solver's row keys, SI, written into the column's name
# (``fx`` -> ``fx_N``; docs/mpm.md, docs/getting-started.md "CSV files"); "" = a count (``step``).
# A second and later body's keys carry a prefix (``b1_x`` -> ``b1_x_m``). The rows in memory and in
# a checkpoint keep the short keys; a file written before the units were in the names has them as
# its header, and :func:`read_timeseries` reads both to the short keys.
TIMESERIES_UNITS: dict[str, str] = {
    "time": "s", "step": "", "x": "m", "z": "m", "theta": "rad", "vx": "m_s", "vz": "m_s", "omega": "rad_s",
    "fx": "N", "fz": "N", "moment": "N_m", "fx_ahead": "N", "fz_ahead": "N", "moment_ahead": "N_m",
    "kinetic_energy": "J", "grain_mass": "kg", "outflow_mass": "kg",
}  # fmt: skip
_TIMESERIES_KEYS = {f"{k}_{u}": k for k, u in TIMESERIES_UNITS.items() if u}


def _body_prefix(name: str) -> tuple[str, str]:
    """("b1_", "x") for "b1_x" (a later body's column), ("", name) otherwise."""
    head, _, rest = name.partition("_")
    if head[:1] == "b" and head[1:].isdigit() and rest:
        return head + "_", rest
    return "", name


def timeseries_column(key: str) -> str:
    """The ``timeseries.csv`` column of a solver row key: the key with its unit (``vx`` -> ``vx_m_s``,
    ``b1_fz`` -> ``b1_fz_N``); a key without a unit in :data:`TIMESERIES_UNITS` as it is."""
    pre, base = _body_prefix(key)
    unit = TIMESERIES_UNITS.get(base, "")
    return f"{pre}{base}_{unit}" if unit else key


def timeseries_key(column: str) -> str:
    """The solver row key of a ``timeseries.csv`` column, with its unit (``vx_m_s``) or, in a file
    written before the units were in the names, without (``vx``): ``vx`` either way."""
    pre, base = _body_prefix(column)
    return pre + _TIMESERIES_KEYS.get(base, base)


def write_timeseries(path: Path, rows: list[dict]) -> None:
    """A run's rows (short keys) as ``timeseries.csv``, each column named with its unit
    (:func:`timeseries_column`), atomically rewritten whole (:func:`write_csv`)."""
    write_csv(path, [{timeseries_column(k): v for k, v in row.items()} for row in rows])


def read_timeseries(path: str | Path) -> dict[str, np.ndarray]:
    """A run folder's ``timeseries.csv`` (the file, or the folder that holds it) as one float array
    per column, keyed by the solver's short keys (``time``, ``x``, ``fx`` ...; SI: s, m, N ...),
    whether the header names the units (``time_s``, ``x_m``, ``fx_N``) or not (files written
    before). An empty cell (a column added when an older run was extended) is NaN. An InputError
    if there is no such file or it has no header."""
    from intrusim.errors import InputError

    path = Path(path)
    if path.is_dir():
        path = path / "timeseries.csv"
    try:
        with path.open(newline="") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            rows = list(reader)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (a run folder's timeseries.csv)") from None
    if not header:
        raise InputError(f"{path} is empty: not a run's time series")
    data = np.full((len(rows), len(header)), np.nan)
    for i, row in enumerate(rows):
        for j, cell in enumerate(row[: len(header)]):
            if cell.strip():
                data[i, j] = float(cell)
    return {timeseries_key(name): data[:, j].copy() for j, name in enumerate(header)}


def write_vtk(path: Path, fields: dict[str, np.ndarray]) -> None:
    """Particle snapshot as a VTK point cloud (meshio); needs 'x' (N, 2) and point fields."""
    import meshio

    x = fields["x"]
    points = np.column_stack([x[:, 0], np.zeros(len(x)), x[:, 1]])  # (x, y=0, z)
    cells = [("vertex", np.arange(len(x)).reshape(-1, 1))]
    point_data = {}
    for k, a in fields.items():
        if k == "x":
            continue
        if a.ndim == 2 and a.shape[1] == 2:  # in-plane vector -> 3 components
            a = np.column_stack([a[:, 0], np.zeros(len(a)), a[:, 1]])
        point_data[k] = np.ascontiguousarray(a, dtype=np.float64)
    with atomic_path(path) as tmp:  # a full disk leaves no truncated file under the final name
        meshio.write(str(tmp), meshio.Mesh(points, cells, point_data=point_data), file_format="vtu", binary=True)


def write_bodies_vtk(path: Path, polygons: list[np.ndarray], cell_data: dict[str, list[float]]) -> None:
    """Rigid bodies as VTK polygons (meshio), one cell per body in the world frame (x, y=0, z),
    with one value per body of each entry of ``cell_data`` (its pose and velocity)."""
    import meshio

    points = np.vstack([np.column_stack([p[:, 0], np.zeros(len(p)), p[:, 1]]) for p in polygons])
    starts = np.cumsum([0] + [len(p) for p in polygons])
    cells = [("polygon", np.arange(a, b).reshape(1, -1)) for a, b in zip(starts[:-1], starts[1:])]
    data = {k: [np.array([v], dtype=np.float64) for v in vals] for k, vals in cell_data.items()}
    with atomic_path(path) as tmp:
        meshio.write(str(tmp), meshio.Mesh(points, cells, cell_data=data), file_format="vtu", binary=True)


def write_pvd(path: Path, entries: list[tuple[float, str, int]]) -> None:
    """ParaView collection: each (time, file name relative to ``path``, part) as a DataSet, so the
    snapshots open as one time series at their physical times (part 0 points, part 1 bodies)."""
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "  <Collection>"]
    lines += [f'    <DataSet timestep="{t:.9g}" part="{part}" file="{name}"/>' for t, name, part in entries]
    lines += ["  </Collection>", "</VTKFile>", ""]
    atomic_write_bytes(Path(path), "\n".join(lines).encode())


def plot_field(
    path: Path,
    x: np.ndarray,
    value: np.ndarray,
    label: str,
    polygons: list[np.ndarray] | None = None,
    size: tuple[float, float] | None = None,
    log: bool = False,
) -> None:
    """Scatter plot of the particles coloured by a field, with rigid bodies drawn on top."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig, ax = plt.subplots(figsize=(8, 4.5))
    norm = None
    if log:
        pos = value[value > 0]
        if len(pos):
            norm = LogNorm(vmin=max(pos.min(), pos.max() * 1e-4), vmax=pos.max())
        value = np.where(value > 0, value, np.nan)
    sc = ax.scatter(x[:, 0], x[:, 1], c=value, s=2, cmap="viridis", norm=norm, linewidths=0)
    fig.colorbar(sc, ax=ax, label=label)
    for poly in polygons or []:
        ax.fill(poly[:, 0], poly[:, 1], color="tab:red", alpha=0.8)
    if size:
        ax.set_xlim(0, size[0])
        ax.set_ylim(0, size[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)
