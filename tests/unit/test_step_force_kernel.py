"""The step-local force evaluation of the compiled loop (elements rotated once per implicit step)
against the force kernel forces._wrench_kernel, and the compiled outline sinkage against NumPy.

The compiled loop's steady states against the Python reference loop (wheel 30 / 90 RPM, runner
lambda 4 at 200 RPM: 0.5 % on v, 0.2 mm on sinkage) are in test_compiled_integrator.py.
"""

import numpy as np
import pytest

from intrusim import _implicit_jit as jit
from intrusim.analysis.steady import outline_sinkage, run_steady
from intrusim.scenarios import get_scenario

CASES = [
    ("wheel", "drft", 30.0, None, "wheel-rear-half"),
    ("wheel", "drft", 90.0, None, "wheel-rear-half-effective"),
    ("wheel", "drft", 60.0, None, "wheel-rear-half-circle"),
    ("wheel", "drft", 90.0, None, ("wheel-rear-half-circle", 0.3)),  # a zone band 0.3 rad wide
    ("wheel", "drft", 30.0, None, ("wheel-rear-half", 0.2)),
    ("runner", "drft", 200.0, 4.0, None),
    ("wheel", "rft", 60.0, None, None),
]


def _model(sc, kind, lam, structural):
    if structural is None:
        return sc.build_model(kind, lam)
    from intrusim.forces import make_force_model

    structural, width = structural if isinstance(structural, tuple) else (structural, 0.0)
    return make_force_model(kind, sc.rft_shape(), lam=1.0, structural=structural, zone_width=width)


@pytest.mark.parametrize("name, kind, rpm, lam, structural", CASES)
def test_step_force_equals_kernel_bit_for_bit(name, kind, rpm, lam, structural):
    sc = get_scenario(name)
    tr = run_steady(sc, kind, rpm, lam).trajectory
    spec = _model(sc, kind, lam, structural).compiled_spec()
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, _, _, zw = spec  # no bulldozing term here
    n_el = mid.shape[0]
    geo, lead, work = np.empty((jit.GEO_ROWS, n_el)), np.empty((jit.GEO_ROWS, n_el)), np.empty((4, n_el))
    k = jit.alpha_constants(coef)
    rng = np.random.default_rng(1)
    dt, slack = 0.01, 0.02
    used = {"lead": 0, "all": 0, "kernel": 0}
    for i in range(1, len(tr.t), 7):
        th, om = tr.theta[i], tr.omega[i]
        z0, vx0, vz0 = tr.z[i - 1], tr.vx[i - 1], tr.vz[i - 1]
        for om_i in (om, 0.0):  # omega = 0: the travel sign follows vx
            _, _, fwd = jit.surface_params(fk, fr, fg, fc, fo, vx0, om_i)
            frame = jit._rotated_frame(spec, th, z0 + dt * (vz0 - slack), fwd, vx0, vz0, om_i, slack, geo, lead)
            for scale in (0.3 * slack, 3.0 * slack, 0.5):  # inside the slack, outside it, far outside
                vx, vz = vx0 + scale * rng.normal(), vz0 + scale * rng.normal()
                z = z0 + dt * vz
                got = jit._step_force(spec, frame, work, k, z, th, vx, vz, om_i)
                ref = jit._force(
                    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, 0.0, z, th, vx, vz, om_i, zw
                )
                assert got == ref
                if z < frame[4] or jit.surface_params(fk, fr, fg, fc, fo, vx, om_i)[2] != fwd:
                    used["kernel"] += 1
                elif abs(vx - vx0) <= slack and abs(vz - vz0) <= slack:
                    used["lead"] += 1
                else:
                    used["all"] += 1
    assert min(used.values()) > 0, used  # every path of _step_force was exercised


def test_outline_sinkage_matches_numpy_formula():
    sc = get_scenario("wheel")
    poly = sc.rft_shape().polygon
    rng = np.random.default_rng(2)
    z = rng.uniform(-0.1, 0.2, 300)
    th = rng.uniform(-10.0, 10.0, 300)
    ref = 0.01 - (z[:, None] + np.sin(th)[:, None] * poly[None, :, 0] + np.cos(th)[:, None] * poly[None, :, 1]).min(
        axis=1
    )
    assert np.array_equal(outline_sinkage(poly, z, th, 0.01), ref)
    z[5] = np.nan
    assert np.isnan(outline_sinkage(poly, z, th)[5]) and np.isfinite(outline_sinkage(poly, z, th)[6])
