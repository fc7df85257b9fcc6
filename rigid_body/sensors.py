"""Proprioceptive and exteroceptive sensors: absolute-encoder Gray code, wrist force/torque sensor.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 5.2.1 (absolute encoders, Gray code; Problem 5.5), Sect. 5.2.3 (force sensors, Eq. (5.32);
Problem 5.6). The pinhole camera of Sect. 5.2.4 lives in :mod:`rigid_body.camera`.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from rigid_body.rotations import as_rotation, skew
from rigid_body.validation import as_vector


def _bits(bits: Sequence[int] | np.ndarray, name: str) -> np.ndarray:
    b = np.asarray(bits)
    if b.ndim != 1 or b.size == 0 or not np.all((b == 0) | (b == 1)):
        raise ValueError(f"`{name}` must be a non-empty sequence of 0/1 bits (most significant first), got {bits!r}")
    return b.astype(np.uint8)


def gray_to_binary(gray: Sequence[int] | np.ndarray) -> np.ndarray:
    """Binary word of a Gray-code word (bits, most significant first): the XOR cascade of Fig. S5.6.

    ``y_1 = x_1``, ``y_k = y_{k−1} ⊕ x_k`` for any word length.

    >>> gray_to_binary([1, 1, 1, 0]).tolist()          # row 11 of Table S5.1
    [1, 0, 1, 1]
    """
    x = _bits(gray, "gray")
    y = np.empty_like(x)
    y[0] = x[0]
    for k in range(1, x.size):
        y[k] = y[k - 1] ^ x[k]
    return y


def binary_to_gray(binary: Sequence[int] | np.ndarray) -> np.ndarray:
    """Gray-code word of a binary word (bits, most significant first): ``x_1 = y_1``, ``x_k = y_{k−1} ⊕ y_k``."""
    y = _bits(binary, "binary")
    x = y.copy()
    x[1:] = y[:-1] ^ y[1:]
    return x


def int_to_bits(value: int, n_bits: int) -> np.ndarray:
    """``value`` as an ``n_bits`` word, most significant bit first."""
    if n_bits < 1 or not 0 <= int(value) < 2**n_bits:
        raise ValueError(f"`value` must be in [0, 2**{n_bits}), got {value}")
    return np.array([(int(value) >> (n_bits - 1 - k)) & 1 for k in range(n_bits)], dtype=np.uint8)


def bits_to_int(bits: Sequence[int] | np.ndarray) -> int:
    """The unsigned integer of a word, most significant bit first."""
    out = 0
    for b in _bits(bits, "bits"):
        out = (out << 1) | int(b)
    return out


def wrench_transform(R_cs: Any, r_cs: Any) -> np.ndarray:
    """The 6×6 map of a wrench [f; μ] from the sensor frame s to the contact frame c, Eq. (5.32).

    ``[f_c^c; μ_c^c] = [[R_s^c, O], [S(r_cs^c) R_s^c, R_s^c]] [f_s^s; μ_s^s]``, with ``R_cs`` = R_s^c the
    orientation of the sensor frame in the contact frame and ``r_cs`` = r_cs^c the position of the
    sensor-frame origin relative to the contact frame, in the contact frame.
    """
    R = as_rotation(R_cs, "R_cs")
    r = as_vector(r_cs, 3, "r_cs")
    W = np.zeros((6, 6))
    W[:3, :3] = R
    W[3:, 3:] = R
    W[3:, :3] = skew(r) @ R
    return W
