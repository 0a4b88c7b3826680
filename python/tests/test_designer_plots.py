"""The designer's plots drawn in the page (issue 35): every plot of x–y panels that
`/api/report` sends with its data is a uPlot chart per panel, drawn (not blank), titled as
the report's SVG and with its axes' units; a plot without panels (the linkage's drawing)
is the server's SVG image. On a panel over the crank angle the angle slider moves the
cursor (a dashed red line) to its angle, and the pointer over such a panel moves the
slider. A chart out of sight is drawn when it comes into sight (`data-stale` until then):
each is scrolled to before its pixels are read. The page's CSP forbids `eval` to the page's own scripts; Playwright's `evaluate`
runs through the DevTools protocol, which it does not govern, and reads the canvases'
pixels here."""

import json
import urllib.request

import pytest

from conftest import CHROMIUM, REPO, solved_after

playwright = pytest.importorskip("playwright.sync_api")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium")

SCENE = "linkage-sixbar-press.toml"

# Pixels of a canvas: how many are not white, and the columns of the angle cursor (#c00:
# pure red, unlike any series' colour) inside the plotting area.
PIXELS = """(canvas) => {
  const c = canvas.getContext("2d");
  const { data, width, height } = c.getImageData(0, 0, canvas.width, canvas.height);
  let inked = 0;
  const columns = new Map();
  for (let i = 0; i < data.length; i += 4) {
    const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
    if (r < 245 || g < 245 || b < 245) inked++;
    if (r > 150 && g < 20 && b < 20) {
      const x = (i / 4) % width;
      columns.set(x, (columns.get(x) || 0) + 1);
    }
  }
  // The cursor: the column with the most pure red, if it spans a good part of the height.
  let best = [-1, 0];
  for (const [x, n] of columns) if (n > best[1]) best = [x, n];
  return { inked, total: width * height, cursor: best[1] > height / 5 ? best[0] : null };
}"""


def report(server, name):
    """`/api/report?plots=data` of a shipped problem, as the page asks for it."""
    text = (REPO / "problems" / name).read_bytes()
    req = urllib.request.Request(
        server + f"api/report?plots=data&name={name}", data=text, method="POST"
    )
    return json.loads(urllib.request.urlopen(req, timeout=60).read())


def pixels(page, panel):
    """PIXELS of a panel's canvas, scrolled into sight and drawn (a chart out of sight waits,
    marked data-stale)."""
    page.locator(panel).scroll_into_view_if_needed()
    page.wait_for_selector(panel + ":not([data-stale])")
    return page.locator(panel + " canvas").evaluate(PIXELS)


def set_frame(page, k):
    """The angle slider at frame k (the page redraws the mechanism and the cursors)."""
    page.locator("#theta").fill(str(k))


def test_panel_plots_are_drawn_in_the_page(page, server):
    answer = report(server, SCENE)
    with_panels = [p for p in answer["plots"] if "panels" in p]
    without = [p for p in answer["plots"] if "panels" not in p]
    assert with_panels and without, [p["suffix"] for p in answer["plots"]]
    solved_after(page, lambda: page.select_option("#open", f"file:{SCENE}"))
    for p in with_panels:
        fig = page.locator(f"#plots figure[data-suffix='{p['suffix']}']")
        assert "svg" not in p
        assert fig.locator(".panel").count() == len(p["panels"])
        for i, panel in enumerate(p["panels"]):
            chart = fig.locator(".panel").nth(i)
            assert chart.locator(".u-title").inner_text() == panel["title"]
            for label in (panel["x_label"], panel["y_label"]):
                assert label.endswith(")") and "(" in label, label  # a unit
            px = pixels(page, f"#plots figure[data-suffix='{p['suffix']}'] .panel:nth-child({i + 1})")
            # Axes, grid, ticks and curves: far more than a blank canvas's nothing.
            assert px["inked"] > 0.03 * px["total"], (p["suffix"], i, px)
            box = chart.bounding_box()
            assert 260 <= box["width"] <= 720 and 200 <= box["height"] <= 640, box
    for p in without:
        img = page.locator(f"#plots figure[data-suffix='{p['suffix']}'] img")
        assert img.get_attribute("src").startswith("data:image/svg+xml;base64,")


def test_the_angle_slider_moves_the_cursor_and_the_pointer_moves_the_slider(page):
    solved_after(page, lambda: page.select_option("#open", f"file:{SCENE}"))
    # The shaking force |F| over the crank angle θ (deg): 0–360° on its x axis.
    panel = "#plots figure[data-suffix='fields'] .panel:nth-child(1)"
    xs = {}
    for k in (0, 18, 36, 18):  # 72 frames a turn: 0°, 90°, 180°, and back to 90°
        set_frame(page, k)
        xs.setdefault(k, []).append(pixels(page, panel)["cursor"])
    x0, x90, x180 = xs[0][0], xs[18][0], xs[36][0]
    assert None not in (x0, x90, x180), xs
    assert x0 < x90 < x180 and abs((x180 - x0) - 2 * (x90 - x0)) <= 2, xs
    assert xs[18][0] == xs[18][1], "back at 90°, the cursor is where it was"
    # The pointer at three quarters of the plotting area's width: θ = 270°, frame 54.
    over = page.locator(panel + " .u-over")
    over.scroll_into_view_if_needed()
    box = over.bounding_box()
    page.mouse.move(box["x"] + 0.75 * box["width"], box["y"] + 0.5 * box["height"])
    playwright.expect(page.locator("#theta")).to_have_value("54")
    assert page.inner_text("#theta-label") == "θ = 270°"
    page.mouse.move(0, 0)
