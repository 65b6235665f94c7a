"""Stage `evaluate`'s report rendered in headless Chromium (end-to-end, minutes)."""

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
