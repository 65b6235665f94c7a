"""The estimate of a whole `dvc repro` that acquire prints from its first samples
(:mod:`ftfof.study.duration` computes it)."""

from __future__ import annotations

from ftfof.pipeline.estimate import FirstSamples


def test_the_estimate_is_printed_once_after_ten_seconds_or_at_the_end(params, capsys):
    heard = FirstSamples(params, todo=1004)
    heard(16, 4.0)  # the first batches back: the pace counts from here
    heard(24, 6.1)
    assert capsys.readouterr().err == ""  # too early to tell
    heard(40, 10.3)  # 24 samples in 6.3 s since the first batches
    said = capsys.readouterr().err
    assert said.count("\n") == 1  # one line, also in a log
    assert said.startswith("estimate: 0.26 s per sample here (0.29 where `dvc repro` took 27 min)")
    assert "the whole run should take about 25 min on these params" in said
    heard(80, 21.0)
    assert capsys.readouterr().err == ""
    short = FirstSamples(params, todo=16)
    short(16, 6.0)  # all back in one batch, before ten seconds: the pace since the start
    assert "0.38 s per sample here" in capsys.readouterr().err
