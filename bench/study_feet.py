"""The grip foot and the plate foot side by side on MST-M3F / acrylic (issue 51, "Study").

    python bench/study_feet.py [--samples 200] [--workers 2] [--out FILE.json]

Why: issue 51's decision record compares the feet on the same measurements, made here by the
library: Table I's six rows with the cost per sample (one process), the spread over the first N
sampled trajectories (data/trajectories.parquet, or `ftfof sample` re-run and checked against
dvc.lock), the climbs and the identify round trip, on temporary params files and folders. The
grip foot has its old values and acrylic calibration (GRIP_FOOT, GRIP_ACRYLIC).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import yaml

from ftfof.config import Params
from ftfof.data.acquisition import sampled_specs
from ftfof.data.targets import full_rate
from ftfof.errors import DataError
from ftfof.evaluate.pick import Source
from ftfof.pipeline.bench import baseline_trajectories, bench, context_of
from ftfof.pipeline.params_file import load_params
from ftfof.pipeline.trajectory import trajectory_of
from ftfof.sim.foot import grip_of
from ftfof.sim.pad import film_grid
from ftfof.sim.pool import run_all
from ftfof.sim.records import SampleResult
from ftfof.sim.simulate import simulate
from ftfof.sim.spec import SampleSpec, baseline_specs

SURFACE = "acrylic"
# the grip foot's values and its acrylic calibration before the plate became the default
GRIP_FOOT = {"model": "grip", "backing": None, "ankle_range": None, "ankle_stiffness": 0.5}
GRIP_FOOT |= {"ankle_damping": 0.005, "inertia": 1.0e-5}
GRIP_ACRYLIC = {"strength": 32711.3, "fracture_energy": 76.8, "preload_pressure": 13035.8}
BASELINES = ("polynomial", "cycloidal", "random_bezier", "eps_bezier")
FIGURES = ("peak_detachment", "peak_pull", "peak_pre_pressure", "jitter", "peak_body_acc")
FIGURES += ("min_bend_radius", "bonds_at_end")
SPREAD = ("peak_detachment", "peak_pull")
FEET = ("grip", "plate")
LEGS = ("FL", "FR", "HL", "HR")
TRAJECTORIES = Path("data/trajectories.parquet")


def feet(params: Params) -> dict[str, Params]:
    """The plate (params.yaml as it is) and the grip foot with its old values and calibration."""
    if params.surface != SURFACE:
        raise SystemExit(f"params.yaml selects surface {params.surface!r}; the study is on acrylic")
    d = params.model_dump()
    d["robots"][d["robot"]]["platform"]["foot"].update(GRIP_FOOT)
    d["surfaces"][SURFACE].update(GRIP_ACRYLIC)
    return {"grip": type(params).model_validate(d), "plate": params}


def node_count(spec: SampleSpec) -> int:
    """Film nodes of the pad, so that a re-bond reads as 'of N'."""
    m, pad, solver = spec.mechanics, spec.pad_length, spec.solver
    grip = grip_of(m.foot, pad)
    return int(film_grid(pad, solver.nodes, m.film.width, grip, solver.edge_element).x_ref.size)


def figures(result: SampleResult, T3: float) -> dict[str, Any]:
    """Table I's figures of one sample; ``jitter`` as evaluate takes it (ftfof.evaluate.runs)."""
    if not result.ok:
        return {"status": "failed", "error": result.error[:160]}
    out: dict[str, Any] = {k: float(result.scalars.get(k, math.nan)) for k in FIGURES}
    out["jitter"] = float(np.max(full_rate(result.channels, T3)["body_acc"]))
    return {"status": "ok", **out}


def optimum_X(params: Params, optimize: Path) -> tuple[np.ndarray | None, str]:
    """The committed optimum's control points, read as `ftfof export` reads them (or why not)."""
    try:
        _, _, X, extra = trajectory_of(params, context_of(params), Source(), optimize)
    except DataError as err:
        return None, str(err)
    return np.asarray(X, float), f"{optimize} row {extra.get('front_row')}"


def table_specs(params: Params, X_opt: np.ndarray | None) -> list[SampleSpec]:
    """Table I's rows on this foot, as evaluate builds them."""
    ctx = context_of(params)
    on = bench(params, ctx)
    specs = baseline_specs(on, baseline_trajectories(params, ctx), BASELINES)
    specs.append(on.bezier("baseline:paper_optimum", 0, np.array(ctx.robot.published_optimum)))
    return specs + ([on.bezier("optimum", 0, X_opt)] if X_opt is not None else [])


def table_and_cost(
    foot: dict[str, Params], X_opt: np.ndarray | None, repeats: int
) -> dict[str, dict[str, Any]]:
    """Table I's rows simulated in this process, one after another: their figures and their wall
    time, the median of ``repeats`` runs after a warm-up, the feet taking turns row by row so that
    a machine's changing load weighs on both alike."""
    specs = {name: table_specs(params, X_opt) for name, params in foot.items()}
    for name in foot:
        simulate(specs[name][0])  # warm-up: kernels and symbolic functions
    out: dict[str, dict[str, Any]] = {name: {"rows": {}} for name in foot}
    for k in range(len(specs["plate"])):
        for name, params in foot.items():
            spec, walls = specs[name][k], []
            for _ in range(repeats):
                t0 = time.perf_counter()
                result = simulate(spec)
                walls.append(time.perf_counter() - t0)
            row = {**figures(result, params.selected_robot.timing.T3), "nodes": node_count(spec)}
            out[name]["rows"][spec.source.removeprefix("baseline:")] = {
                **row,
                "wall_s": float(np.median(walls)),
                "walls": walls,
            }
    for o in out.values():
        o["cost_s"] = float(np.mean([r["wall_s"] for r in o["rows"].values()]))
    return out


def trajectories_table(tmp: Path) -> tuple[Path, str]:
    """The committed sampled trajectories: data/trajectories.parquet, or `ftfof sample` re-run
    into ``tmp`` and checked against dvc.lock's md5 (the DVC cache may not be checked out)."""
    if TRAJECTORIES.exists():
        return TRAJECTORIES, str(TRAJECTORIES)
    out = tmp / "trajectories.parquet"
    cmd = ["ftfof", "sample", "--out", str(out), "--metrics", str(tmp / "sample.json")]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    md5 = hashlib.md5(out.read_bytes()).hexdigest()
    verdict = "matches" if md5 in Path("dvc.lock").read_text() else "DIFFERS from"
    return out, f"re-made by `ftfof sample` (md5 {md5}, {verdict} dvc.lock's)"


def spread(params: Params, table: Path, n: int, workers: int) -> dict[str, Any]:
    """Quantiles of peak detachment and pull over the first ``n`` sampled trajectories."""
    ctx = context_of(params)
    specs, _ = sampled_specs(bench(params, ctx), pq.read_table(table), ctx.name, str(table), n)
    t0 = time.perf_counter()
    rows = [figures(r, ctx.robot.timing.T3) for r in run_all(specs, workers)]
    ok = [r for r in rows if r["status"] == "ok"]
    out: dict[str, Any] = {"n": len(specs), "failed": len(specs) - len(ok)}
    out["wall_s"] = time.perf_counter() - t0
    out["errors"] = sorted({r["error"][:80] for r in rows if r["status"] != "ok"})[:5]
    for k in SPREAD:
        v = np.array([r[k] for r in ok], float)
        q = {f"q{p}": float(np.quantile(v, p / 100)) for p in (10, 50, 90)}
        out[k] = {**q, "max": float(v.max()), "spread": (q["q90"] - q["q10"]) / q["q50"]}
    ok_ids = [
        (r["peak_pull"], s.sample_id) for r, s in zip(rows, specs, strict=True) if "error" not in r
    ]
    out["largest_pulls"] = [{"sample_id": i, "peak_pull": f} for f, i in sorted(ok_ids)[-5:]]
    return out


def params_file(params: Params, folder: Path) -> Path:
    """``params`` as a YAML file for the command line (checked to load back equal)."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "params.yaml"
    path.write_text(yaml.safe_dump(params.model_dump(mode="json"), sort_keys=False))
    if load_params(path) != params:
        raise SystemExit(f"{path} does not load back as the params it was written from")
    return path


def command(args: list[str]) -> tuple[int, str]:
    """Run an ftfof command: its exit status and the tail of its output."""
    done = subprocess.run(["ftfof", *args], capture_output=True, text=True)
    return done.returncode, (done.stdout + done.stderr)[-600:]


def climb(params_path: Path, name: str, points: list[float] | None, out: Path) -> dict[str, Any]:
    """One `ftfof climb`; one the rules refuse is climbed again with --allow-infeasible (and the
    result says so)."""
    what = ["--baseline", name] if points is None else ["--points", ",".join(map(str, points))]
    base = ["climb", "-p", str(params_path), *what, "--out-dir", str(out)]
    t0 = time.perf_counter()
    rc, tail = command(base)
    allowed = rc != 0 and not list(out.glob("*.json"))
    if allowed:
        rc, tail = command([*base, "--allow-infeasible"])
    docs = [p for p in out.glob("*.json") if p.name != "manifest.json" and p.suffixes == [".json"]]
    if not docs:
        return {"error": f"exit {rc}: {tail}", "allow_infeasible": allowed}
    doc = json.loads(docs[0].read_text())
    figs = read_climb(doc, pd.read_parquet(docs[0].with_suffix(".parquet")), params_path)
    figs["wall_s"] = time.perf_counter() - t0  # the record holds no wall time
    return {"allow_infeasible": allowed, "refused": tail if allowed else "", **figs}


def read_climb(doc: dict[str, Any], df: pd.DataFrame, params_path: Path) -> dict[str, Any]:
    """A climb's figures: steps, the fall, the worst joint, each landing's re-bond."""
    s, params = doc["summary"], load_params(params_path)
    robot = params.selected_robot
    limits = np.array(robot.climber.torque_limits, float)
    torques = [c for c in df if c.startswith("torque_")]
    ratio = {c[7:]: float(df[c].abs().max() / limits[int(c[-1]) - 1]) for c in torques}
    joint = max(ratio, key=ratio.__getitem__) if ratio else ""
    landed = landing_bonds(df, robot.timing.T3 + params.platform.protocol.landing_hold)
    done = [st for st in doc["steps"] if st["complete"]]
    keys = ("steps_done", "fell", "torque_ratio", "peak_pull", "jitter", "min_bend_radius")
    return {
        **{k: s.get(k) for k in keys},
        "fall": doc.get("fall", ""),
        "error": doc.get("error", ""),
        "torque_joint": joint,
        # the worst complete step's servo verdict ("" within the limits)
        "torque_worst": max(done, key=lambda st: st["torque_ratio"])["torque"] if done else "",
        "least_rebond": min(landed) if landed else None,
        "rebonds": landed,
        "slip_distance": s.get("slip_distance"),
    }


def landing_bonds(df: pd.DataFrame, hold_end: float) -> list[int]:
    """The landed pad's intact bonds at the end of each landing hold (``hold_end`` after the
    step's lift-off), over the steps whose landing hold ran to its end."""
    t, swing = df["t"].to_numpy(), df["swing"].to_numpy()
    out = []
    for i in np.flatnonzero(np.diff(swing, prepend=-1) != 0):
        if swing[i] < 0:
            continue
        at = np.flatnonzero((t >= t[i]) & (t <= t[i] + hold_end) & (swing == swing[i]))
        if at.size and t[at[-1]] >= t[i] + hold_end - 0.01:
            out.append(int(df[f"bonds_{LEGS[swing[i]]}"].to_numpy()[at[-1]]))
    return out


def identify(params_path: Path, out: Path) -> dict[str, Any]:
    """`ftfof identify --surface acrylic --simulate`: mu and F_adh(v) against their truth."""
    report = out / "identify.json"
    args = ["identify", "-p", str(params_path), "--surface", SURFACE, "--simulate"]
    rc, tail = command([*args, "--report", str(report), "--folder", str(out / "identify")])
    if rc != 0 or not report.exists():
        return {"error": f"exit {rc}: {tail}"}
    doc = json.loads(report.read_text())
    res = {k: {x: doc[k][x] for x in ("estimate", "truth")} for k in ("mu", "adhesion")}
    for r in res.values():
        r["error"] = (r["estimate"] - r["truth"]) / r["truth"]
    return res


def with_budget(params: Params, seconds: float | None) -> Params:
    """``params`` with a climb's wall-time budget of ``seconds`` (None: its own): on a loaded
    machine a climb runs out of wall time, not of physics."""
    climb = params.climb.model_copy(update={"time_budget": seconds or params.climb.time_budget})
    return params.model_copy(update={"climb": climb})


def robot_runs(foot: dict[str, Params], tmp: Path, a: argparse.Namespace) -> dict:
    """Every climb and identify run of both feet, at most ``a.workers`` (<= 2) at a time."""
    jobs: dict[tuple[str, str], Callable[[], dict[str, Any]]] = {}
    parts = set(a.parts.split(","))
    for name, params in foot.items():
        params = with_budget(params, a.climb_budget)
        path, paper = params_file(params, tmp / name), params.selected_robot.published_optimum
        todo = {b: None for b in BASELINES} | {"paper_optimum": paper}
        for b, x in todo.items() if "climb" in parts else ():
            jobs[(name, b)] = lambda p=path, b=b, x=x, d=tmp / name / b: climb(p, b, x, d)
        if "identify" in parts:
            jobs[(name, "identify")] = lambda p=path, d=tmp / name: identify(p, d)
    with ThreadPoolExecutor(max_workers=max(1, min(2, a.workers))) as pool:
        futures = {k: pool.submit(f) for k, f in jobs.items()}
        return {k: f.result() for k, f in futures.items()}


def fmt(v: Any, digits: int = 3) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def table(title: str, header: str, rows: list[list[Any]]) -> list[str]:
    """A markdown table under a heading; ``header``'s columns separated by '|'."""
    cols = header.split("|")
    rows = [[*r, *[""] * (len(cols) - len(r))] for r in rows]
    lines = ["| " + " | ".join(map(str, r)) + " |" for r in [cols, ["---"] * len(cols), *rows]]
    return ["", f"## {title}", "", *lines]


def table_rows(out: dict[str, Any]) -> list[list[Any]]:
    """Table I's rows, the grip foot above the plate."""
    rows: list[list[Any]] = []
    for row in out["plate"].get("table", {}).get("rows", {}):
        for foot in FEET:
            r = out[foot]["table"]["rows"][row]
            if r["status"] != "ok":
                rows.append([row, foot, "failed: " + r["error"][:60]])
                continue
            forces = [f"{r[k]:.2f}" for k in FIGURES[:3]]
            jitter = [fmt(r["jitter"]), fmt(r["peak_body_acc"])]
            film = [f"{1e3 * r['min_bend_radius']:.1f}", f"{r['bonds_at_end']:.0f}/{r['nodes']}"]
            rows.append([row, foot, *forces, *jitter, *film, f"{r['wall_s']:.2f}"])
    return rows


def markdown(out: dict[str, Any]) -> str:
    """The study's tables, for the decision record."""
    head = "row|foot|detach N|pull N|pre-press N|jitter m/s²|body acc m/s²|bend mm|bonds at end|s"
    lines = table("Table I rows (platform, acrylic)", head, table_rows(out))
    lines += ["", f"Committed optimum: {out['optimum']}"]
    if "spread" in out["plate"]:
        rows = []
        for foot in FEET:
            s = out[foot]["spread"]
            for k in SPREAD:
                q = [f"{s[k][x]:.2f}" for x in ("q10", "q50", "q90", "max")]
                rows.append([foot, k, *q, f"{100 * s[k]['spread']:.1f} %", f"{s['failed']}"])
        head = "foot|figure|q10|q50|q90|max|(q90-q10)/q50|failed"
        lines += table(f"Spread over the first {out['samples']} sampled trajectories", head, rows)
        lines += ["", f"Source: {out['trajectories']}. FTFOF Table I spans 28 % (5.40-7.49 N)."]
    if "cost_s" in out["plate"].get("table", {}):
        g, p = out["grip"]["table"]["cost_s"], out["plate"]["table"]["cost_s"]
        lines += ["", "## Cost per sample (one process, one worker, Table I rows, medians)", ""]
        lines += [f"grip {g:.3f} s, plate {p:.3f} s, plate / grip {p / g:.2f}"]
    return "\n".join(lines + robot_markdown(out))


def robot_markdown(out: dict[str, Any]) -> list[str]:
    """The climbs' and the identify round trip's tables."""
    rows: list[list[Any]] = []
    for name in (*BASELINES, "paper_optimum"):
        for foot in FEET:
            c = out[foot].get("climbs", {}).get(name)
            if c is None or "steps_done" not in c:
                rows += [[name, foot, f"error: {c['error'][-80:]!r}"]] if c else []
                continue
            note = ["--allow-infeasible"] if c["allow_infeasible"] else []
            note += [x for x in (c["error"][:70], c["torque_worst"]) if x]
            bend = 1e3 * c["min_bend_radius"] if c["min_bend_radius"] else None
            torque = f"{fmt(c['torque_ratio'])} ({c['torque_joint']})"
            rebond = f"{fmt(c['least_rebond'])} {c['rebonds']}"
            figs = [fmt(c[k]) for k in ("peak_pull", "jitter")] + [fmt(bend), f"{c['wall_s']:.0f}"]
            steps = f"{fmt(c['steps_done'])}/8"
            fell = c["fall"] or ("stopped" if c["error"] else "no")
            rows.append([name, foot, steps, fell, torque, rebond, *figs])
            rows[-1].append("; ".join(note))
    head = "trajectory|foot|steps|fell|torque ratio (joint)|re-bonds (least, all)|peak pull N"
    lines = table("Climbs (MST-M3F, acrylic)", head + "|jitter m/s²|bend mm|wall s|note", rows)
    rows = []
    for foot in FEET:
        i = out[foot].get("identify")
        if i is None or "mu" not in i:
            rows += [[foot, f"error: {i['error'][-80:]!r}"]] if i else []
            continue
        values = [f"{i[k][x]:.4g}" for k in ("mu", "adhesion") for x in ("estimate", "truth")]
        rows.append([foot, *values, *(f"{100 * i[k]['error']:+.1f} %" for k in i)])
    head = "foot|mu est|mu truth|F_adh est N|F_adh truth N|mu err|F_adh err"
    return lines + table("Identify round trip (acrylic, simulated slip test)", head, rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "study_feet.json")
    ap.add_argument("--optimize", type=Path, default=Path("data/polish/optimize"))
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each Table I row")
    ap.add_argument("--parts", default="table,spread,climb,identify")
    ap.add_argument("--climb-budget", type=float, help="wall seconds per climb (params' own)")
    a = ap.parse_args()
    parts, foot = set(a.parts.split(",")), feet(load_params(Path("params.yaml")))
    X, where = optimum_X(foot["plate"], a.optimize)
    out: dict[str, Any] = {"optimum": where, "samples": a.samples, "workers": a.workers}
    out |= {"grip_foot": GRIP_FOOT, "grip_acrylic": GRIP_ACRYLIC, **{f: {} for f in FEET}}
    with tempfile.TemporaryDirectory(prefix="study_feet_") as tmp_name:
        tmp = Path(tmp_name)
        if "table" in parts:
            for name, res in table_and_cost(foot, X, a.repeats).items():
                out[name]["table"] = res
            print("table done", file=sys.stderr, flush=True)
        if "spread" in parts:
            trajectories, out["trajectories"] = trajectories_table(tmp)
            for name, params in foot.items():
                out[name]["spread"] = spread(params, trajectories, a.samples, a.workers)
                print(f"{name}: spread done", file=sys.stderr, flush=True)
        for (name, what), res in robot_runs(foot, tmp, a).items():
            if what == "identify":
                out[name]["identify"] = res
                continue
            out[name].setdefault("climbs", {})[what] = res
    a.out.write_text(json.dumps(out, indent=2, default=float) + "\n")
    print(markdown(out))
    print(f"\nwrote {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
