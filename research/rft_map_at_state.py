"""RFT force on the Table S1 wheel at a prescribed state, from the MPM medium's own plate map.

Does superposing the MPM's plate responses (RFT's assumption) give the force the MPM grains put
on the whole wheel? The wheel is held at centre height --z above the undisturbed surface (m),
moving at --vx (m/s) and spinning forward at --rpm; the force is averaged over one revolution
(720 angles). Models: the generic fit x 0.35 (the paper's RFT), the Li form fitted to the MPM map
(--table, `examples/mpm_rft_map.py fit`), and the measured map itself, interpolated linearly in
(beta, gamma) with the same mirror extension (--map, an alpha_map.csv on a regular grid).

    python research/rft_map_at_state.py --map runs/rftmap/base/alpha_map.csv \
        --table docs/figures/rft_map_mpm.json --z 0.0602 --vx 0.148 --rpm 30 --raise-mm 0,10,20,30,40

--raise-mm also evaluates each model with the free surface raised by that much (as if the grains
stood higher: a bulge, or the size term of a footing's strength that alpha |z| lacks). --parts
splits each force by part (rim, grouser sides, grouser tips) ahead of and behind the centre, as
the MPM's fx_ahead / fz_ahead split its own.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from intrusim._checks import InputError
from intrusim.analysis.compare import forces_by_part
from intrusim.analysis.rft_fit import interpolated_map
from intrusim.kinematics import BodyState, element_motion
from intrusim.laws.rft import alpha, load_coefficients, rft_traction_with
from intrusim.mpm.rft_map import read_alpha_map
from intrusim.scenarios import get_scenario
from intrusim.scenarios.locomotor import without_lugs


def map_from_csv(path: Path):
    """The measured map of an alpha_map.csv, interpolated (``analysis.rft_fit.interpolated_map``)."""
    try:
        m = read_alpha_map(path)  # the units in the header (beta_rad, alpha_x_N_m3 ...) or not (older maps)
        return interpolated_map(m["beta"], m["gamma"], m["alpha_x"], m["alpha_z"])
    except InputError as err:
        raise SystemExit(f"{path}: {err}") from None


def element_forces(elements, state: BodyState, alpha_fn) -> tuple[np.ndarray, np.ndarray]:
    """Element offsets from the centre (N, 2) and RFT forces (N, 2, N) with ``alpha_fn`` (surface at z = 0)."""
    mo = element_motion(elements, state)
    return mo.offset, rft_traction_with(alpha_fn, mo.normal, mo.velocity, mo.position[:, 1]) * elements.area[:, None]


def wrench(elements, state: BodyState, alpha_fn) -> np.ndarray:
    """(fx, fz, moment) of RFT with the stress-per-depth function ``alpha_fn`` (surface at z = 0)."""
    r, f = element_forces(elements, state, alpha_fn)
    return np.array([f[:, 0].sum(), f[:, 1].sum(), np.sum(r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0])])


def part_forces(elements, state: BodyState, alpha_fn) -> dict[str, np.ndarray]:
    """(fx, fz) of each part, ahead of (x > centre) and behind the centre."""
    r, f = element_forces(elements, state, alpha_fn)
    return forces_by_part(elements.tag, r[:, 0] > 0.0, f)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--map", type=Path, required=True, help="alpha_map.csv of examples/mpm_rft_map.py run")
    ap.add_argument("--table", type=Path, required=True, help="the Li form fitted to it (JSON)")
    ap.add_argument("--z", type=float, required=True, help="wheel centre above the undisturbed surface, m")
    ap.add_argument("--vx", type=float, required=True, help="forward speed, m/s")
    ap.add_argument("--rpm", type=float, required=True, help="forward spin, RPM (> 0)")
    ap.add_argument("--raise-mm", default="0", help="comma-separated raises of the free surface, mm (default 0)")
    ap.add_argument("--parts", action="store_true", help="also split each force by part and half")
    ap.add_argument("--smooth", action="store_true", help="the wheel's outer radius without grousers")
    ap.add_argument(
        "--lug-scale",
        type=float,
        default=None,
        help="RFT grouser height / true height (default: the scenario's 1/3, the paper's shadowing)",
    )
    ap.add_argument("--out", type=Path, help="also write the table to this CSV")
    args = ap.parse_args()
    if args.rpm <= 0:
        ap.error("--rpm must be > 0")
    try:
        raises = [float(v) for v in args.raise_mm.split(",") if v.strip()]
    except ValueError:
        ap.error(f"--raise-mm must be comma-separated numbers, got {args.raise_mm!r}")
    sc = get_scenario("wheel")
    if args.smooth:
        sc = without_lugs(sc)
    if args.lug_scale is not None:
        if not 0.0 < args.lug_scale <= 1.0:
            ap.error(f"--lug-scale must be in (0, 1], got {args.lug_scale}")
        sc = sc.model_copy(update={"lug_height_scale": args.lug_scale})
    els = sc.rft_shape().elements
    table = load_coefficients(args.table)
    models = {
        "generic x 0.35 (paper RFT)": lambda b, g: alpha(b, g, 0.35),
        "Li form fitted to the MPM map": lambda b, g: alpha(b, g, 1.0, table),
        "MPM map, interpolated": map_from_csv(args.map),
    }
    omega = -args.rpm * 2 * np.pi / 60
    thetas = np.linspace(0.0, 2 * np.pi, 721)[:-1]
    rows = []
    for up in raises:
        z = args.z - up * 1e-3  # the surface raised by `up` = the wheel that much deeper
        for name, fn in models.items():
            w = np.mean([wrench(els, BodyState(0.0, z, t, args.vx, 0.0, omega), fn) for t in thetas], axis=0)
            rows.append({"raise_mm": up, "model": name, "part": "all", "fx": w[0], "fz": w[1], "moment": w[2]})
            print(f"surface +{up:4.1f} mm  {name:32s} fx {w[0]:7.2f} N  fz {w[1]:7.2f} N  moment {w[2]:6.3f} N m")
            if args.parts:
                split = [part_forces(els, BodyState(0.0, z, t, args.vx, 0.0, omega), fn) for t in thetas]
                for key in split[0]:
                    fx, fz = np.mean([p[key] for p in split], axis=0)
                    rows.append({"raise_mm": up, "model": name, "part": key, "fx": fx, "fz": fz, "moment": ""})
                    print(f"    {key:<22s} fx {fx:7.2f} N  fz {fz:7.2f} N")
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with args.out.open("w", newline="") as f:
            w_ = csv.DictWriter(
                f, fieldnames=["body", "z", "vx", "rpm", "lug_scale", "raise_mm", "model", "part", "fx", "fz", "moment"]
            )
            w_.writeheader()
            w_.writerows({"body": sc.name, "z": args.z, "vx": args.vx, "rpm": args.rpm, "lug_scale": sc.lug_height_scale, **r}
                         for r in rows)  # fmt: skip


if __name__ == "__main__":
    main()
