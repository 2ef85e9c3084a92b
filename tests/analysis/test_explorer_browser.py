"""The explorer page in headless Chromium: sliders moved, the counts shown checked.

Chromium is driven over the DevTools protocol on a pipe (``--remote-debugging-pipe``:
JSON messages ended by a NUL byte, commands on its file descriptor 3, answers on 4), so
no driver or Python package is needed. Marked ``browser``: ``make test-browser`` runs
these tests (installing Chromium first), ``make test-python`` leaves them out; without
Chromium they fail, never skip.
"""

import csv
import json
import select
import shutil
import subprocess
from pathlib import Path

import pytest

from hrbench_analysis.explorer import EPS, LENGTHS, write_explorer

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
TIMEOUT = 60  # seconds for Chromium to start and to answer


class Browser:
    """One headless Chromium and one page, driven with DevTools protocol commands."""

    def __init__(self, profile):
        program = shutil.which("chromium") or shutil.which("chromium-browser")
        if program is None:
            pytest.fail("chromium is not installed: run `scripts/setup.sh --browser` "
                        "(make test-browser does)")
        # The shell moves our pipes to descriptors 3 (commands) and 4 (answers).
        self.proc = subprocess.Popen(
            ["sh", "-c", 'exec "$0" "$@" 3<&0 4>&1 0</dev/null 1>/dev/null', program,
             "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--remote-debugging-pipe", f"--user-data-dir={profile}", "about:blank"],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            bufsize=0)
        self.buffer = b""
        self.next_id = 0
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.send("Target.attachToTarget", targetId=target,
                                 flatten=True)["sessionId"]

    def send(self, method, session=None, **params):
        # Send one command and return its result; events in between are dropped.
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        self.proc.stdin.write(json.dumps(message).encode() + b"\0")
        self.proc.stdin.flush()
        while True:
            answer = self._read()
            if answer.get("id") == self.next_id:
                if "error" in answer:
                    raise AssertionError(f"{method}: {answer['error']}")
                return answer["result"]

    def _read(self):
        # One message; the pipe is unbuffered, so select sees every byte not yet read.
        while b"\0" not in self.buffer:
            ready, _, _ = select.select([self.proc.stdout], [], [], TIMEOUT)
            chunk = self.proc.stdout.read(65536) if ready else b""
            if not chunk:
                raise AssertionError("chromium did not answer within "
                                     f"{TIMEOUT} s (exit code {self.proc.poll()})")
            self.buffer += chunk
        message, _, self.buffer = self.buffer.partition(b"\0")
        return json.loads(message)

    def evaluate(self, expression):
        """The value of a JavaScript expression in the page (an exception fails)."""
        result = self.send("Runtime.evaluate", session=self.session, expression=expression,
                           returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in result:
            raise AssertionError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def open(self, url):
        self.send("Page.navigate", session=self.session, url=url)
        for _ in range(TIMEOUT * 10):
            if self.evaluate("document.readyState === 'complete' && "
                             "document.getElementById('n-value') !== null && "
                             "document.getElementById('n-value').textContent !== ''"):
                return
            self.evaluate("new Promise(r => setTimeout(r, 100))")
        raise AssertionError(f"{url} did not load within {TIMEOUT} s")

    def close(self):
        self.proc.stdin.close()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    if not HRBENCH.exists():
        pytest.fail("build/hrbench is not built: run `make build`")
    return write_explorer(tmp_path_factory.mktemp("explorer"), HRBENCH)


@pytest.fixture
def browser(tmp_path):
    b = Browser(tmp_path / "profile")
    yield b
    b.close()


def engine_counts(l, eps):
    """N and L of `hrbench run parallel l=L d=1 --eps E`, run here."""
    out = subprocess.run([HRBENCH, "run", "parallel", f"l={l:g}", "d=1", "--eps", f"{eps:g}",
                          "--count-only", "--json"], capture_output=True, text=True,
                         check=True).stdout
    record = json.loads(out)
    return record["nodes"], record["links"]


SHOWN = ("[document.getElementById('eps-value').textContent, "
         "document.getElementById('length-value').textContent, "
         "document.getElementById('n-value').textContent, "
         "document.getElementById('links-value').textContent]")


def move(browser, slider, index):
    """Set a slider as a user would leave it: its value, then the input event."""
    browser.evaluate(f"(() => {{ const s = document.getElementById('{slider}'); "
                     f"s.value = '{index}'; s.dispatchEvent(new Event('input')); }})()")


def shown(browser):
    eps, l, n, links = browser.evaluate(SHOWN)
    return float(eps), float(l), int(n), int(links)


def test_moving_the_sliders_shows_the_engines_counts(page, browser):
    browser.open(page.as_uri())
    # The page opens on eps = 0.25, l = 8 (the tutorial's first run).
    assert shown(browser) == (0.25, 8.0, *engine_counts(8, 0.25))
    for slider, index, (l, eps) in (("eps-slider", 3, (8, 0.125)),
                                    ("length-slider", 2, (32, 0.125)),
                                    ("eps-slider", 0, (32, 1.0)),
                                    ("length-slider", 3, (64, 1.0))):
        move(browser, slider, index)
        assert shown(browser) == (eps, float(l), *engine_counts(l, eps)), (slider, index)
    # Moving a slider also records the grid point in the address, to share it.
    assert browser.evaluate("location.hash") == "#eps=1&l=64"


def engine_link_at(l, eps, ti, tj, folder):
    """The rectangle and depth of the engine's link that covers (ti, tj), from its CSV."""
    path = folder / "links.csv"
    subprocess.run([HRBENCH, "links", "parallel", f"l={l:g}", "d=1", "--eps", f"{eps:g}",
                    "--out", path], check=True, capture_output=True)
    for row in csv.DictReader(path.open()):
        x0, x1, y0, y1 = (float(row[k]) for k in ("t0_i", "t1_i", "t0_j", "t1_j"))
        if row["root_i"] == "1":  # patch 0 across, patch 1 up
            x0, x1, y0, y1 = y0, y1, x0, x1
        if x0 <= ti < x1 and y0 <= tj < y1:
            return (x0, x1, y0, y1), int(row["depth_i"]) + int(row["depth_j"])
    raise AssertionError(f"no link covers ({ti}, {tj})")


def test_the_tiling_draws_the_engines_links(page, browser, tmp_path):
    l, eps = 16.0, 0.5
    browser.open(page.as_uri())
    move(browser, "eps-slider", EPS.index(eps))
    move(browser, "length-slider", LENGTHS.index(l))
    # Sample the canvas at the centres of the engine's links under three points: on the
    # anti-diagonal t_i + t_j = l, where the plates face each other, the deepest links;
    # in the corner (0, 0), plate ends far apart, shallow ones; between them, others.
    # Each pixel must have the page's colour of that link's depth.
    depths = set()
    for ti, tj in ((0.5 * l, 0.5 * l), (0.03 * l, 0.03 * l), (0.3 * l, 0.45 * l)):
        (x0, x1, y0, y1), depth = engine_link_at(l, eps, ti, tj, tmp_path)
        depths.add(depth)
        pixel, expected = browser.evaluate(
            "(() => { const c = document.getElementById('tiling'), g = c.getContext('2d');"
            f" const size = c.width - 50 - 56, x = 50 + {(x0 + x1) / 2 / l} * size,"
            f" y = 14 + size - {(y0 + y1) / 2 / l} * size;"
            " const colour = viridis((" + str(depth) + " - depthLow) / (depthHigh - depthLow));"
            " return [Array.from(g.getImageData(Math.floor(x), Math.floor(y), 1, 1).data),"
            " colour.match(/\\d+/g).map(Number)]; })()")
        assert all(abs(a - b) <= 2 for a, b in zip(pixel[:3], expected, strict=True)), \
            (ti, tj, depth, pixel, expected)
    assert len(depths) == 3, depths


def test_the_address_picks_the_grid_point(page, browser):
    browser.open(page.as_uri() + "#eps=0.0625&l=16")
    assert shown(browser) == (0.0625, 16.0, *engine_counts(16, 0.0625))
    assert browser.evaluate("document.getElementById('eps-slider').value") == "4"
