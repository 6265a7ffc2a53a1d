"""intrusim's public API: every name of __all__ resolves (lazily) to the object its module defines."""

import importlib
import subprocess
import sys

import intrusim


def test_every_public_name_resolves():
    for name in intrusim.__all__:
        if name == "__version__":
            continue
        value = getattr(intrusim, name)
        assert value is getattr(importlib.import_module(intrusim._EXPORTS[name]), name), name


def test_import_intrusim_is_light():
    code = "import sys, intrusim; print(any(m in sys.modules for m in ('numba', 'taichi', 'matplotlib')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "False"


def test_the_api_runs_a_steady_state():
    st = intrusim.run_steady(intrusim.grousered_wheel_scenario(), "drft", omega_rpm=30.0)
    assert 0.1 < st.velocity < 0.4 and 0 < st.slip < 1
