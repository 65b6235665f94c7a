"""Helpers for end-to-end tests: a throw-away copy of the repository with git and DVC."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT


def clone_to(dest: Path) -> Path:
    """Copy what a clean clone would hold (tracked and untracked-but-not-ignored files)."""
    files = (
        subprocess.run(
            ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            cwd=ROOT,
            capture_output=True,
            check=True,
        )
        .stdout.decode()
        .split("\0")
    )
    for rel in filter(None, files):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    env = pipeline_env(dest)
    for cmd in (
        ["git", "init", "-q", "-b", "main"],
        ["git", "add", "-A"],
        ["git", "commit", "-q", "-m", "test clone"],
    ):
        subprocess.run(cmd, cwd=dest, env=env, check=True)
    return dest


def pipeline_env(repo: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env['PATH']}"
    env["MLFLOW_TRACKING_URI"] = f"sqlite:///{repo / 'mlflow.db'}"
    env.update(
        DVC_NO_ANALYTICS="true",
        MLFLOW_DISABLE_TELEMETRY="true",
        GIT_AUTHOR_NAME="ftfof test",
        GIT_AUTHOR_EMAIL="test@ftfof.invalid",
        GIT_COMMITTER_NAME="ftfof test",
        GIT_COMMITTER_EMAIL="test@ftfof.invalid",
    )
    return env


def run(
    repo: Path, *args: str, timeout: float = 900, unset: tuple[str, ...] = ()
) -> subprocess.CompletedProcess[str]:
    """Run a command in ``repo`` and require success; ``unset`` drops variables from its env."""
    env = {k: v for k, v in pipeline_env(repo).items() if k not in unset}
    result = subprocess.run(
        list(args),
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert result.returncode == 0, f"{' '.join(args)} failed:\n{result.stdout}\n{result.stderr}"
    return result
