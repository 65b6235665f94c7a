"""Adam whose square root is the correctly rounded one, so training is the same bits on any CPU.

torch's CPU ``sqrt`` goes through MKL's vector library, which picks its kernels by the CPU: on an
Intel Xeon its COMPATIBLE branch (the pinned one) rounds 17 % of square roots otherwise than
IEEE's, and its AVX2 branch otherwise again, so Adam's ``exp_avg_sq.sqrt()`` trained other
weights on each. NumPy's ``sqrt`` is IEEE's correctly rounded one on every CPU. The update is
torch's single-tensor Adam (L2 weight decay, no amsgrad) otherwise, step for step.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import torch


class Adam(torch.optim.Optimizer):
    """``torch.optim.Adam(params, lr, betas, eps, weight_decay)`` with an IEEE square root."""

    def __init__(
        self,
        params: Iterable[torch.nn.Parameter],
        lr: float = 1e-3,
        betas: tuple[float, float] = (0.9, 0.999),
        eps: float = 1e-8,
        weight_decay: float = 0.0,
    ):
        super().__init__(
            params, {"lr": lr, "betas": betas, "eps": eps, "weight_decay": weight_decay}
        )

    @torch.no_grad()
    def step(self, closure=None):  # type: ignore[override]
        for group in self.param_groups:
            beta1, beta2 = group["betas"]
            for param in group["params"]:
                if param.grad is not None:
                    self._update(param, group, beta1, beta2)
        return None

    def _update(self, param: torch.Tensor, group: dict, beta1: float, beta2: float) -> None:
        state = self.state[param]
        if not state:
            state["step"] = 0
            state["exp_avg"] = torch.zeros_like(param)
            state["exp_avg_sq"] = torch.zeros_like(param)
        grad = param.grad
        if group["weight_decay"] != 0:
            grad = grad.add(param, alpha=group["weight_decay"])
        state["step"] += 1
        exp_avg, exp_avg_sq = state["exp_avg"], state["exp_avg_sq"]
        exp_avg.lerp_(grad, 1 - beta1)
        exp_avg_sq.mul_(beta2).addcmul_(grad, grad, value=1 - beta2)
        step = state["step"]
        step_size = group["lr"] / (1 - beta1**step)
        root = torch.from_numpy(np.sqrt(exp_avg_sq.numpy()))
        denom = (root / (1 - beta2**step) ** 0.5).add_(group["eps"])
        param.addcdiv_(exp_avg, denom, value=-step_size)
