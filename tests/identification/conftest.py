"""Independent 'measurements' for the identification tests: modal sums, complex noise, impulse responses and a
randomly excited response, made with numpy/scipy alone (no package code), after review Q's generators; and the
``identify`` sub-commands' runner the CLI tests share."""

import argparse
from types import SimpleNamespace

import numpy as np
import pytest


def _receptance(f_hz, f_n, eta=None, zeta=None, A=None):
    """Modal sum receptance at ``f_hz`` (Hz): structural ``A_k / (w_k^2 (1 + i eta_k) - w^2)`` or viscous
    ``A_k / (w_k^2 - w^2 + 2 i zeta_k w_k w)``; residues ``A`` (1 each by default)."""
    w = 2 * np.pi * np.asarray(f_hz, dtype=float)
    H = np.zeros(w.shape, complex)
    for k, fk in enumerate(f_n):
        wk = 2 * np.pi * fk
        a = 1.0 if A is None else A[k]
        H += a / (wk**2 * (1 + 1j * eta[k]) - w**2) if eta is not None else a / (wk**2 - w**2 + 2j * zeta[k] * wk * w)
    return H


def _cnoise(seed, n, level):
    """Complex Gaussian noise of rms ``level`` (real and imaginary parts level / sqrt 2 each)."""
    rng = np.random.default_rng(seed)
    return level * (rng.standard_normal(n) + 1j * rng.standard_normal(n)) / np.sqrt(2)


def _impulse(t, f_n, zeta, amp):
    """Viscous modes' impulse response ``sum a exp(-zeta w t) sin(w_d t)`` (0 before t = 0)."""
    x = np.zeros_like(t)
    for fk, z, a in zip(f_n, zeta, amp):
        w = 2 * np.pi * fk
        x += np.where(t >= 0, a * np.exp(-z * w * t) * np.sin(w * np.sqrt(1 - z * z) * t), 0.0)
    return x


def _random_response(force, fs, f_n, zeta, A):
    """Response of viscous receptance modes ``A / (w^2 - W^2 + 2 i zeta w W)`` to the sampled force, each mode
    by its exact discrete impulse response ``A / w_d exp(-zeta w t) sin(w_d t)`` (impulse invariance,
    scipy.signal.lfilter)."""
    from scipy.signal import lfilter

    y = np.zeros(force.size)
    for fk, z, a in zip(f_n, zeta, A):
        w = 2 * np.pi * fk
        wd, r = w * np.sqrt(1 - z * z), np.exp(-z * w / fs)
        y += lfilter([0, a / wd * r * np.sin(wd / fs) / fs], [1, -2 * r * np.cos(wd / fs), r * r], force)
    return y


@pytest.fixture(scope="session")
def synth():
    """``receptance(f_hz, f_n, eta=|zeta=, A=)``, ``cnoise(seed, n, level)``, ``impulse(t, f_n, zeta, amp)``,
    ``random_response(force, fs, f_n, zeta, A)``: the tests' own modal sums and noise."""
    return SimpleNamespace(receptance=_receptance, cnoise=_cnoise, impulse=_impulse, random_response=_random_response)


@pytest.fixture(scope="session")
def identify_cli():
    """``identify_cli(argv)``: the exit status of ``cablecasing identify ...`` run on a parser built with
    :func:`~cablecasing_core.cli.identify.add_parser` alone (its sub-commands' own handling of errors)."""
    from cablecasing_core.cli.identify import add_parser

    def run(argv):
        p = argparse.ArgumentParser(prog="cablecasing")
        sub = p.add_subparsers(dest="command", required=True)
        add_parser(sub)
        args = p.parse_args(argv)
        return args.func(args)

    return run
