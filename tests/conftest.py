"""Shared fixtures: the repository's own params.yaml and the two robots' resolved policies."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from ftfof.config import Params
from stages.robot import RobotContext, robot_context

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"

# The paper's published MST-M3F optimum (FTFOF §VI.C), metres.
PUBLISHED_M3F = np.array([2.3, 18.3, 31.4, 108.8, 123.7, 124.5, 23.6, 25.5, 29.0, 48.6, 30.5, 11.1])
PUBLISHED_M3F = PUBLISHED_M3F / 1000.0


@pytest.fixture(scope="session")
def raw_params() -> dict:
    return yaml.safe_load((ROOT / "params.yaml").read_text())


@pytest.fixture
def params_dict(raw_params: dict) -> dict:
    """A private deep copy to edit."""
    return copy.deepcopy(raw_params)


@pytest.fixture(scope="session")
def params(raw_params: dict) -> Params:
    return Params.model_validate(raw_params)


def _context(raw: dict, robot: str) -> RobotContext:
    data = copy.deepcopy(raw)
    data["robot"] = robot
    return robot_context(Params.model_validate(data))


@pytest.fixture(scope="session")
def m3f(raw_params: dict) -> RobotContext:
    return _context(raw_params, "mst_m3f")


@pytest.fixture(scope="session")
def mst_q(raw_params: dict) -> RobotContext:
    return _context(raw_params, "mst_q")


def write_params(path: Path, data: dict) -> Path:
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path
