"""Forced response (``pdamper frf``) wall times, and the DEM's FRF against effective fields
built from a DEM map of the same damper.

Run: ``python benchmarks/bench_frf.py [--dem] [--seeds 0,1] [--frequencies 5:6:7]
[--map-frequency 5:6:5] [--map-amplitude 3e-3:30e-3:8] [--max-cycles 150] [--map FILE.nc]``

1. The paper's damper (32 spheres) on the paper's structure under a 2 N force, 121
   frequencies over 3-9 Hz: harmonic balance and both stepped sines, with the analytical
   model and with effective fields from an analytical map (wall seconds).
2. ``--dem``: the DEM stepped sine (up) at a few frequencies around resonance, once per
   seed of the random packing (the realisation spread), and the same stepped sine with
   effective fields from a DEM map (:func:`pdamper.analysis.fields.effective_field` of the
   DEM model over a small (f, X) grid around the resonance; outside it the analytical
   model answers). Prints the cost per frequency step (wall seconds, steps, cycles) and the
   amplitudes side by side with the agreement criterion: within the DEM's realisation
   spread (largest minus smallest over the seeds) or 10 % of the DEM's mean, whichever is
   larger.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from pdamper.analysis.fields import effective_field
from pdamper.coupling.frf import HarmonicLoad, frequency_response
from pdamper.models import AnalyticalDamper, DEMDamper, EffectiveFieldDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

LOAD = HarmonicLoad("force", 2.0)


def _grid(text: str, log: bool = False) -> np.ndarray:
    a, b, n = (float(v) for v in text.split(":"))
    return np.geomspace(a, b, int(n)) if log else np.linspace(a, b, int(n))


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dem", action="store_true", help="run the DEM comparison (minutes)")
    ap.add_argument("--seeds", default="0,1", help="random-packing seeds of the DEM runs")
    ap.add_argument("--frequencies", default="5:6:7", help="DEM FRF frequencies start:stop:n")
    ap.add_argument("--map-frequency", default="5:6:5", help="DEM map frequencies")
    ap.add_argument("--map-amplitude", default="3e-3:30e-3:8", help="DEM map strokes (log)")
    ap.add_argument("--max-cycles", type=int, default=150, help="DEM cycles per step at most")
    ap.add_argument("--figure", help="write the worked example of docs/forced.md (PNG)")
    ap.add_argument("--map", help="DEM map (NetCDF): reused if it exists, else computed and "
                                  "written there")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    s = PAPER_STRUCTURE
    f121 = np.linspace(3.0, 9.0, 121)

    print("\n121-point frf, 3-9 Hz, 2 N, paper damper (32 spheres) and structure")
    print("model                       harmonic balance [s]  up [s]  down [s]  total [s]  peak [mm]")
    analytic = AnalyticalDamper(PAPER_DAMPER)
    with tempfile.TemporaryDirectory() as tmp:
        amap = Path(tmp) / "analytic.nc"
        effective_field(analytic, np.linspace(2.0, 20.0, 37),
                        np.geomspace(1e-4, 0.2, 60)).to_netcdf(amap)
        fields = EffectiveFieldDamper(PAPER_DAMPER, amap, extrapolation="clamp")
        for name, m in (("analytic", analytic), ("fields (analytical map)", fields)):
            wall, r = timed(lambda m=m: frequency_response(m, s, LOAD, f121))
            w = r.wall_seconds
            print(f"{name:28s}{w['harmonic_balance']:>12.2f}{w['up']:>14.2f}{w['down']:>9.2f}"
                  f"{wall:>10.2f}{r.peak() * 1e3:>10.2f}")
    if args.figure:
        figure(Path(args.figure))
    if not args.dem:
        return

    freqs = _grid(args.frequencies)
    seeds = [int(v) for v in args.seeds.split(",")]
    print(f"\nDEM stepped sine (up), {len(freqs)} frequencies {freqs[0]:g}-{freqs[-1]:g} Hz, "
          f"at most {args.max_cycles} cycles per step, seeds {seeds} (random packing)")
    dem_amp = []
    for seed in seeds:
        dem = DEMDamper(PAPER_DAMPER, packing="random", seed=seed)
        rows = []

        def progress(f, info, rows=rows, seed=seed):
            rows.append((f, info))
            print(f"  seed {seed}: {f:6.3f} Hz  {info['cycles']:3d} cycles  "
                  f"steady {info['steady']!s:5s}  {info['wall_seconds']:7.1f} s", flush=True)

        wall, r = timed(lambda dem=dem, progress=progress: frequency_response(
            dem, s, LOAD, freqs, sweep="up", max_cycles=args.max_cycles, progress=progress))
        c = r.sweeps["up"]
        steps = c.diagnostics["steps"]
        per = c.diagnostics["wall_seconds"]
        print(f"  seed {seed}: {wall:.1f} s in all; per frequency step {np.mean(per):.1f} s "
              f"(worst {np.max(per):.1f} s), {np.mean(per / c.cycles):.2f} s and "
              f"{np.mean(steps / c.cycles):.0f} steps per load cycle; "
              f"{int(np.count_nonzero(c.steady))}/{len(freqs)} steps steady")
        dem_amp.append((c.amplitude, c.steady))

    tmp = None
    if args.map and Path(args.map).exists():
        dmap = Path(args.map)
    else:
        mf, mx = _grid(args.map_frequency), _grid(args.map_amplitude, log=True)
        print(f"\nDEM map for the fields model: {mf.size} x {mx.size} points "
              f"({mf[0]:g}-{mf[-1]:g} Hz, {mx[0] * 1e3:g}-{mx[-1] * 1e3:g} mm)", flush=True)
        if args.map:  # computed once, kept for the next run
            dmap = Path(args.map)
        else:
            tmp = tempfile.TemporaryDirectory()
            dmap = Path(tmp.name) / "dem.nc"
        wall, ds = timed(lambda: effective_field(DEMDamper(PAPER_DAMPER, packing="random",
                                                           seed=seeds[0]), mf, mx))
        ds.to_netcdf(dmap)
        print(f"  map: {wall:.0f} s, {int(ds['stationary'].sum())}/{ds['stationary'].size} "
              "points steady")
    fields = EffectiveFieldDamper(PAPER_DAMPER, dmap, extrapolation="analytic",
                                  nonstationary="use")
    r = frequency_response(fields, s, LOAD, freqs, sweep="up")
    fa = r.sweeps["up"].amplitude
    amps = np.array([a for a, _ in dem_amp])
    mean = amps.mean(axis=0)
    spread = amps.max(axis=0) - amps.min(axis=0)
    allowed = np.maximum(spread, 0.1 * mean)
    print("\n  f [Hz]  DEM [mm] (per seed)          fields from DEM map [mm]  |diff| [mm]  "
          "allowed [mm]  ok")
    for i, f in enumerate(freqs):
        per = " ".join(f"{a[i] * 1e3:6.2f}{'' if st[i] else '*'}" for a, st in dem_amp)
        ok = abs(fa[i] - mean[i]) <= allowed[i]
        print(f"  {f:6.3f}  {per:28s} {fa[i] * 1e3:10.2f}            {abs(fa[i] - mean[i]) * 1e3:8.2f}"
              f"  {allowed[i] * 1e3:10.2f}    {'yes' if ok else 'NO'}")
    print("  (* : the DEM step did not become steady within --max-cycles)")
    if tmp is not None:
        tmp.cleanup()


def figure(path: Path) -> None:
    """docs/forced.md's worked example: the paper's damper at 2 N over 3-9 Hz, and 128
    spheres at 1 N, whose sweeps jump between branches near 5.1 Hz."""
    from matplotlib.figure import Figure

    from pdamper.plots.frf import plot_frf

    s = PAPER_STRUCTURE
    a = frequency_response(AnalyticalDamper(PAPER_DAMPER), s, LOAD, np.linspace(3, 9, 121))
    b = frequency_response(AnalyticalDamper(PAPER_DAMPER.with_count(128)), s,
                           HarmonicLoad("force", 1.0), np.linspace(4.9, 5.4, 26))
    fig = Figure(figsize=(11, 6), layout="constrained")
    ax = fig.subplots(2, 2, sharex="col")
    plot_frf(a, axes=ax[:, 0])
    ax[0, 0].set_ylim(0, 50)
    ax[0, 0].set_title("32 spheres, 2 N (analytic model)")
    plot_frf(b, axes=ax[:, 1])
    ax[0, 1].set_ylim(0, 16)
    ax[0, 1].set_title("128 spheres, 1 N: a jump, up and down sweeps differ")
    fig.savefig(path, dpi=72)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()
