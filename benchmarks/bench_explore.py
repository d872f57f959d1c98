"""Latency of ``pdamper explore``: from a slider's new value to the views it redraws.

The page redraws in stages (docs/explore.md): the quick views (the bare structure's FRF,
the Level II map, the mass) in the server's event loop, then in a worker thread while the
page keeps answering the forced response (harmonic balance and the stepped sines of the
sweep, what ``pdamper frf`` computes): first on a coarser grid of the same band (the
preview, ``pdamper frf`` at 21 frequencies for the default 121), then on the full grid,
then the time view (``pdamper simulate``'s release or ``[load]`` run). This prints them,
per structure, for a sequence of slider values each seen for the first time (no cache),
plus a cached revisit: wall and CPU time from the slider's value to the first answer
(quick views and preview) and to the full answer (all three, as the page runs them).

    python benchmarks/bench_explore.py [--grid 3Hz:9Hz:121]
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from pdamper.explore import design
from pdamper.explore.design import Inputs

MODES = """frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]
5.5, 0.8, 0.2582, 0.2582
31.0, 0.8, -0.3162, -0.3162
"""


def _cases(tmp: Path, grid: str) -> dict[str, Inputs]:
    modes = tmp / "modes.csv"
    modes.write_text(MODES)
    scen = tmp / "two_modes.toml"
    scen.write_text(f'[structure]\nmodes = "{modes}"\n')
    return {"1-DOF (the paper's structure)": Inputs(frequency=grid),
            "two modes (modes file)": Inputs(scenario=scen, frequency=grid),
            # the page's start: no frequencies given, the command's default grid
            "1-DOF, the default grid (the mode resolved)": Inputs()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--grid", default="3Hz:9Hz:121", help="the page's frequencies")
    ap.add_argument("--moves", type=int, default=7, help="slider values per case")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        for name, base in _cases(Path(d), args.grid).items():
            # the page's first design, solved when it loads: imports and first calls out of
            # the figures
            design.quick(base)
            design.preview(base)
            design.response(base)
            quick, first, first_cpu, full, cpu, timed = [], [], [], [], [], []
            for i in range(args.moves):
                inputs = base.with_value("particles.count", 33 + i)
                t0, c0 = time.perf_counter(), time.process_time()
                design.quick(inputs)
                quick.append(time.perf_counter() - t0)
                design.preview(inputs)
                first.append(time.perf_counter() - t0)
                first_cpu.append(time.process_time() - c0)
                design.response(inputs)
                full.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
                t3 = time.perf_counter()
                design.time_response(inputs)  # the time view, solved after the response
                timed.append(time.perf_counter() - t3)
            t0 = time.perf_counter()
            design.quick(base.with_value("particles.count", 33))
            design.response(base.with_value("particles.count", 33))
            cached = time.perf_counter() - t0
            med = statistics.median
            grid = base.frequency or f"default, {design.quick(base).frequency.size} points"
            print(f"{name}, analytic, {grid}:\n"
                  f"  quick views median {med(quick) * 1e3:.0f} ms (worst "
                  f"{max(quick) * 1e3:.0f} ms)\n"
                  f"  first answer (quick views and preview) median {med(first):.2f} s "
                  f"(worst {max(first):.2f} s); CPU median {med(first_cpu):.2f} s (worst "
                  f"{max(first_cpu):.2f} s)\n"
                  f"  full answer median {med(full):.2f} s (worst {max(full):.2f} s); CPU "
                  f"median {med(cpu):.2f} s (worst {max(cpu):.2f} s)\n"
                  f"  then the time view median {med(timed):.2f} s; a revisited design "
                  f"{cached * 1e3:.1f} ms; load average {os.getloadavg()[0]:.1f} on "
                  f"{os.cpu_count()} cores", flush=True)


if __name__ == "__main__":
    main()
