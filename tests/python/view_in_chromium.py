"""`rfidray view` in headless Chromium (Debian's chromium, software WebGL): the paper warehouse page loads with
no script errors, draws something (pixel check of a screenshot), lists the expected number of paths — the sum
over its links of the paths the Python API (identical to `rfidray link --json`, test_channel.py) finds — and
hovering over a path shows its kind, length and coefficient. Without WebGL the page says so and still lists every path.
Exit 77 (ctest: skipped) when Chromium or libjs-three is not installed."""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

SOURCE_DIR = pathlib.Path(os.environ.get("RFIDRAY_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = pathlib.Path(os.environ.get("RFIDRAY_BINARY", SOURCE_DIR / "build" / "rfidray"))


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def browse(browser, html, work, *extra, fragment="", webgl=True):
    """Runs headless Chromium on a file (+ #fragment) with a fresh profile; returns its stdout. webgl=False: without
    --enable-unsafe-swiftshader (headless Chromium's only WebGL here) and with WebGL turned off (--disable-3d-apis,
    so the result does not depend on whether this Chromium version falls back to software WebGL by itself)."""
    profile = tempfile.mkdtemp(prefix="profile-", dir=work)
    gl = ["--enable-unsafe-swiftshader"] if webgl else ["--disable-3d-apis"]
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", *gl,
           "--disable-dev-shm-usage", "--disable-quic", "--no-first-run", "--disable-background-networking",
           "--disable-component-update", "--disable-sync",
           "--hide-scrollbars", f"--user-data-dir={profile}", "--window-size=1280,800",
           # let the page's script run before the DOM is dumped or the screenshot taken
           "--virtual-time-budget=5000", *extra, html.as_uri() + fragment]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    if proc.returncode != 0:
        raise SystemExit(f"chromium exited {proc.returncode}:\n{proc.stderr[-3000:]}")
    return proc.stdout


def body_attributes(dom):
    m = re.search(r"<body([^>]*)>", dom)
    assert m, "no <body> in the dumped DOM"
    return dict(re.findall(r'data-([a-z]+)="([^"]*)"', m.group(1)))


def expected_path_count():
    """The paper scenario at t = 0 as `rfidray view` shows it: both antennas (mobile on the robot at (−1, −10),
    1.68 m high; fixed at (3.5, −4, 2)), all ten tags, single-bounce (the scenario's channel is ideal, so view
    traces single-bounce). Every antenna and tag there is isotropic with linear polarization along z, so the
    paths are those of bare positions."""
    import rfidray
    channel = rfidray.Channel(rfidray.Scene.load(SOURCE_DIR / "scenes" / "paper_warehouse.obj"), "single-bounce")
    antennas = [[-1.0, -10.0, 1.68], [3.5, -4.0, 2.0]]
    tags = [[2.90, 0.57, 2.05], [2.90, -1.24, 2.05], [2.90, -3.03, 2.05], [2.90, -4.82, 2.05], [2.90, -6.75, 2.05],
            [2.90, -8.66, 2.05], [-4.85, -7.70, 1.85], [-4.85, -3.03, 1.85], [-4.85, 1.44, 1.85], [-4.85, 5.95, 1.85]]
    return sum(len(channel.paths(a, t, 865.7e6)) for a in antennas for t in tags)


def main():
    browser = chromium()
    if browser is None:
        print("chromium not installed: skipped (apt-get install chromium)")
        return 77
    if not pathlib.Path("/usr/share/javascript/three/three.min.js").exists():
        print("libjs-three not installed (rfidray view inlines it): skipped (apt-get install libjs-three)")
        return 77
    work = pathlib.Path(tempfile.mkdtemp(prefix="rfidray-view-"))
    try:
        html = work / "view.html"
        proc = subprocess.run([str(BINARY), "view", str(SOURCE_DIR / "scenes" / "paper_warehouse.yaml"), "-o", str(html)],
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        m = re.search(r"(\d+) links, (\d+) paths", proc.stdout)
        assert m, proc.stdout
        links, paths = int(m.group(1)), int(m.group(2))
        expected = expected_path_count()
        print(f"rfidray view: {links} links, {paths} paths; Python API: {expected} paths")
        assert links == 20 and paths == expected, (links, paths, expected)
        page = html.read_text()
        assert "http://" not in page.split("<script>", 1)[0] and "<script src" not in page, "the page must be self-contained"

        dom = browse(browser, html, work, "--dump-dom")
        attrs = body_attributes(dom)
        print("body:", attrs)
        assert attrs.get("status") == "ready", attrs
        assert attrs.get("errors") == "0", attrs
        assert int(attrs.get("paths", -1)) == expected, attrs
        rows = len(re.findall(r'<tr class="path"', dom))
        assert rows == expected, (rows, expected)

        # No WebGL: the view says why it is empty, the side panel is still complete, and nothing is an error.
        dom = browse(browser, html, work, "--dump-dom", webgl=False)
        attrs = body_attributes(dom)
        print("body without WebGL:", attrs)
        assert attrs.get("status") == "no-webgl" and attrs.get("webgl") == "no", attrs
        assert attrs.get("errors") == "0", attrs
        note = re.search(r'<div id="nowebgl">([^<]*)</div>', dom)
        assert note and "WebGL is not available" in note.group(1), note and note.group(0)
        assert len(re.findall(r'<tr class="path"', dom)) == expected
        assert int(attrs.get("paths", -1)) == expected, attrs
        assert "triangles)" in dom  # the materials legend

        # The error counter itself: a console.error and an uncaught exception planted in a copy must show.
        planted = work / "planted.html"
        planted.write_text(page.replace("</body>", "<script>console.error('planted')</script>"
                                                   "<script>no_such_function()</script></body>"))
        attrs = body_attributes(browse(browser, planted, work, "--dump-dom"))
        assert attrs.get("status") == "error" and attrs.get("errors") == "2", attrs

        # Hover: the page moves the mouse over path 0 (#hover=0); the tooltip must describe a path.
        dom = browse(browser, html, work, "--dump-dom", fragment="#hover=0")
        tip = re.search(r'<div id="tip"[^>]*>([^<]*)</div>', dom)
        assert tip and "display: block" in tip.group(0), tip and tip.group(0)
        print("tooltip:", tip.group(1).replace("\n", " | "))
        assert re.match(r"path \d+: (los|blocked|reflection)", tip.group(1)), tip.group(1)
        assert "length " in tip.group(1) and "coefficient " in tip.group(1), tip.group(1)
        assert body_attributes(dom).get("errors") == "0"

        shot = work / "shot.png"
        browse(browser, html, work, f"--screenshot={shot}")
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.image
        img = matplotlib.image.imread(str(shot))[..., :3]
        # The 3-D view is the left part of the page (the side panel is 440 px wide on the right).
        view = img[:, : img.shape[1] - 460]
        background = np.array([0x1D, 0x21, 0x27]) / 255.0
        drawn = np.abs(view - background).max(axis=2) > 0.08
        colours = len(np.unique((view * 255).astype(np.uint8).reshape(-1, 3), axis=0))
        print(f"screenshot {img.shape[1]}x{img.shape[0]}: {drawn.mean():.1%} of the view drawn, {colours} colours")
        assert drawn.mean() > 0.05, "the canvas is (nearly) blank"
        assert colours > 50, "the canvas has almost no colours"
        print("ok")
        return 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
