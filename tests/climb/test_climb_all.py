"""evaluate's climbs: written as `ftfof climb` writes one, and resumed after an interruption."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

import ftfof.pipeline.climb as climbs
from tests.climb.helpers import spec_of

pytestmark = pytest.mark.integration


def test_an_interrupted_set_of_climbs_resumes_from_those_written(params, tmp_path, monkeypatch):
    params = params.model_copy(update={"climb": params.climb.model_copy(update={"steps": 1})})
    specs = {}
    for name in ("polynomial", "cycloidal"):
        spec = spec_of(params, name)
        specs[name] = replace(spec, climb=params.climb)
    out = tmp_path / "climb"
    first = climbs.climb_all(params, specs, out, workers=2)
    assert set(first) == set(specs) and all(d["summary"]["steps_done"] == 1 for d in first.values())
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
    for name in specs:  # the same climb again, bit for bit, but for its wall time
        assert {**second[name], "wall_time_s": 0} == {**first[name], "wall_time_s": 0}
