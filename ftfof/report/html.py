"""A self-contained HTML report: every figure inlined as a data URI, no external resource."""

from __future__ import annotations

import base64
import io
from importlib import resources

import jinja2
from matplotlib.figure import Figure

TEMPLATE = "evaluate.html.j2"


def png_data_uri(png: bytes) -> str:
    if not png.startswith(b"\x89PNG\r\n\x1a\n"):
        raise ValueError("not a PNG image")
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def figure_data_uri(fig: Figure, dpi: int = 100) -> str:
    """The figure as an inline PNG; the figure is closed (pyplot keeps it alive until then)."""
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=dpi)
    finally:
        plt.close(fig)
    return png_data_uri(buffer.getvalue())


def render(context: dict, template: str = TEMPLATE) -> str:
    """Fill the packaged template; values are HTML-escaped, images must be data URIs."""
    source = resources.files("ftfof.report").joinpath("templates", template).read_text("utf-8")
    env = jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined)
    env.filters["num"] = lambda v, digits=3: "–" if v is None or v != v else f"{v:.{digits}f}"
    env.filters["pct"] = lambda v: "–" if v != v else f"{v:+.1f} %"
    return env.from_string(source).render(**context)
