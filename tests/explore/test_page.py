"""``pdamper explore`` in headless Chromium (Playwright driving Debian's chromium): the page
loads, a slider moves the forced response by what ``pdamper frf`` gives, the scenario saves,
a DEM check runs without freezing the page, bad input gets the command line's message,
Ctrl-C stops the server, which listens on this machine only.

Long tests: they need the optional ``explore`` and ``browser`` dependencies, which
``.ci/run`` installs before ``pytest -m long``."""

from __future__ import annotations

import contextlib
import signal
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("panel")
pytest.importorskip("tomli_w")
sync_api = pytest.importorskip("playwright.sync_api")

from browser import chromium  # noqa: E402
from proc import command, env  # noqa: E402

pytestmark = [pytest.mark.long,
              pytest.mark.skipif(chromium() is None, reason="chromium is not installed")]

GRID = "3Hz:9Hz:31"
#: The text of an element and of its shadow roots, without the style sheets.
TEXT = """e => { let t = ''; const walk = n => { if (n.nodeName === 'STYLE') return;
  if (n.nodeType === 3) t += n.textContent; if (n.shadowRoot) walk(n.shadowRoot);
  n.childNodes.forEach(walk); }; walk(e); return t; }"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def _server(tmp_path: Path, *args: object) -> Iterator[tuple[subprocess.Popen, str, float]]:
    port = _free_port()
    proc = subprocess.Popen(command("explore", "--no-browser", "--port", port, "--out",
                                    tmp_path, *args), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env())
    try:
        assert proc.stdout is not None
        seen = []
        for line in proc.stdout:  # the address is printed once the server listens
            seen.append(line)
            if "serving http://127.0.0.1:" in line or len(seen) > 20:
                break
        ready = time.monotonic()
        assert "serving http://127.0.0.1:" in seen[-1], "".join(seen)
        yield proc, f"http://127.0.0.1:{port}/", ready
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait(10)
        for pipe in (proc.stdout, proc.stderr):
            if pipe is not None:
                pipe.close()


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        yield b
        b.close()


def _text(page, selector: str) -> str:
    return page.locator(selector).first.evaluate(TEXT)


def _open(browser, url: str):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.goto(url)
    page.wait_for_selector(".ctl-particles-count .noUi-handle", timeout=30_000)
    return page


def _frf_peaks(*args: object) -> list[str]:
    out = subprocess.run(command("frf", "--frequency", GRID, "--sweep", "both", *args),
                         capture_output=True, text=True, env=env(), timeout=300)
    assert out.returncode == 0, out.stderr
    return [line for line in out.stdout.splitlines() if ": peak " in line]


def _peaks(page) -> list[str]:
    return [line for line in _text(page, ".peaks").splitlines() if ": peak " in line]


def _wait_text(page, selector: str, needle: str, timeout: float = 60.0) -> str:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        text = _text(page, selector)
        if needle in text:
            return text
        time.sleep(0.1)
    raise AssertionError(f"{needle!r} not in {selector}: {_text(page, selector)!r}")


def _set_frequency(page, grid: str) -> None:
    box = page.locator("input[type=text]").first  # the first text input: the frequencies
    box.fill(grid)
    box.press("Enter")


def test_page_slider_save_and_bad_input(tmp_path, browser):
    with _server(tmp_path) as (_, url, ready):
        page = _open(browser, url)
        loaded = time.monotonic() - ready
        assert loaded < 3.0, f"the page took {loaded:.1f} s"
        _set_frequency(page, GRID)
        first = _wait_text(page, ".peaks", "up: peak")
        assert _peaks(page) == _frf_peaks("--particles", 32), first
        handle = page.locator(".ctl-particles-count .noUi-handle")
        handle.focus()
        for _ in range(8):  # 32 -> 40 spheres
            page.keyboard.press("ArrowRight")
        _wait_text(page, ".ctl-particles-count", "40")
        expected = _frf_peaks("--particles", 40)
        end = time.monotonic() + 60
        while _peaks(page) != expected and time.monotonic() < end:
            time.sleep(0.2)
        assert _peaks(page) == expected  # the command's numbers, to the printed digit
        # save: the file's forced response is the view's
        page.locator(".save button").click()
        saved = Path(_wait_text(page, ".saved", "saved").split("saved ")[1].split(";")[0]
                     .strip().strip("`"))
        assert saved.parent == tmp_path and saved.exists()
        assert _frf_peaks("--scenario", saved, "--force", "2N") == expected
        # bad input: the command line's one line, on the page
        _set_frequency(page, "3Hz:9Hz:0")
        message = _wait_text(page, ".message", "error: frequency")
        cli = subprocess.run(command("frf", "--frequency", "3Hz:9Hz:0"), capture_output=True,
                             text=True, env=env(), timeout=120)
        assert cli.returncode == 2
        assert cli.stderr.strip().splitlines()[-1] in message


def test_dem_check_leaves_the_page_answering(tmp_path, browser):
    with _server(tmp_path) as (_, url, _ready):
        page = _open(browser, url)
        _set_frequency(page, GRID)
        _wait_text(page, ".peaks", "up: peak")
        page.locator(".demcheck button").click()
        _wait_text(page, ".dem", "running", timeout=30)
        # while the DEM runs, a slider still answers: the quick views redraw
        handle = page.locator(".ctl-particles-count .noUi-handle")
        handle.focus()
        page.keyboard.press("ArrowLeft")
        t0 = time.monotonic()
        _wait_text(page, ".status", "views redrawn", timeout=10)
        assert time.monotonic() - t0 < 5.0
        assert "running" in _text(page, ".dem")  # the check was still going
        done = _wait_text(page, ".dem", "DEM at", timeout=600)
        assert "eta" in done


def test_ctrl_c_stops_the_server_and_it_listens_on_localhost_only(tmp_path):
    with _server(tmp_path) as (proc, url, _ready):
        port = int(url.rsplit(":", 1)[1].strip("/"))
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:  # this machine's address
            s.connect(("10.255.255.255", 1))
            own = s.getsockname()[0]
        if own != "127.0.0.1":
            with socket.socket() as c, pytest.raises(OSError):
                c.settimeout(2)
                c.connect((own, port))
        proc.send_signal(signal.SIGINT)
        assert proc.wait(15) == 130
        assert proc.stderr is not None
        assert proc.stderr.read().strip().splitlines()[-1] == "interrupted"
