"""The report is self-contained: escaped values, inline PNGs only."""

import io

import matplotlib.pyplot as plt
import pytest

from ftfof.report.html import figure_data_uri, png_data_uri


def test_figure_becomes_a_decodable_png_data_uri():
    import base64

    from PIL import Image

    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    uri = figure_data_uri(fig)
    assert uri.startswith("data:image/png;base64,")
    image = Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1])))
    assert image.format == "PNG" and image.size[0] > 100


def test_non_png_is_refused():
    with pytest.raises(ValueError, match="PNG"):
        png_data_uri(b"GIF89a....")
