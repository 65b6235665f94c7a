"""The compiled GRU and Linear layers against torch's own: same values and gradients (to the
rational tanh's 4e-7), state dicts that load both ways, and sums that do not depend on threads."""

import numba
import numpy as np
import torch
from torch import nn

from ftfof.surrogate import layers


def _pair(inputs=4, hidden=8, num_layers=2, seed=0):
    torch.manual_seed(seed)
    ours = layers.GRU(inputs, hidden, num_layers)
    theirs = nn.GRU(inputs, hidden, num_layers=num_layers, batch_first=True)
    theirs.load_state_dict(ours.state_dict())
    return ours, theirs


def _grads(module, x, weights):
    x = x.clone().requires_grad_(True)
    out = module(x)
    out = out[0] if isinstance(out, tuple) else out
    (out * weights).sum().backward()
    named = {k: p.grad.clone() for k, p in module.named_parameters()}
    return out.detach(), x.grad.clone(), named


def test_the_gru_computes_torchs_gru_and_its_gradients():
    ours, theirs = _pair()
    x = torch.randn(5, 30, 4)
    w = torch.randn(5, 30, 8)
    y_ours, dx_ours, g_ours = _grads(ours, x, w)
    y_theirs, dx_theirs, g_theirs = _grads(theirs, x, w)
    torch.testing.assert_close(y_ours, y_theirs, atol=2e-6, rtol=0)
    torch.testing.assert_close(dx_ours, dx_theirs, atol=2e-5, rtol=1e-4)
    assert g_ours.keys() == g_theirs.keys() and len(g_ours) == 8
    for name in g_ours:
        torch.testing.assert_close(g_ours[name], g_theirs[name], atol=5e-5, rtol=1e-4)


def test_the_last_states_are_torchs():
    ours, theirs = _pair()
    x = torch.randn(3, 12, 4)
    with torch.no_grad():
        torch.testing.assert_close(ours(x)[1], theirs(x)[1], atol=2e-6, rtol=0)


def test_the_linear_layer_computes_torchs_linear_and_its_gradients():
    torch.manual_seed(1)
    ours = layers.Linear(8, 3)
    theirs = nn.Linear(8, 3)
    theirs.load_state_dict(ours.state_dict())
    x = torch.randn(4, 20, 8)
    w = torch.randn(4, 20, 3)
    for a, b in zip(_grads(ours, x, w)[:2], _grads(theirs, x, w)[:2], strict=True):
        torch.testing.assert_close(a, b, atol=1e-5, rtol=1e-5)
    g_ours, g_theirs = _grads(ours, x, w)[2], _grads(theirs, x, w)[2]
    for name in ("weight", "bias"):
        torch.testing.assert_close(g_ours[name], g_theirs[name], atol=1e-4, rtol=1e-5)


def test_initialisation_draws_what_torch_draws():
    """Same seed, same first weights as nn.GRU / nn.Linear (same bounds, same order)."""
    torch.manual_seed(3)
    ours = layers.GRU(4, 8, 2).state_dict()
    torch.manual_seed(3)
    theirs = nn.GRU(4, 8, num_layers=2, batch_first=True).state_dict()
    assert all(torch.equal(ours[k], theirs[k]) for k in theirs)
    torch.manual_seed(4)
    lin = layers.Linear(8, 3).state_dict()
    torch.manual_seed(4)
    ref = nn.Linear(8, 3).state_dict()
    assert all(torch.equal(lin[k], ref[k]) for k in ref)


def _one_training_step() -> float:
    ours, _ = _pair(hidden=8, num_layers=1, seed=2)
    return float(_grads(ours, torch.randn(4, 10, 4), torch.randn(4, 10, 8))[2]["bias_hh_l0"].sum())


def test_a_forked_child_trains_after_the_parent_ran_numbas_thread_pool():
    """`train` forks its model processes after the parent may have run the population kernel
    (numba's OpenMP pool), which aborts a child that starts the pool again: the training
    kernels never do."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from ftfof.surrogate.gru_kernel import Layer

    rng = np.random.default_rng(0)
    w = [rng.normal(size=s).astype(np.float32) for s in ((24, 4), (24, 8), (24,), (24,))]
    Layer.from_torch(*w).hidden_states(rng.normal(size=(8, 5, 4)).astype(np.float32))
    assert numba.threading_layer()  # the parent's pool is running
    expected = _one_training_step()
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork")) as pool:
        assert pool.submit(_one_training_step).result(timeout=120) == expected


def test_dropout_between_layers_only_while_training():
    torch.manual_seed(0)
    gru = layers.GRU(4, 8, 2, dropout=0.5)
    x = torch.randn(2, 10, 4)
    gru.eval()
    with torch.no_grad():
        assert torch.equal(gru(x)[0], gru(x)[0])
        gru.train()
        assert not torch.equal(gru(x)[0], gru(x)[0])
