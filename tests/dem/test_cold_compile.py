"""A run gives the same bits whether its process compiles the numba kernels or loads them
from numba's cache (``cache=True``).

numba compiles a jitted helper that leaves ``fastmath`` unset with the setting of the
kernel whose compilation first needed it, and a kernel may call its own copy of a helper
or the separately compiled one depending on what the process compiled or loaded first;
with reassociation allowed the two copies round differently. The sampled centre of mass
and energies of :func:`pdamper.dem.kernels.sampling.record_sample` differed so in their
last bits between a cold and a warm cache (and a structure's acceleration, with it the
structure's trajectory). Each half runs in a fresh process with ``NUMBA_CACHE_DIR`` at one new directory:
the first compiles the Verlet kernels (about 20 s), the second loads them. Likewise a
contact helper compiled first by a direct call from Python (strict arithmetic) used to be
the one the kernels then linked: the force on the container differed.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from proc import env

#: A short Verlet run of a lattice under harmonic excitation; prints a SHA-256 per field.
CHILD = r"""
import dataclasses, hashlib, json, sys
if "--contact-first" in sys.argv:
    from pdamper.contact.forces import normal_force
    normal_force(1e-6, 0.1, 1e9, 0.1, 0)   # compiled from Python before any kernel
import numpy as np
from dem_inputs import engine, lattice
from pdamper.dem import HarmonicMotion

res = engine(lattice(16), motion=HarmonicMotion(0.032, 10.0), integrator="verlet",
             settle_time=0.01).run(0.02, sample_rate=2000.0, snapshot_rate=500.0)
out = {}
for f in dataclasses.fields(res):
    if f.name in ("wall_seconds", "settle_seconds", "kernel_seconds_per_sample"):
        continue  # wall times: the only thing that may differ
    v = getattr(res, f.name)
    b = (np.ascontiguousarray(v).tobytes() if isinstance(v, np.ndarray)
         else json.dumps(v, default=repr).encode())
    out[f.name] = hashlib.sha256(b).hexdigest()
print(json.dumps(out))
"""


def _hashes(tests_dir, cache, *args) -> dict:
    e = env(NUMBA_CACHE_DIR=str(cache))
    e["PYTHONPATH"] = f"{tests_dir}:{e['PYTHONPATH']}"
    proc = subprocess.run([sys.executable, "-c", CHILD, *args], env=e, capture_output=True,
                          text=True, timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def cold(tmp_path_factory, request):
    """Hashes of the run in a process that compiled every kernel into an empty cache, and
    that cache."""
    cache = tmp_path_factory.mktemp("numba-cache")
    hashes = _hashes(request.config.rootpath / "tests", cache)
    assert any(cache.rglob("*.nbi")), "the first process wrote no cache"
    return hashes, cache


@pytest.mark.long  # compiles the kernels from nothing in a subprocess: 15-20 s
def test_cold_and_warm_cache_give_the_same_bits(cold, request):
    cold, cache = cold
    warm = _hashes(request.config.rootpath / "tests", cache)   # loads the kernels
    assert "center_of_mass" in cold and "snapshot_positions" in cold
    differ = sorted(k for k in cold if cold[k] != warm.get(k))
    assert not differ, f"fields that differ between a cold and a warm numba cache: {differ}"


@pytest.mark.long  # compiles the kernels from nothing in a subprocess: 15-20 s
def test_a_helper_compiled_first_from_python_changes_no_bit(cold, tmp_path, request):
    cold, _ = cold
    other = _hashes(request.config.rootpath / "tests", tmp_path, "--contact-first")
    differ = sorted(k for k in cold if cold[k] != other.get(k))
    assert not differ, f"fields that differ when normal_force was compiled first: {differ}"
