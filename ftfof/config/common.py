"""What every settings block shares: the strict base model and the allowed names."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
)

Fraction = Annotated[float, Field(gt=0, le=1)]
# The allowed names: every module that needs one of these lists reads it here (typing.get_args).
# fs6 is the bending constraint; fsj the body jitter; *_normal the paper's normal-only fs1/fs2
Objective = Literal["fs1", "fs2", "fs3", "fs4", "fs5", "fs7", "fsj", "fs1_normal", "fs2_normal"]
Strategy = Literal[Objective, "fs6"]  # every strategy function (FTFOF §V.A)
Loss = Literal["dilate", "mse"]
# the surrogates' target series (ftfof.data.targets.TARGETS, in its order)
Target = Literal[
    "pull", "Fd", "Fp", "jitter", "body_acc", "curvature", "clearance", "retouch", "holds"
]
# those read by their maximum, which a peak GP may set (pull and Fd: fs2 reads their mean). The
# clearance's swing gap reads its dip, which the GP's scaling of the series scales alike: a
# choice for a surrogate too small to reach the required clearance (the tiny MST-Q's GRU
# predicts 14-16 mm where the simulator measures 25-47 mm)
PeakTarget = Literal["Fp", "jitter", "body_acc", "curvature", "retouch", "holds", "clearance"]
Baseline = Literal["polynomial", "cycloidal", "random_bezier", "eps_bezier"]
Design = Literal["sobol", "lhs"]


class Strict(BaseModel):
    """Base for every settings block: unknown keys are errors, values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


def _distinct(names: list[str]) -> list[str]:
    if len(set(names)) != len(names):
        raise ValueError("must not repeat a name")
    return names
