"""Stage `evaluate`'s report rendered in headless Chromium (end-to-end, minutes)."""

import re
import shutil
import subprocess

import pytest
from PIL import Image

pytestmark = pytest.mark.slow


def test_report_renders_in_headless_chromium(evaluated, tmp_path):
    work, *_ = evaluated
    shot = tmp_path / "report.png"
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    subprocess.run(
        [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
            "--no-first-run", "--disable-background-networking", "--disable-component-update",
            "--disable-sync", f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,3000",
            f"--screenshot={shot}", (work / "report.html").as_uri(),
        ],
        check=True, capture_output=True, timeout=120,
    )  # fmt: skip
    image = Image.open(shot)
    assert image.size == (1280, 3000)
    # a rendered page, not a blank one: the table and figures put many colours on it
    assert len(image.convert("RGB").getcolors(maxcolors=1 << 20) or []) > 50


PROBE = """<script>
window.addEventListener("load", () => {
  const cut = t => t.scrollWidth > t.parentElement.clientWidth;
  const tables = [...document.querySelectorAll("h2 ~ div.scroll > table")];
  const first = tables.filter(t => t.closest("div").previousElementSibling.tagName === "H3");
  document.body.dataset.tableOneTables = String(first.length);
  document.body.dataset.tableOverflow = String(first.some(cut));
  document.body.dataset.cutTables = tables.filter(cut).map(t => t.rows[0].cells.length).join(",");
  document.body.dataset.pageOverflow = String(
    document.documentElement.scrollWidth > window.innerWidth);
});
</script>"""


def test_the_first_screen_fits_1280_px_and_says_what_to_run(evaluated, tmp_path):
    """At 1280 px the three Table I tables (the paper's figures; the foot and the film, 13
    columns; the landed pad) and every other table need no horizontal scroll, and the run-this
    box holds the chosen control points and the export command (laid out by headless
    Chromium)."""
    work, *_ = evaluated
    html = (work / "report.html").read_text()
    probe = tmp_path / "probe.html"
    probe.write_text(html.replace("</body>", PROBE + "</body>"))
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    dom = subprocess.run(
        [
            chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,2000",
            "--virtual-time-budget=3000", "--dump-dom", probe.as_uri(),
        ],
        check=True, capture_output=True, text=True, timeout=120,
    ).stdout  # fmt: skip
    body = re.search(r"<body[^>]*>", dom).group(0)
    assert 'data-table-one-tables="3"' in body and 'data-table-overflow="false"' in body
    assert 'data-cut-tables=""' in body and 'data-page-overflow="false"' in body
    box = dom[dom.index('class="run-this"') : dom.index("Table I analogue")]
    assert all(f"<td>P{n}</td>" in box for n in (3, 4, 5, 10, 11, 12))
    assert "ftfof export --format ros-yaml" in box and "RHS visited" in box
