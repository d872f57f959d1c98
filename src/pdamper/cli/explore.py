"""``pdamper explore``: a local web page to design a damper by hand (docs/explore.md)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pdamper.cli._common import ScenarioOpt, key_help

#: Where the page's files go by default (saved scenarios, reports).
DEFAULT_OUT = "."


def explore(
    fields: Annotated[Path | None, typer.Option(
        help=key_help("fields.file", "Effective-field map (NetCDF from `pdamper map`): "
                      "offers the fields fidelity on the page."))] = None,
    port: Annotated[int, typer.Option(
        help="Port on 127.0.0.1 (0: any free port; the page binds to this machine only).",
        min=0, max=65535)] = 5006,
    no_browser: Annotated[bool, typer.Option(
        "--no-browser", help="Do not open a browser (print the address only).")] = False,
    out: Annotated[str, typer.Option(
        help="Directory where 'Save scenario' and 'Report' write by default.")] = DEFAULT_OUT,
    mass_limit: Annotated[str | None, typer.Option(
        "--max-mass", help="Mass limit of bed plus container drawn on the page, e.g. '0.5kg'.")
    ] = None,
    scenario: ScenarioOpt = None,
) -> None:
    """Start a local web page (on 127.0.0.1) to design a damper by hand: sliders for the
    damper, the structure and the load; the forced response, the Level II map with the
    structure's operating points on it, the mass against its limit; a DEM check in the background; save the
    scenario or write its report. Needs the optional dependencies:
    pip install -e ".[explore]"."""
    from pdamper.errors import InputError
    from pdamper.files import check_directory_target

    try:
        import panel  # noqa: F401
        import tomli_w  # noqa: F401
    except ImportError as exc:
        raise InputError("explore", f"needs the optional dependencies ({exc.name} is missing): "
                         "pip install -e \".[explore]\" (or pip install \"pdamper[explore]\")"
                         ) from None
    limit = None
    if mass_limit is not None:
        from pdamper.units import parse_quantity

        limit = parse_quantity(mass_limit, "kg", "max_mass")
        if not limit > 0:
            raise InputError("max_mass", f"must be > 0 kg, got {mass_limit!r}")
    out_dir = check_directory_target(out, "out")
    from pdamper.explore.design import Inputs, quick, scenario_load

    base = Inputs(scenario=scenario, fields=fields,
                  model="fields" if fields is not None else "analytic")
    base = scenario_load(base)  # the page starts from the scenario's [frf] load
    quick(base)  # the scenario judged (one line, exit 2) before the server starts
    from pdamper.explore.app import serve

    serve(base, port=port, show=not no_browser, out_dir=Path(out_dir), mass_limit=limit)
