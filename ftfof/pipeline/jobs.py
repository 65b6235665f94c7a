"""A resumable simulation job on disk: manifest, pending parts, compaction, failure policy and
statistics.

Results are written as they complete, one atomic Parquet part per finished batch under
``<out>/pending/``; a killed run re-run resumes from them (a manifest fingerprint of the inputs,
params and code versions guards against mixing runs). When every sample is in, the parts are
compacted into one canonical ``samples.parquet`` sorted by key, so the output does not depend on
completion order. Shared by `acquire` and `evaluate` (which re-simulates the optimum and baselines).
"""

from __future__ import annotations

import json
import shutil
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ftfof.config import Params
from ftfof.data.acquisition import (
    ACQUISITION,
    PENDING,
    canonical_rows,
    check_complete,
    check_failures,
    sampled_specs,
    summarize,
    to_table,
)
from ftfof.data.schema import TRAJECTORIES
from ftfof.digests import bytes_sha256, file_sha256, json_sha256, tree_sha256
from ftfof.files import atomic_path, read_table, write_json, write_parquet
from ftfof.pipeline import interrupt
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.console import progress
from ftfof.robot import RobotContext
from ftfof.sim import pool
from ftfof.sim.simulate import SampleResult
from ftfof.sim.spec import SampleSpec, baseline_specs
from ftfof.version import __version__

FINAL = "samples.parquet"
PENDING_DIR = "pending"
MANIFEST = "manifest.json"


@dataclass
class Acquisition:
    params: Params
    ctx: RobotContext
    out: Path
    specs: list[SampleSpec]
    controls: dict[str, np.ndarray]
    key: str

    @classmethod
    def prepare(
        cls, params: Params, trajectories: Path, out: Path, limit: int | None = None
    ) -> Acquisition:
        """The `acquire` job: every sampled trajectory (the first ``limit``) and the baselines."""
        ctx = context_of(params)
        table = read_table(trajectories, TRAJECTORIES, "trajectory table")
        on = bench(params, ctx)
        specs, controls = sampled_specs(on, table, ctx.name, str(trajectories), limit)
        if params.acquire.baselines:
            specs += baseline_specs(on, baseline_trajectories(params, ctx))
        inputs = {"trajectories": file_sha256(trajectories), "limit": limit}
        return cls.start(params, ctx, out, specs, controls, inputs)

    @classmethod
    def start(
        cls,
        params: Params,
        ctx: RobotContext,
        out: Path,
        specs: list[SampleSpec],
        controls: dict[str, np.ndarray],
        inputs: dict[str, object],
    ) -> Acquisition:
        """A job over ``specs``, resumable while the physics settings and ``inputs`` hold."""
        key = job_key(params, ctx, inputs)
        job = cls(params, ctx, out, specs, controls, key)
        job._open()
        return job

    @staticmethod
    def finished(
        params: Params, ctx: RobotContext, out: Path, inputs: dict[str, object]
    ) -> pa.Table | None:
        """The compacted samples of a finished job of the same inputs under ``out``, if any.

        For callers that keep a finished job's results (``start`` would simulate them again).
        """
        manifest, final = out / MANIFEST, out / FINAL
        if not (manifest.exists() and final.exists()):
            return None
        if json.loads(manifest.read_text()).get("fingerprint") != job_key(params, ctx, inputs):
            return None
        return read_table(final, ACQUISITION, "simulations")

    # --- the pending area -------------------------------------------------------------------

    @property
    def pending(self) -> Path:
        return self.out / PENDING_DIR

    def _parts(self) -> list[Path]:
        return sorted(self.pending.glob("part-*.parquet"))

    def _open(self) -> None:
        """Resume only an interrupted run of the same inputs; anything else starts afresh.

        A finished run leaves no pending parts, so a re-run (``dvc repro --force``) recomputes.
        """
        manifest = self.out / MANIFEST
        saved = json.loads(manifest.read_text()) if manifest.exists() else {}
        code = source()
        if (saved.get("fingerprint"), saved.get("source")) != (self.key, code) or not self._parts():
            if self.out.exists():
                shutil.rmtree(self.out)
            self.pending.mkdir(parents=True)
            write_json(manifest, self._manifest() | {"source": code})

    def _manifest(self) -> dict[str, object]:
        """The finished job's manifest: its fingerprint and versions, not the source digest that
        guards its pending parts (so equal results leave equal outputs after a code change)."""
        return {"fingerprint": self.key, "versions": versions()}

    def done_keys(self) -> set[str]:
        keys: set[str] = set()
        for part in self._parts():
            keys.update(pq.read_table(part, columns=["key"]).column("key").to_pylist())
        return keys

    def remaining(self) -> list[SampleSpec]:
        done = self.done_keys()
        return [s for s in self.specs if s.key not in done]

    def simulate(
        self,
        todo: Sequence[SampleSpec],
        workers: int,
        address: str | None,
        label: str,
        on_batch: Callable[[int, float], None] | None = None,
    ) -> float:
        """Run ``todo`` with a progress bar (already-done samples count as complete), persisting
        each finished batch; wall time. ``on_batch`` hears the samples finished and the seconds
        taken after each batch; a stop request (:mod:`ftfof.pipeline.interrupt`) ends the run
        after the batch just written."""
        started = time.perf_counter()
        with progress(label) as bar:
            total, done = len(self.specs), len(self.specs) - len(todo)
            task = bar.add_task(label, total=total, completed=done, resumed=done, info="")
            finished = 0
            with interrupt.deferred():
                for results in pool.run(todo, workers, self.params.acquire.batch, address):
                    self._write_part(results)
                    interrupt.check()
                    finished += len(results)
                    elapsed = time.perf_counter() - started
                    rate = finished / max(elapsed, 1e-9)
                    bar.update(task, advance=len(results), info=f"{rate:.2f} samples/s")
                    if on_batch is not None:
                        on_batch(finished, elapsed)
        return time.perf_counter() - started

    def _write_part(self, results: Sequence[SampleResult]) -> None:
        T3 = self.ctx.robot.timing.T3
        table = to_table(results, self.ctx.name, self.params.surface, self.controls, T3)
        name = bytes_sha256("|".join(sorted(r.key for r in results)).encode(), 16)
        write_parquet(self.pending / f"part-{name}.parquet", table)

    # --- completion ---------------------------------------------------------------------------

    def collect(self) -> pa.Table:
        parts = [pq.read_table(p) for p in self._parts()]
        table = pa.concat_tables(parts).cast(PENDING) if parts else PENDING.empty_table()
        return canonical_rows(table, {s.key for s in self.specs})

    def finish(self, wall: float, simulated: int, timing: Path | None = None) -> dict[str, object]:
        table = self.collect()
        check_complete(table, len(self.specs), str(self.out))
        clearance = self.ctx.robot.foot.swing_clearance
        summary = summarize(table, self.ctx.rules.film, clearance, wall, simulated)
        check_failures(table, self.params.acquire.max_failure_rate)
        if timing is not None:
            with atomic_path(timing) as tmp:
                table.select(["key", "status", "wall_time"]).to_pandas().to_csv(tmp, index=False)
        write_parquet(self.out / FINAL, table.drop_columns(["wall_time"]).cast(ACQUISITION))
        shutil.rmtree(self.pending)
        write_json(self.out / MANIFEST, self._manifest())
        return summary


def job_key(params: Params, ctx: RobotContext, inputs: dict[str, object]) -> str:
    """The fingerprint of a job: the physics settings, the seed, the code and ``inputs``."""
    return json_sha256(
        {
            "robot": ctx.robot.model_dump(),
            "surface": params.selected_surface.model_dump(),
            "platform": params.platform.model_dump(),
            "acquire": params.acquire.model_dump(exclude={"workers", "scheduler", "batch"}),
            "baselines": params.baselines.model_dump(),
            "seed": params.base.seed,
            "versions": versions(),
            **inputs,
        }
    )


def versions() -> dict[str, str]:
    """The code that made a job's numbers: part of its fingerprint and of the dataset's metadata."""
    import exudyn

    return {"ftfof": __version__, "exudyn": exudyn.__version__}


def source() -> str:
    """A digest of ftfof's Python source: an interrupted job resumes only under the code that
    began it (the version string does not change with every edit)."""
    return tree_sha256(Path(__file__).resolve().parents[1], "*.py")  # the ftfof package


def open_resumable(out: Path, identity: dict[str, object]) -> str:
    """The fingerprint of ``identity`` and the code versions. ``out`` is kept only to resume an
    interrupted run of the same fingerprint and source; otherwise it is emptied and marked
    incomplete."""
    key = json_sha256({**identity, "versions": versions()})
    manifest = out / MANIFEST
    saved = json.loads(manifest.read_text()) if manifest.exists() else {}
    code = source()
    same = (saved.get("fingerprint"), saved.get("source")) == (key, code)
    if not same or saved.get("complete", True):
        if out.exists():
            shutil.rmtree(out)
        write_json(manifest, {"fingerprint": key, "complete": False, "source": code})
    return key


def close_resumable(out: Path, key: str) -> None:
    """Mark the run of ``key`` in ``out`` complete: the next run starts afresh."""
    write_json(out / MANIFEST, {"fingerprint": key, "complete": True})
