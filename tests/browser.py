"""Headless Chromium for the tests of the HTML reports (this directory is on ``sys.path``):
find it, load a page with a probe script and read back what the browser made of it, take
a screenshot."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path


def chromium() -> str | None:
    """The Chromium executable, or None where it is not installed."""
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def flags(tmp_path: Path) -> list[str]:
    """Chromium headless, no network use, a private profile under ``tmp_path``."""
    return [str(chromium()), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--disable-extensions", "--no-first-run", "--user-data-dir=" + str(tmp_path / "u")]


def probe(page: Path, script: str, tmp_path: Path) -> dict:
    """Load a copy of ``page`` with ``script`` (which writes JSON into the body's
    ``data-check`` attribute on load) and return that JSON."""
    copy = tmp_path / "probe.html"
    copy.write_text(page.read_text(encoding="utf-8").replace("</body>", script + "</body>"),
                    encoding="utf-8")
    dom = subprocess.run(flags(tmp_path) + ["--virtual-time-budget=10000", "--dump-dom",
                                            copy.as_uri()],
                         capture_output=True, text=True, timeout=120).stdout
    start = dom.index('data-check="') + len('data-check="')
    return json.loads(dom[start:dom.index('"', start)].replace("&quot;", '"')
                      .replace("&amp;", "&"))


def screenshot(page: Path, tmp_path: Path, height: int, width: int = 1280):
    """The page rendered at ``width`` x ``height`` pixels, as an RGB array in [0, 1]."""
    from matplotlib.image import imread

    shot = tmp_path / "shot.png"
    subprocess.run(flags(tmp_path) + [f"--screenshot={shot}", f"--window-size={width},{height}",
                                      page.as_uri()], capture_output=True, timeout=120,
                   check=True)
    return imread(shot)[..., :3]
