"""The unit registry's cache of pint's parsed definitions: used, and harmless when damaged."""

from __future__ import annotations

import subprocess
import sys

from proc import env

PROBE = ("from pdamper.units import parse_quantity, format_quantity, _registry\n"
         "print(round(parse_quantity('7.9 g/cm^3', 'kg/m^3', 'x'), 9), "
         "parse_quantity('600 1/min', 'Hz', 'x'), format_quantity(0.032, 'mm'), "
         "_registry().cache_folder)")


def _probe(cache_home):
    p = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                       env=env(XDG_CACHE_HOME=str(cache_home)), timeout=120)
    assert p.returncode == 0, p.stderr
    return p.stdout.split()


def test_definitions_cached_per_user_and_a_damaged_cache_rebuilt(tmp_path):
    folder = tmp_path / "pdamper" / "pint"
    first = _probe(tmp_path)
    assert first[:4] == ["7900.0", "10.0", "32", "mm"] and first[4] == str(folder)
    cached = sorted(folder.glob("*.pickle"))
    assert cached
    for f in cached:  # another process's half-written file, a full disk
        f.write_bytes(f.read_bytes()[:100])
    assert _probe(tmp_path) == first
    assert _probe(tmp_path) == first
    assert all(f.stat().st_size > 100 for f in folder.glob("*.pickle"))


def test_a_cache_directory_that_cannot_be_ours_is_passed_over(tmp_path):
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    out = _probe(blocked)
    assert out[:4] == ["7900.0", "10.0", "32", "mm"] and not out[4].startswith(str(blocked))
