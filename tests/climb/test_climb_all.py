"""evaluate's climbs: written as `ftfof climb` writes one, and resumed after an interruption."""

from __future__ import annotations

import json
import re
from dataclasses import replace

import pytest

import ftfof.pipeline.climb as climbs
from tests.climb.helpers import spec_of

pytestmark = pytest.mark.integration


def test_an_interrupted_set_of_climbs_resumes_from_those_written(
    params, tmp_path, monkeypatch, capsys
):
    params = params.model_copy(update={"climb": params.climb.model_copy(update={"steps": 1})})
    specs = {}
    for name in ("polynomial", "cycloidal"):
        spec = spec_of(params, name)
        specs[name] = replace(spec, climb=params.climb)
    out = tmp_path / "climb"
    first = climbs.climb_all(params, specs, out, workers=2)
    assert set(first) == set(specs) and all(d["summary"]["steps_done"] == 1 for d in first.values())
    said = capsys.readouterr().err
    for name in specs:  # one line per climb as it ends, with its outcome
        assert re.search(rf"^  {name}: (ok|FELL: .+); 1 of 1 steps in [0-9.]+ s$", said, re.M)
    # as a run stopped after the polynomial's climb leaves it: incomplete, one climb written
    manifest = json.loads((out / "manifest.json").read_text())
    (out / "manifest.json").write_text(json.dumps({**manifest, "complete": False}))
    for path in out.glob("cycloidal*"):
        path.unlink()
    written = []
    real = climbs.write_climb
    monkeypatch.setattr(
        climbs,
        "write_climb",
        lambda out_, d, title: written.append(out_.name) or real(out_, d, title),
    )
    second = climbs.climb_all(params, specs, out, workers=2)
    assert written == ["cycloidal"]  # the polynomial's climb was read back, not run again
    assert second == first  # the same climbs again, bit for bit (no wall time in them)
